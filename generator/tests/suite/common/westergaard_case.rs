//! The Westergaard case of the adaptivity and contact-edge tests: the
//! small-strain wavy sample (`A/λ = 5e-4`, `H = λ`, PR, constant
//! conductivity, plain two-phase) as a case file.

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
/// `[discretization]` and `[contact]` ([`WavySample::case`]).
pub fn case(
    levels: &[f64],
    upper: [usize; 2],
    lower: [usize; 2],
    discretization: &str,
    contact: &str,
) -> Case {
    sample()
        .case(levels, upper, lower, discretization, contact)
        .unwrap()
}
