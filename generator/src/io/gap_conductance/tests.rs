use super::*;
use lookup::{Axes, Extrapolation, ExtrapolationPolicy, Law, LawInfo};

/// A law with a jump ∝ p^(−0.8) at two fluxes and two temperatures.
fn power_law(policy: ExtrapolationPolicy) -> Law {
    let axes = Axes {
        pressure: vec![1e3, 1e4, 1e5],
        flux: vec![1e5, 1e6],
        contact_temperature: vec![293.15, 393.15],
    };
    let mut jump = Vec::new();
    for &p in &axes.pressure {
        for &h in &axes.flux {
            for &t in &axes.contact_temperature {
                jump.push(h / 1e5 * (p / 1e3).powf(-0.8) * (t / 293.15));
            }
        }
    }
    let n = jump.len();
    let info = LawInfo {
        extrapolation: policy,
        ..LawInfo::default()
    };
    Law::from_grid(axes, jump, vec![0.0; n], info).unwrap()
}

fn error_policy() -> ExtrapolationPolicy {
    ExtrapolationPolicy::uniform(Extrapolation::Error)
}

#[test]
fn unit_factors_follow_from_mm_n_s() {
    let u = DeckUnits::MmNSK;
    // 1 N/mm² = 1 MPa.
    assert_eq!(u.pressure() * 1e6, 1.0);
    // 1 mW/mm² = 1e-3 W / 1e-6 m² = 1e3 W/m².
    assert_eq!(u.flux() * 1e3, 1.0);
    assert_eq!(u.conductance(), u.flux());
    // 1 mW/(mm K) = 1e-3 W / (1e-3 m K) = 1 W/(m K).
    assert_eq!(u.conductivity(), 1.0);
    assert_eq!(u.length(), 1e3);
    let si = DeckUnits::Si;
    assert_eq!(
        [si.pressure(), si.flux(), si.conductance(), si.length()],
        [1.0; 4]
    );
    for (s, v) in [("SI", DeckUnits::Si), ("mm-N-s-K", DeckUnits::MmNSK)] {
        assert_eq!(s.parse::<DeckUnits>().unwrap(), v);
        assert_eq!(v.name(), s);
    }
    let e = "inch".parse::<DeckUnits>().unwrap_err().to_string();
    assert!(e.contains("--units") && e.contains("mm-N-s-K"), "{e}");
    let e = "nastran".parse::<LawFormat>().unwrap_err().to_string();
    assert!(e.contains("--format") && e.contains("calculix"), "{e}");
}

/// Every row is |h|/jump of the law, the table's nodes are rows, and the
/// solver's interpolation stays within the tolerance (checked on a grid
/// 8 times finer than the writer's own sampling).
#[test]
fn rows_are_the_law_and_follow_it_within_the_tolerance() {
    let law = power_law(error_policy());
    for tol in [1e-2, 1e-3, 1e-4] {
        let o = GapConductanceOptions {
            flux: Some(1e5),
            tolerance: tol,
            deck: GapDeck::Abaqus,
            ..Default::default()
        };
        let rows = gap_conductance_rows(&law, &o).unwrap();
        for p in [1e3, 1e4, 1e5] {
            assert!(rows.pressures.contains(&p), "{p}");
        }
        for (it, &t) in rows.temperatures.iter().enumerate() {
            for (ip, &p) in rows.pressures.iter().enumerate() {
                let v = law.eval(p, 1e5, t).unwrap();
                assert_eq!(rows.at(it, ip), v.conductance);
                assert!((v.conductance * v.jump / 1e5 - 1.0).abs() < 1e-15);
            }
        }
        let mut worst: f64 = 0.0;
        let n = 4000;
        for i in 0..=n {
            let p = 1e3 * 100f64.powf(i as f64 / n as f64);
            for t in [293.15, 310.0, 343.15, 393.15] {
                let exact = law.eval(p, 1e5, t).unwrap().conductance;
                worst = worst.max((rows.interpolate(p, t) / exact - 1.0).abs());
            }
        }
        assert!(worst <= tol, "tol {tol}: {worst}");
        assert!(rows.max_deviation <= tol);
        println!(
            "tol {tol:e}: {} pressures x {} temperatures, worst {worst:.3e}",
            rows.pressures.len(),
            rows.temperatures.len()
        );
    }
}

/// Ten times tighter costs about √10 times the rows (the chord error of
/// a smooth curve is O(Δ²)).
#[test]
fn row_count_grows_like_the_inverse_square_root_of_the_tolerance() {
    let law = power_law(error_policy());
    let count = |tol: f64| {
        let o = GapConductanceOptions {
            flux: Some(1e6),
            tolerance: tol,
            ..Default::default()
        };
        gap_conductance_rows(&law, &o).unwrap().pressures.len() as f64
    };
    let (a, b) = (count(1e-3), count(1e-5));
    let ratio = (b - 1.0) / (a - 1.0);
    assert!(ratio > 5.0 && ratio < 20.0, "{a} -> {b}: {ratio}");
}

#[test]
fn deck_lines_are_converted_and_readable_by_calculix() {
    let law = power_law(error_policy());
    let o = GapConductanceOptions {
        flux: Some(1e5),
        units: DeckUnits::MmNSK,
        celsius: true,
        tolerance: 5e-2,
        ..Default::default()
    };
    let rows = gap_conductance_rows_for_deck(&law, &o).unwrap();
    let source = DeckSource {
        table: "t.h5".into(),
        sha256: "ab".repeat(32),
        statistic: "deterministic".into(),
    };
    let deck = render_deck(&law, &rows, &o, &source);
    let data: Vec<&str> = deck
        .lines()
        .skip_while(|l| *l != "*GAP CONDUCTANCE")
        .skip(1)
        .collect();
    assert_eq!(data.len(), rows.pressures.len() * rows.temperatures.len());
    let first: Vec<f64> = data[0]
        .split(',')
        .map(|f| f.trim().parse().unwrap())
        .collect();
    assert!((first[0] / (1e-3 * rows.at(0, 0)) - 1.0).abs() < 1e-10);
    assert!((first[1] - 1e3 * 1e-6).abs() < 1e-15);
    assert!((first[2] - 20.0).abs() < 1e-9);
    for l in &data {
        assert!(l.split(',').all(|f| f.trim().len() <= 20), "{l}");
    }
    for needle in [
        "t.h5",
        &"ab".repeat(32),
        "statistic: deterministic",
        "|h| = 1e5 W/m^2",
        "mW/(mm^2 K)",
        "OUTSIDE",
        "degC",
    ] {
        assert!(deck.contains(needle), "{needle}\n{deck}");
    }
    assert!(
        deck.lines()
            .all(|l| l.starts_with("**") || !l.contains("**"))
    );
    let abaqus = render_deck(
        &law,
        &rows,
        &GapConductanceOptions {
            deck: GapDeck::Abaqus,
            ..o
        },
        &source,
    );
    assert!(abaqus.contains("\n*GAP CONDUCTANCE, PRESSURE\n"));
}

#[test]
fn flux_and_range_are_checked() {
    let law = power_law(error_policy());
    let o = GapConductanceOptions::default();
    let e = gap_conductance_rows(&law, &o).unwrap_err().to_string();
    assert!(e.contains("--flux") && e.contains("2 fluxes"), "{e}");
    for bad in [2e6, 1e4, -1.0] {
        let e = gap_conductance_rows(
            &law,
            &GapConductanceOptions {
                flux: Some(bad),
                ..o
            },
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("--flux"), "{e}");
    }
    // Inside: interpolated by the law.
    let r = gap_conductance_rows(
        &law,
        &GapConductanceOptions {
            flux: Some(4e5),
            tolerance: 1e-2,
            ..o
        },
    )
    .unwrap();
    assert_eq!(r.flux_source, FluxSource::Interpolated);
    let v = law.eval(1e4, 4e5, 293.15).unwrap();
    let i = r.pressures.iter().position(|&p| p == 1e4).unwrap();
    assert_eq!(r.at(0, i), v.conductance);
    // Beyond the table only under a pressure policy.
    let wide = GapConductanceOptions {
        flux: Some(1e5),
        pressure_range: Some([100.0, 1e6]),
        tolerance: 1e-2,
        ..o
    };
    let e = gap_conductance_rows(&law, &wide).unwrap_err().to_string();
    assert!(
        e.contains("--pressure-range") && e.contains("pressure=clamp"),
        "{e}"
    );
    let mut clamp = error_policy();
    clamp.pressure = Extrapolation::Clamp;
    let r = gap_conductance_rows(&power_law(clamp), &wide).unwrap();
    // Explicit end rows, constant beyond the table.
    assert_eq!(r.pressures[0], 100.0);
    assert_eq!(*r.pressures.last().unwrap(), 1e6);
    assert_eq!(r.at(0, 0), r.at(0, 1));
    let mut power = error_policy();
    power.pressure = Extrapolation::Power;
    let r = gap_conductance_rows(&power_law(power), &wide).unwrap();
    // k ∝ p^0.8 continued: 10× the pressure, 10^0.8 × the conductance.
    let k_hi = r.at(0, r.pressures.len() - 1);
    let k_1e5 = r.at(0, r.pressures.iter().position(|&p| p == 1e5).unwrap());
    assert!((k_hi / k_1e5 / 10f64.powf(0.8) - 1.0).abs() < 1e-9);
    assert!(parse_pressure_range("1e3:1e2").is_err());
    assert_eq!(parse_pressure_range("1e2:1e3").unwrap(), [1e2, 1e3]);
}

#[test]
fn calculix_row_limit_names_a_tolerance_that_fits() {
    let law = power_law(error_policy());
    let o = GapConductanceOptions {
        flux: Some(1e5),
        tolerance: 1e-4,
        ..Default::default()
    };
    let e = gap_conductance_rows_for_deck(&law, &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--tolerance") && e.contains("at most 20"), "{e}");
    let fit: f64 = e
        .split("use --tolerance ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let r = gap_conductance_rows_for_deck(
        &law,
        &GapConductanceOptions {
            tolerance: fit,
            ..o
        },
    )
    .unwrap();
    assert!(r.pressures.len() <= CALCULIX_MAX_PRESSURE_ROWS);
}
