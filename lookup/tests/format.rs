//! The law file: round trip, and every malformed, truncated, extended,
//! wrong-version or corrupted input is an error naming the problem, never a panic.

mod common;

use common::*;
use lookup::{
    Axes, Error, Extrapolation, ExtrapolationPolicy, HEADER_BYTES, Law, LawInfo, Statistic, crc32,
};
use proptest::prelude::*;

fn small_law(np: usize, nh: usize, nt: usize, seed: u64) -> Law {
    let mut rng = Lcg(seed);
    let axes = Axes {
        pressure: geomspace(1e4, 1e7, np),
        flux: uneven(1e4, 1e6, nh),
        contact_temperature: uneven(290.0, 400.0, nt),
    };
    let n = axes.len();
    let mean = (0..n).map(|_| rng.range(0.0, 50.0)).collect();
    let std = (0..n).map(|_| rng.range(0.0, 2.0)).collect();
    let info = LawInfo {
        statistic: Statistic::EnsembleMean { samples: 20 },
        extrapolation: ExtrapolationPolicy {
            pressure: Extrapolation::Error,
            flux: Extrapolation::Clamp,
            contact_temperature: Extrapolation::Linear,
        },
        material: None,
        provenance: vec![
            ("generator".into(), "tcgen 0.1.0".into()),
            ("source".into(), "sweep/table.h5 (θ̄c in K)".into()),
        ],
    };
    Law::from_grid(axes, mean, std, info).unwrap()
}

/// Recomputes the CRC so that a deliberate edit reaches the later checks.
fn reseal(bytes: &mut [u8]) {
    let body = bytes.len() - 4;
    let crc = crc32(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
}

fn meta_range(bytes: &[u8]) -> std::ops::Range<usize> {
    let len = u64::from_le_bytes(bytes[24..32].try_into().unwrap()) as usize;
    HEADER_BYTES..HEADER_BYTES + len
}

/// Replaces the metadata text, fixing the declared length and the CRC.
fn with_metadata(bytes: &[u8], edit: impl Fn(&str) -> String) -> Vec<u8> {
    let r = meta_range(bytes);
    let text = edit(std::str::from_utf8(&bytes[r.clone()]).unwrap());
    let mut out = bytes[..HEADER_BYTES].to_vec();
    out[24..32].copy_from_slice(&(text.len() as u64).to_le_bytes());
    out.extend_from_slice(text.as_bytes());
    out.extend_from_slice(&bytes[r.end..]);
    reseal(&mut out);
    out
}

#[test]
fn file_round_trip_is_bit_identical() {
    let dir = std::env::temp_dir().join(format!("lookup-format-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("law.tclaw");
    let law = physical_law(Extrapolation::Clamp);
    law.write(&path).unwrap();
    let back = Law::open(&path).unwrap();
    assert_eq!(back, law);
    let again = dir.join("again.tclaw");
    back.write(&again).unwrap();
    assert_eq!(
        std::fs::read(&path).unwrap(),
        std::fs::read(&again).unwrap()
    );
    // Bit-identical values (including signed zeros and subnormals).
    let mean: Vec<u64> = law.jump_mean().iter().map(|x| x.to_bits()).collect();
    let back_mean: Vec<u64> = back.jump_mean().iter().map(|x| x.to_bits()).collect();
    assert_eq!(mean, back_mean);
    let e = Law::open(dir.join("missing.tclaw")).unwrap_err();
    assert!(matches!(e, Error::Io { .. }) && e.to_string().contains("missing.tclaw"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every single-byte corruption of a valid file (each byte, three masks) is detected.
#[test]
fn every_single_byte_corruption_is_detected() {
    let bytes = small_law(3, 2, 2, 5).to_bytes();
    let mut detected = 0;
    for i in 0..bytes.len() {
        for mask in [0x01u8, 0x80, 0xFF] {
            let mut b = bytes.clone();
            b[i] ^= mask;
            let e = Law::from_bytes(&b).expect_err("corruption not detected");
            assert!(!e.to_string().is_empty());
            detected += 1;
        }
    }
    println!(
        "{detected} single-byte corruptions of a {}-byte file detected",
        bytes.len()
    );
}

/// Header problems are named: magic, version, truncation, trailing bytes, checksum.
#[test]
fn header_problems_are_named() {
    let bytes = small_law(4, 3, 2, 9).to_bytes();
    let msg = |b: &[u8]| Law::from_bytes(b).unwrap_err().to_string();
    assert!(msg(b"").contains("truncated"));
    assert!(msg(b"PK\x03\x04 a zip file perhaps").contains("not a law file"));
    let mut v = bytes.clone();
    v[8..12].copy_from_slice(&7u32.to_le_bytes());
    assert!(msg(&v).contains("unsupported law format version 7"));
    assert!(msg(&bytes[..bytes.len() / 2]).contains("truncated"));
    let mut long = bytes.clone();
    long.extend_from_slice(b"extra");
    assert!(msg(&long).contains("trailing"));
    let mut c = bytes.clone();
    let i = c.len() - 12;
    c[i] ^= 4;
    assert!(msg(&c).contains("CRC-32"));
}

/// Content problems behind a valid checksum are named: metadata and values.
#[test]
fn content_problems_behind_a_valid_checksum_are_named() {
    let bytes = small_law(4, 3, 2, 9).to_bytes();
    let msg = |b: &[u8]| Law::from_bytes(b).unwrap_err().to_string();
    type Edit = Box<dyn Fn(&str) -> String>;
    let cases: [(&str, Edit); 6] = [
        ("jump.unit", Box::new(|t| t.replace("jump.unit = K\n", ""))),
        ("MPa", Box::new(|t| t.replace("unit = Pa", "unit = MPa"))),
        ("unknown key", Box::new(|t| format!("{t}colour = blue\n"))),
        (
            "duplicate",
            Box::new(|t| format!("{t}statistic = ensemble_mean\n")),
        ),
        (
            "extrapolation.flux",
            Box::new(|t| t.replace("flux = clamp", "flux = cubic")),
        ),
        ("key = value", Box::new(|t| format!("{t}no separator\n"))),
    ];
    for (needle, edit) in cases {
        let m = msg(&with_metadata(&bytes, edit));
        assert!(m.contains(needle), "{needle:?} not in {m:?}");
    }
    let mut utf = with_metadata(&bytes, |t| t.to_string());
    utf[HEADER_BYTES + 3] = 0xFF;
    reseal(&mut utf);
    assert!(msg(&utf).contains("UTF-8"));
    // Values: the first pressure node made NaN, then non-increasing; a negative jump.
    let data = meta_range(&bytes).end;
    for (value, at, needle) in [
        (f64::NAN, data, "pressure[0]"),
        (1e9, data, "pressure[1]"),
        (-1.0, bytes.len() - 4 - 8 * 3 * 24, "jump_mean[0]"),
    ] {
        let mut b = bytes.clone();
        b[at..at + 8].copy_from_slice(&value.to_le_bytes());
        reseal(&mut b);
        let m = msg(&b);
        assert!(m.contains(needle), "{needle:?} not in {m:?}");
    }
    // A zero-length axis.
    let mut z = bytes.clone();
    z[16..20].copy_from_slice(&0u32.to_le_bytes());
    let n = z.len();
    let body = with_len(&z, n - 8 * (3 + 3 * 24));
    assert!(msg(&body).contains("flux"), "{}", msg(&body));
}

/// Drops bytes before the CRC so that a header edit matches the size, and reseals.
fn with_len(bytes: &[u8], len: usize) -> Vec<u8> {
    let mut out = bytes[..len - 4].to_vec();
    out.extend_from_slice(&[0; 4]);
    reseal(&mut out);
    out
}

#[derive(Debug, Clone)]
enum Mutation {
    Flip(Vec<(usize, u8)>),
    Truncate(usize),
    Extend(Vec<u8>),
    Overwrite(usize, Vec<u8>),
    Splice(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        prop::collection::vec((any::<usize>(), 1u8..=255), 1..6).prop_map(Mutation::Flip),
        any::<usize>().prop_map(Mutation::Truncate),
        prop::collection::vec(any::<u8>(), 1..64).prop_map(Mutation::Extend),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(i, v)| Mutation::Overwrite(i, v)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::Splice(a, b)),
    ]
}

fn apply(bytes: &[u8], m: &Mutation) -> Vec<u8> {
    let mut b = bytes.to_vec();
    let n = b.len();
    match m {
        Mutation::Flip(flips) => {
            for &(i, mask) in flips {
                b[i % n] ^= mask;
            }
        }
        Mutation::Truncate(len) => b.truncate(len % n),
        Mutation::Extend(extra) => b.extend_from_slice(extra),
        Mutation::Overwrite(at, v) => {
            for (k, &x) in v.iter().enumerate() {
                let i = (at + k) % n;
                b[i] = x;
            }
        }
        Mutation::Splice(a, len) => {
            let a = a % n;
            let end = (a + len % 64).min(n);
            b.drain(a..end);
        }
    }
    b
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Mutated files give an error or (if the mutation is a no-op) the same law,
    /// never a panic; truncation, extension and single flips are always errors.
    #[test]
    fn mutated_files_are_errors_never_panics(
        dims in (1usize..5, 1usize..4, 1usize..3),
        seed in any::<u64>(),
        m in mutation(),
    ) {
        let law = small_law(dims.0, dims.1, dims.2, seed);
        let bytes = law.to_bytes();
        let mutated = apply(&bytes, &m);
        match Law::from_bytes(&mutated) {
            Ok(back) => {
                prop_assert_eq!(&mutated, &bytes, "a changed file was accepted");
                prop_assert_eq!(back, law);
            }
            Err(e) => {
                prop_assert!(!e.to_string().is_empty());
                prop_assert!(mutated != bytes, "valid file rejected: {}", e);
            }
        }
    }

    /// Mutations behind a resealed checksum reach the metadata and value checks:
    /// still an error or a valid law, never a panic.
    #[test]
    fn resealed_mutations_are_errors_or_valid_laws(
        seed in any::<u64>(),
        m in mutation(),
    ) {
        let bytes = small_law(3, 2, 2, seed).to_bytes();
        let mut mutated = apply(&bytes, &m);
        if mutated.len() >= 4 {
            reseal(&mut mutated);
        }
        if let Ok(law) = Law::from_bytes(&mutated) {
            // A valid law round-trips and evaluates without panicking.
            let again = Law::from_bytes(&law.to_bytes()).unwrap();
            prop_assert_eq!(&again, &law);
            let _ = law.eval(1e5, 1e5, 300.0);
            let _ = law.eval_at_jump(1e5, 1.0, 300.0);
        }
    }

    /// Arbitrary bytes are errors, never panics.
    #[test]
    fn arbitrary_bytes_are_errors(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        prop_assert!(Law::from_bytes(&bytes).is_err());
    }

    /// Random valid laws round-trip bit-identically.
    #[test]
    fn random_laws_round_trip(dims in (1usize..6, 1usize..5, 1usize..4), seed in any::<u64>()) {
        let law = small_law(dims.0, dims.1, dims.2, seed);
        let bytes = law.to_bytes();
        let back = Law::from_bytes(&bytes).unwrap();
        prop_assert_eq!(back.to_bytes(), bytes);
        prop_assert_eq!(back, law);
    }
}

/// The bytes of the same law in format version 1 (no discretization-error
/// array, no `discretization_error` / `material` keys).
fn as_version_1(law: &Law) -> Vec<u8> {
    assert!(!law.error_estimated());
    let v2 = law.to_bytes();
    let stripped = with_metadata(&v2, |t| {
        t.replace("discretization_error = not_estimated\n", "")
            .replace("material = unspecified\n", "")
    });
    let n = law.jump_mean().len();
    let mut v1 = stripped[..stripped.len() - 4 - 8 * n].to_vec();
    v1[8..12].copy_from_slice(&1u32.to_le_bytes());
    v1.extend_from_slice(&[0; 4]);
    reseal(&mut v1);
    v1
}

/// Version-1 files (written before the error estimate and the material)
/// are still read, and written back as version 2.
#[test]
fn version_1_files_are_still_read() {
    let law = small_law(5, 3, 2, 11);
    let back = Law::from_bytes(&as_version_1(&law)).unwrap();
    assert_eq!(back, law);
    assert_eq!(back.to_bytes(), law.to_bytes());
    assert_eq!(
        u32::from_le_bytes(law.to_bytes()[8..12].try_into().unwrap()),
        2
    );
    // A version-1 file may not carry version-2 keys.
    let bad = with_metadata(&as_version_1(&law), |t| {
        format!("{t}material = unspecified\n")
    });
    assert!(
        Law::from_bytes(&bad)
            .unwrap_err()
            .to_string()
            .contains("material")
    );
}

/// The discretization error is stored, read back, interpolated like the
/// jump (exact on data linear in ln p), and zeros are demanded when the
/// metadata says not estimated.
#[test]
fn discretization_error_round_trips_and_interpolates() {
    let axes = Axes {
        pressure: geomspace(1e4, 1e7, 6),
        flux: vec![1e5, 1e6],
        contact_temperature: vec![300.0],
    };
    let (mean, std) = tabulate(&axes, linear_jump);
    let error: Vec<f64> = mean.iter().map(|m| 0.01 * m).collect();
    let info = LawInfo {
        statistic: Statistic::EnsembleMeanConductance { samples: 4 },
        ..LawInfo::default()
    };
    let law = Law::from_grid_with_error(axes, mean, std, Some(error), info).unwrap();
    assert!(law.error_estimated());
    let back = Law::from_bytes(&law.to_bytes()).unwrap();
    assert_eq!(back, law);
    let (p, h) = (3.3e5, 4.2e5);
    let v = back.eval(p, h, 300.0).unwrap();
    assert!(
        (v.jump_error - 0.01 * linear_jump(p, h, 300.0).0).abs() < 1e-10,
        "{v:?}"
    );
    let w = back.eval_at_jump(p, v.jump, 300.0).unwrap();
    assert!(
        (w.jump_error - v.jump_error).abs() < 1e-9 * v.jump_error,
        "{w:?}"
    );
    // Claiming no estimate while the array holds values is refused.
    let lie = with_metadata(&law.to_bytes(), |t| {
        t.replace(
            "discretization_error = estimated",
            "discretization_error = not_estimated",
        )
    });
    assert!(
        Law::from_bytes(&lie)
            .unwrap_err()
            .to_string()
            .contains("jump_error")
    );
}

/// `power` along pressure continues `jump = C p^s` exactly from data that
/// follow a power law, below and above the table, with its derivative.
#[test]
fn power_extrapolation_is_exact_on_power_law_data() {
    let axes = Axes {
        pressure: geomspace(1e3, 1e6, 7),
        flux: vec![1e5, 2e5],
        contact_temperature: vec![300.0],
    };
    let f = |p: f64, h: f64, _t: f64| {
        (
            h * 1e-3 * (p / 1e3).powf(-0.8),
            0.1 * h * 1e-3 * (p / 1e3).powf(-0.8),
        )
    };
    let (mean, std) = tabulate(&axes, f);
    let info = LawInfo {
        extrapolation: ExtrapolationPolicy {
            pressure: Extrapolation::Power,
            ..ExtrapolationPolicy::default()
        },
        statistic: Statistic::EnsembleMean { samples: 3 },
        ..LawInfo::default()
    };
    let law = Law::from_grid(axes, mean, std, info).unwrap();
    for p in [1.0, 50.0, 3e6, 1e8] {
        let v = law.eval(p, 1.5e5, 300.0).unwrap();
        let (j, s) = f(p, 1.5e5, 300.0);
        assert!(v.extrapolated[0]);
        assert!((v.jump - j).abs() < 1e-9 * j, "p {p}: {} vs {j}", v.jump);
        assert!(
            (v.jump_std - s).abs() < 1e-9 * s,
            "p {p}: std {}",
            v.jump_std
        );
        let dj = -0.8 * j / p;
        assert!(
            (v.d_jump_dp - dj).abs() < 1e-8 * dj.abs(),
            "p {p}: {} vs {dj}",
            v.d_jump_dp
        );
        // The conductance follows k ∝ p^0.8.
        assert!((v.conductance - 1.5e5 / j).abs() < 1e-9 * v.conductance);
    }
    assert!(law.eval(0.0, 1.5e5, 300.0).is_err());
    // Along flux it is refused.
    let mut bad = law.clone();
    let e = bad
        .set_extrapolation(ExtrapolationPolicy {
            flux: Extrapolation::Power,
            ..ExtrapolationPolicy::default()
        })
        .unwrap_err();
    assert!(e.to_string().contains("extrapolation.flux"), "{e}");
}

/// The material is written, read back and checked property by property.
#[test]
fn material_is_recorded_and_checked() {
    use lookup::{BodyMaterial, LawMaterial};
    let mut law = small_law(3, 2, 2, 5);
    let upper = BodyMaterial::from_values([1e6, 0.3, 1e-5, 1.0, 0.01, 293.15]);
    let lower = BodyMaterial {
        youngs_modulus: 2.1e11,
        ..upper
    };
    let mut info = law.info().clone();
    info.material = Some(LawMaterial { upper, lower });
    law = Law::from_grid(
        law.axes().clone(),
        law.jump_mean().to_vec(),
        law.jump_std().to_vec(),
        info,
    )
    .unwrap();
    let back = Law::from_bytes(&law.to_bytes()).unwrap();
    assert_eq!(back.info().material, law.info().material);
    back.check_material("upper", &upper, 0.0).unwrap();
    back.check_material("lower", &lower, 1e-12).unwrap();
    let e = back
        .check_material("upper", &lower, 1e-6)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("material.upper.youngs_modulus") && e.contains("1000000"),
        "{e}"
    );
    let slightly = BodyMaterial {
        poisson_ratio: 0.3 * (1.0 + 1e-9),
        ..upper
    };
    back.check_material("upper", &slightly, 1e-6).unwrap();
    assert!(back.check_material("upper", &slightly, 0.0).is_err());
    assert!(
        small_law(3, 2, 2, 5)
            .check_material("upper", &upper, 1.0)
            .is_err()
    );
}
