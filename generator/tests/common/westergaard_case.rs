//! The Westergaard case of the adaptivity and contact-edge tests: the
//! small-strain wavy sample (`A/λ = 5e-4`, `H = λ`, PR, constant
//! conductivity, plain two-phase) as a case file.

use std::path::Path;

use tcgen::sample::Case;
use tcgen::verify::contact::wavy::WavySample;

/// `WavySample` with `A/λ = 5e-4`.
pub fn sample() -> WavySample {
    WavySample {
        amplitude: 5.0e-9,
        ..WavySample::default()
    }
}

/// The case of [`sample`] at the fractions `levels` of `p*`, with the
/// elements `[nx, nz]` of the upper and lower bodies and extra lines for
/// `[discretization]` and `[contact]`.
pub fn case(
    levels: &[f64],
    upper: [usize; 2],
    lower: [usize; 2],
    discretization: &str,
    contact: &str,
) -> Case {
    let s = sample();
    let pressures: Vec<String> = levels
        .iter()
        .map(|f| format!("{:e}", f * s.p_star()))
        .collect();
    let text = format!(
        r#"
[sample]
width = {w:e}
height = {h:e}
lateral = "periodic"
[surface.upper]
kind = "sinusoid"
rms = {rms:e}
wavelength = {w:e}
[surface.lower]
kind = "flat"
[material]
conductivity_slope = 0.0
[discretization]
degree = 2
elements_upper = {upper:?}
elements_lower = {lower:?}
{discretization}
[contact]
{contact}
[homogenization]
method = "two-phase"
[load]
flux = {flux:e}
pressures = [{p}]
"#,
        w = s.wavelength,
        h = s.height,
        rms = s.amplitude / 2f64.sqrt(),
        flux = s.flux,
        p = pressures.join(", "),
    );
    Case::from_toml(&text, Path::new(".")).unwrap()
}
