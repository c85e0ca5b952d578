//! The contact law inside the real CalculiX solver (issue 13): `tcgen law
//! --format calculix` writes the `*GAP CONDUCTANCE` block of the committed
//! reference table, a two-block CalculiX model includes it, and the jump
//! CalculiX computes across the interface must be `|h̄| / k̄c(p̄N, θ̄c)` of the
//! law at the contact pressure CalculiX reports.
//!
//! The model (built here, in either unit system through
//! `tcgen::io::DeckUnits`, the export's own conversion factors): two
//! 1 × 1 × 1 mm steel blocks stacked along z, 1 × 1 × 4 C3D8 elements each,
//! frictionless face-to-face penalty contact (lower block master), lateral
//! symmetry planes, the bottom face at a fixed temperature chosen so that the
//! master surface sits at the table's θ̄c = 293.15 K, and on the top face the
//! law's flux (in) and a pressure, changed step by step to three values
//! inside the table's range, each a steady-state coupled
//! temperature-displacement step. One heat path, no lateral flux: the jump
//! is `T_slave − T_master` at the interface nodes (`*NODE PRINT`), the
//! pressure the mean contact stress (`*CONTACT PRINT`).
//!
//! Tolerances: the deck follows the law within its `--tolerance` (1e-3,
//! relative, and 3e-5 in a third run; the writer's sampled maximum is in
//! the deck's header); CalculiX prints
//! temperatures to 7 significant digits (±5e-5 K at 295 K, ≤ 1e-4 of the
//! 1.5 K jump at 1e5 W/m², ≤ 1e-5 of the 15 K jump at 1e6 W/m²) and solves
//! each step to its residual tolerance. So: against the law tolerance + 2e-4;
//! against the deck's own linear interpolation (what CalculiX should do
//! exactly) 2e-4.
//!
//! CalculiX is installed by `scripts/install_test_tools.sh` when missing; if
//! it cannot be installed or run, the test fails with the reason.

use std::path::{Path, PathBuf};
use std::process::Command;

use tcgen::io::DeckUnits;
use tcgen::io::gap_conductance::deck_number as num;

const THETA_C: f64 = 293.15;
const HEIGHT: f64 = 1e-3; // m, each block
const LAYERS: usize = 4; // elements along z per block
const YOUNGS_MODULUS: f64 = 210e9; // Pa
const CONDUCTIVITY: f64 = 50.0; // W/(m K)
const PENALTY: f64 = 1e16; // Pa/m: 1e-10 m of overclosure at 1 kPa
const OUTPUT_PRECISION: f64 = 2e-4;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ccx_runs() -> Result<String, String> {
    let o = Command::new("ccx")
        .arg("-v")
        .output()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    if text.contains("Version") {
        Ok(text.trim().to_string())
    } else {
        Err(format!("`ccx -v` printed {text:?}"))
    }
}

/// `ccx` on the PATH, installed by the project's script if missing.
fn ensure_ccx() -> String {
    if let Ok(v) = ccx_runs() {
        return v;
    }
    let script = root().join("scripts/install_test_tools.sh");
    let o = Command::new("bash").arg(&script).output();
    match ccx_runs() {
        Ok(v) => v,
        Err(e) => panic!(
            "CalculiX (`ccx`) is needed by this test and could not be run ({e}); \
             {} did not install it ({}): install the Debian package calculix-ccx",
            script.display(),
            match o {
                Ok(o) => String::from_utf8_lossy(&o.stderr).trim().to_string(),
                Err(e) => e.to_string(),
            }
        ),
    }
}

fn tcgen_law(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_tcgen"))
        .arg("law")
        .arg(root().join("tables/reference.h5"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "tcgen law {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// One CalculiX model: the unit system, the flux [W/m²] and the pressures [Pa].
struct Model {
    units: DeckUnits,
    celsius: bool,
    flux: f64,
    pressures: Vec<f64>,
    /// The export's `--tolerance`.
    tolerance: f64,
}

impl Model {
    fn temperature(&self, kelvin: f64) -> f64 {
        if self.celsius {
            kelvin - tcgen::io::gap_conductance::CELSIUS_OFFSET
        } else {
            kelvin
        }
    }

    /// The input deck, including the `*GAP CONDUCTANCE` block `gap_file`.
    fn deck(&self, gap_file: &str) -> String {
        let u = self.units;
        let l = HEIGHT * u.length();
        let nz = 2 * LAYERS + 2; // node layers: lower block 0..=LAYERS, upper LAYERS+1..
        let mut s = String::from(
            "** tcgen calculix_end_to_end: two blocks in thermal contact\n*NODE, NSET=NALL\n",
        );
        let node = |layer: usize, corner: usize| layer * 4 + corner + 1;
        let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        for layer in 0..nz {
            // The upper block's first layer coincides with the lower's last.
            let k = if layer <= LAYERS { layer } else { layer - 1 };
            let z = k as f64 * l / LAYERS as f64;
            for (c, (x, y)) in corners.iter().enumerate() {
                s += &format!(
                    "{}, {}, {}, {}\n",
                    node(layer, c),
                    num(x * l),
                    num(y * l),
                    num(z)
                );
            }
        }
        let element = |e: usize, layer: usize| {
            let n: Vec<String> = (0..8)
                .map(|i| node(layer + i / 4, i % 4).to_string())
                .collect();
            format!("{e}, {}\n", n.join(", "))
        };
        s += "*ELEMENT, TYPE=C3D8, ELSET=ELOWER\n";
        for k in 0..LAYERS {
            s += &element(k + 1, k);
        }
        s += "*ELEMENT, TYPE=C3D8, ELSET=EUPPER\n";
        for k in 0..LAYERS {
            s += &element(LAYERS + k + 1, LAYERS + 1 + k);
        }
        let set = |name: &str, nodes: Vec<usize>| {
            // At most 16 entries a line.
            let lines: Vec<String> = nodes
                .chunks(16)
                .map(|c| {
                    c.iter()
                        .map(usize::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .collect();
            format!("*NSET, NSET={name}\n{}\n", lines.join("\n"))
        };
        let on = |pred: &dyn Fn(usize) -> bool| -> Vec<usize> {
            (0..nz)
                .flat_map(|layer| (0..4).map(move |c| (layer, c)))
                .filter(|&(_, c)| pred(c))
                .map(|(layer, c)| node(layer, c))
                .collect()
        };
        s += "*ELSET, ELSET=EALL\nELOWER, EUPPER\n";
        s += &set("NBOTTOM", (0..4).map(|c| node(0, c)).collect());
        s += &set("NMASTER", (0..4).map(|c| node(LAYERS, c)).collect());
        s += &set("NSLAVE", (0..4).map(|c| node(LAYERS + 1, c)).collect());
        s += &set("NX0", on(&|c| c == 0 || c == 3));
        s += &set("NY0", on(&|c| c == 0 || c == 1));
        let (top, bottom) = (2 * LAYERS, LAYERS + 1); // top element of the upper block, its bottom element
        let flux = self.flux * u.flux();
        let theta_bottom = THETA_C - self.flux * HEIGHT / CONDUCTIVITY;
        s += &format!(
            "*MATERIAL, NAME=STEEL\n*ELASTIC\n{}, 0.3\n*CONDUCTIVITY\n{}\n\
             *SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n\
             *SURFACE, NAME=SMASTER\n{LAYERS}, S2\n*SURFACE, NAME=SSLAVE\n{bottom}, S1\n\
             *CONTACT PAIR, INTERACTION=SI1, TYPE=SURFACE TO SURFACE\nSSLAVE, SMASTER\n\
             *SURFACE INTERACTION, NAME=SI1\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{}\n\
             *INCLUDE, INPUT={gap_file}\n\
             *INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, {}\n\
             *BOUNDARY\nNBOTTOM, 3, 3\nNX0, 1, 1\nNY0, 2, 2\nNBOTTOM, 11, 11, {}\n",
            num(YOUNGS_MODULUS * u.pressure()),
            num(CONDUCTIVITY * u.conductivity()),
            num(PENALTY * u.pressure() / u.length()),
            num(self.temperature(THETA_C)),
            num(self.temperature(theta_bottom)),
        );
        for &p in &self.pressures {
            s += &format!(
                "*STEP\n*COUPLED TEMPERATURE-DISPLACEMENT, STEADY STATE\n1., 1.\n\
                 *DLOAD\n{top}, P2, {}\n*DFLUX\n{top}, S2, {}\n\
                 *NODE PRINT, NSET=NMASTER\nNT\n*NODE PRINT, NSET=NSLAVE\nNT\n\
                 *NODE PRINT, NSET=NALL\nNT\n*CONTACT PRINT\nCSTR\n*END STEP\n",
                num(p * u.pressure()),
                num(flux)
            );
        }
        s
    }
}

/// One step of the `.dat` file: the interface temperatures and the contact pressures.
#[derive(Default, Debug)]
struct Step {
    master: Vec<f64>,
    slave: Vec<f64>,
    pressure: Vec<f64>,
}

fn parse_dat(dat: &str) -> Vec<Step> {
    let mut steps: Vec<Step> = Vec::new();
    let mut target: Option<(usize, u8)> = None;
    for line in dat.lines() {
        let t = line.trim();
        if t.starts_with("temperatures for set") || t.starts_with("contact stress") {
            let time: f64 = t.split_whitespace().last().unwrap().parse().unwrap();
            let step = time.round() as usize - 1;
            while steps.len() <= step {
                steps.push(Step::default());
            }
            target = Some((
                step,
                if t.contains("set NMASTER ") {
                    b'm'
                } else if t.contains("set NSLAVE ") {
                    b's'
                } else if t.starts_with("contact stress") {
                    b'p'
                } else {
                    b'-'
                },
            ));
            continue;
        }
        let fields: Vec<f64> = t
            .split_whitespace()
            .filter_map(|f| f.parse().ok())
            .collect();
        let (Some((step, kind)), false) = (target, fields.is_empty()) else {
            continue;
        };
        let s = &mut steps[step];
        match kind {
            b'm' => s.master.push(fields[1]),
            b's' => s.slave.push(fields[1]),
            b'p' => s.pressure.push(fields[2]),
            _ => {}
        }
    }
    steps
}

fn mean(v: &[f64]) -> f64 {
    assert!(!v.is_empty());
    v.iter().sum::<f64>() / v.len() as f64
}

/// The deck's rows `(conductance, pressure)` and CalculiX's linear
/// interpolation of them (one temperature set).
fn deck_interpolation(gap: &str, p: f64) -> f64 {
    let rows: Vec<(f64, f64)> = gap
        .lines()
        .skip_while(|l| !l.starts_with("*GAP CONDUCTANCE"))
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.trim().parse().unwrap()).collect();
            (f[0], f[1])
        })
        .collect();
    let i = rows.windows(2).position(|w| p <= w[1].1).unwrap();
    let ((k0, p0), (k1, p1)) = (rows[i], rows[i + 1]);
    k0 + (k1 - k0) * (p - p0) / (p1 - p0)
}

/// Exports the block, runs CalculiX and compares the jumps; returns the
/// worst relative difference against the law.
fn run_model(
    dir: &Path,
    name: &str,
    m: &Model,
    law: &lookup::Law,
    in_process: &lookup::Law,
) -> f64 {
    let u = m.units;
    let gap_file = format!("{name}_gap.inp");
    let mut args = vec![
        "--format".to_string(),
        "calculix".into(),
        "--flux".into(),
        format!("{:e}", m.flux),
        "--units".into(),
        u.name().into(),
        "--tolerance".into(),
        format!("{:e}", m.tolerance),
        "-o".into(),
        dir.join(&gap_file).display().to_string(),
    ];
    if m.celsius {
        args.push("--celsius".into());
    }
    tcgen_law(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let gap = std::fs::read_to_string(dir.join(&gap_file)).unwrap();
    std::fs::write(dir.join(format!("{name}.inp")), m.deck(&gap_file)).unwrap();
    let o = Command::new("ccx")
        .arg("-i")
        .arg(name)
        .current_dir(dir)
        .output()
        .expect("run ccx");
    let log = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && log.contains("Job finished") && !log.contains("*ERROR"),
        "ccx failed on {}:\n{log}",
        dir.join(name).display()
    );
    let dat = std::fs::read_to_string(dir.join(format!("{name}.dat"))).unwrap();
    let steps = parse_dat(&dat);
    assert_eq!(steps.len(), m.pressures.len(), "{dat}");
    let t_lo = law.axes().contact_temperature[0];
    let t_hi = *law.axes().contact_temperature.last().unwrap();
    let mut worst: f64 = 0.0;
    for (s, &p_load) in steps.iter().zip(&m.pressures) {
        let p = mean(&s.pressure) / u.pressure(); // Pa
        let jump = mean(&s.slave) - mean(&s.master); // K (= °C difference)
        let theta_c = mean(&s.master) + if m.celsius { 273.15 } else { 0.0 };
        assert!(
            (p / p_load - 1.0).abs() < 1e-4,
            "pressure {p} vs load {p_load}"
        );
        assert!((theta_c - THETA_C).abs() < 1e-3, "θc {theta_c}");
        // The deck has one temperature set; the law is evaluated at its node.
        let theta = theta_c.clamp(t_lo, t_hi);
        let v = law.eval(p, m.flux, theta).unwrap();
        let w = in_process.eval(p, m.flux, theta).unwrap();
        assert!((v.conductance / w.conductance - 1.0).abs() < 1e-14);
        let jump_law = m.flux / v.conductance;
        let jump_deck = m.flux * u.flux() / deck_interpolation(&gap, p * u.pressure());
        let (rel_law, rel_deck) = (jump / jump_law - 1.0, jump / jump_deck - 1.0);
        println!(
            "{name}: p = {p:.6e} Pa, |h| = {:e} W/m^2: jump CalculiX {jump:.6} K, law {jump_law:.6} K \
             (rel. {rel_law:+.2e}), deck rows {jump_deck:.6} K (rel. {rel_deck:+.2e})",
            m.flux
        );
        assert!(
            rel_deck.abs() <= OUTPUT_PRECISION,
            "{name} at {p} Pa: CalculiX {jump} K vs its rows {jump_deck} K"
        );
        assert!(
            rel_law.abs() <= m.tolerance + OUTPUT_PRECISION,
            "{name} at {p} Pa: CalculiX {jump} K vs the law {jump_law} K"
        );
        worst = worst.max(rel_law.abs());
    }
    worst
}

#[test]
fn calculix_jump_matches_the_law_through_gap_conductance() {
    let version = ensure_ccx();
    println!("{version}");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("calculix-e2e");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let law_path = dir.join("reference.tclaw");
    tcgen_law(&["-o", law_path.to_str().unwrap()]);
    let law = lookup::Law::open(&law_path).unwrap();
    let table = tcgen::io::read_table(&root().join("tables/reference.h5")).unwrap();
    let in_process = tcgen::io::law_from_table(&table, "reference.h5").unwrap();
    let pressures = vec![1.2e3, 2.4e3, 3.5e3];
    let mm = Model {
        units: DeckUnits::MmNSK,
        celsius: false,
        flux: 1e5,
        pressures: pressures.clone(),
        tolerance: 1e-3,
    };
    let fine = Model {
        tolerance: 3e-5,
        pressures: pressures.clone(),
        ..mm
    };
    let si = Model {
        units: DeckUnits::Si,
        celsius: true,
        flux: 1e6,
        pressures,
        tolerance: 1e-3,
    };
    let a = run_model(&dir, "blocks_mm", &mm, &law, &in_process);
    let b = run_model(&dir, "blocks_si", &si, &law, &in_process);
    let c = run_model(&dir, "blocks_fine", &fine, &law, &in_process);
    println!(
        "worst relative difference CalculiX vs law: mm-N-s-K {a:.2e}, SI/Celsius {b:.2e}, \
         mm-N-s-K with --tolerance 3e-5 {c:.2e}"
    );
    // A tighter deck follows the law more closely, down to the output precision.
    assert!(c < a / 3.0, "{c} vs {a}");
}

/// Bad options exit 2 with the option named, and leave no file behind.
#[test]
fn bad_deck_options_exit_2_without_output() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("calculix-bad-options");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("gap.inp");
    for (args, needle) in [
        (vec!["--format", "nastran"], "--format"),
        (vec!["--format", "calculix"], "--flux"),
        (vec!["--format", "calculix", "--flux", "5e6"], "--flux"),
        (
            vec!["--format", "calculix", "--flux", "1e5", "--units", "inch"],
            "--units",
        ),
        (
            vec!["--format", "calculix", "--flux", "1e5", "--tolerance", "0"],
            "--tolerance",
        ),
        (
            vec![
                "--format",
                "abaqus",
                "--flux",
                "1e5",
                "--pressure-range",
                "1e2:1e4",
            ],
            "--pressure-range",
        ),
        (vec!["--flux", "1e5"], "--flux"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_tcgen"))
            .arg("law")
            .arg(root().join("tables/reference.h5"))
            .args(&args)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} left {}", out.display());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "{args:?}");
    }
}
