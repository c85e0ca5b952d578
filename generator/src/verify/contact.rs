//! Verification of the contact algorithms (issue 3; spec §10.2–10.5; paper
//! Sects. 5.1, 5.2, 5.7), printed by `tcgen verify` and checked by
//! `tests/suite/contact_verification.rs`.
//!
//! - [`patch`]: thermal patch tests on flat and curved (NURBS-exact)
//!   conforming interfaces with non-matching meshes, and the mechanical patch
//!   test (uniform platen pressure transmitted uniformly);
//! - [`hertz`]: thermoelastic Hertz contact of two cylinders, half-width and
//!   pressure against Hertz, interface flux against (5.2) as `kθ` grows;
//! - [`hertz3d`]: a sphere on a flat in 3D, contact radius and pressure
//!   against Hertz, the constraint-limit flux of the isothermal spot;
//! - [`wavy`]: Westergaard's sinusoid on a flat in the small-strain limit, the
//!   thermal constriction of its strips and Barber's analogy;
//! - [`robustness`]: the sinusoid of Sect. 5.7 from first touch to 95 %
//!   contact, and bit-for-bit determinism across rayon thread counts.
//!
//! The cases of the catalogue use the meshes the default test suite can
//! afford; the functions take the setups, so that the long runs
//! (`TCGEN_LONG_TESTS=1`) refine them. Each tolerance below is the figure
//! achieved with a margin, and its reason (a quadrature or discretization
//! error whose convergence was measured, or the benchmark's modelling error).

pub mod egg_box;
pub mod hertz;
pub mod hertz3d;
pub mod patch;
pub mod robustness;
pub mod wavy;

use crate::Result;
use crate::contact::ThermalMethod;
use crate::sample::case::{LateralCondition, Method};
use crate::verify::{Case, Check};

use hertz::{HertzSetup, ThermalModel};
use hertz3d::Hertz3dSetup;
use patch::{Interface, PatchSetup, continuum_penalty, mortar_al, thermal_patch};
use wavy::{WESTERGAARD_LEVELS, WavySample};

/// Table I with a constant conductivity: the material of the small-strain
/// benchmarks (Hertz, Westergaard), both bodies.
pub fn benchmark_material() -> crate::material::Material {
    crate::material::Material {
        conductivity_slope: 0.0,
        ..crate::material::Material::default()
    }
}

/// `E*` of two equal plane-strain bodies of [`benchmark_material`].
pub fn benchmark_e_star() -> f64 {
    let m = benchmark_material();
    crate::analytical::westergaard::effective_modulus(
        m.youngs_modulus,
        m.poisson_ratio,
        m.youngs_modulus,
        m.poisson_ratio,
    )
}

/// Flux of the thermal patch tests (W/m²): a 10 K rise over the 10 μm block.
pub const PATCH_FLUX: f64 = 1.0e6;

/// The patch setup with nested non-matching meshes: the slave (p = 3, 6
/// elements) refines the master's knots (p = 2, 3 elements), so the master
/// basis is smooth inside every slave element and the element-based mortar
/// integrals are exact up to the rational weights.
pub fn nested_patch(interface: Interface) -> PatchSetup {
    let mut s = PatchSetup::new(interface);
    s.upper.elements = 6;
    s
}

/// Thermal patch test, flat interface: exact to round-off with nested
/// non-matching meshes; element-based integration error on non-nested ones
/// (the master's kinks inside slave elements: 1.0e−4 with 8 interface points,
/// 2.5e−5 with 16, 4.4e−7 with 32, 6.0e−8 with 64); the continuum penalty
/// method gives the uniform penalty jump `h̄/εθ`.
pub fn thermal_patch_flat() -> Result<Vec<Check>> {
    let name = "contact_patch_thermal_flat";
    let mut v = Vec::new();
    let m = thermal_patch(&nested_patch(Interface::Flat), &mortar_al(), PATCH_FLUX)?;
    v.push(Check::absolute(
        name,
        "AL nested: interface flux dev.",
        m.flux_deviation,
        0.0,
        1e-9,
    ));
    v.push(Check::absolute(
        name,
        "AL nested: max |γθ^I| (K)",
        m.lumped_jump,
        0.0,
        1e-6,
    ));
    v.push(Check::absolute(
        name,
        "AL nested: max |ϑc| at points (K)",
        m.pointwise_jump,
        0.0,
        1e-6,
    ));
    v.push(Check::absolute(
        name,
        "AL nested: max |θ − θ_exact| (K)",
        m.temperature_error,
        0.0,
        1e-9,
    ));
    let general = PatchSetup::new(Interface::Flat);
    let g8 = thermal_patch(&general, &mortar_al(), PATCH_FLUX)?;
    v.push(Check::absolute(
        name,
        "AL non-nested 8 pts: flux dev.",
        g8.flux_deviation,
        0.0,
        2e-4,
    ));
    v.push(Check::absolute(
        name,
        "AL non-nested 8 pts: max |γθ^I| (K)",
        g8.lumped_jump,
        0.0,
        1e-6,
    ));
    let mut s32 = mortar_al();
    s32.interface_points = 32;
    let g32 = thermal_patch(&general, &s32, PATCH_FLUX)?;
    v.push(Check::absolute(
        name,
        "AL non-nested 32 pts: flux dev.",
        g32.flux_deviation,
        0.0,
        1e-6,
    ));
    v.push(Check::absolute(
        name,
        "AL non-nested 32 pts: max |ϑc| (K)",
        g32.pointwise_jump,
        0.0,
        1e-6,
    ));
    let c = thermal_patch(
        &nested_patch(Interface::Flat),
        &continuum_penalty(),
        PATCH_FLUX,
    )?;
    v.push(Check::relative(
        name,
        "continuum penalty: jump (K) vs h̄/εθ",
        c.lumped_jump,
        PATCH_FLUX / c.penalty,
        1e-9,
    ));
    v.push(Check::absolute(
        name,
        "continuum penalty: bulk flux dev.",
        c.bulk_flux_deviation,
        0.0,
        1e-9,
    ));
    Ok(v)
}

/// Thermal patch test, curved interface (exact 90° arc): the mortar method
/// with the augmented Lagrangian keeps the bodies one (its floor, 6e−7, is
/// the default `p + 2` bulk quadrature of the rational basis: 6e−13 with 8
/// points); the continuum penalty method does not (paper Fig. 9).
pub fn thermal_patch_curved() -> Result<Vec<Check>> {
    let name = "contact_patch_thermal_curved";
    let mut v = Vec::new();
    let nested = nested_patch(Interface::Curved);
    let m = thermal_patch(&nested, &mortar_al(), PATCH_FLUX)?;
    for (q, e, tol) in [
        ("AL nested: interface flux dev.", m.flux_deviation, 1e-6),
        ("AL nested: bulk flux dev.", m.bulk_flux_deviation, 1e-6),
        ("AL nested: max |γθ^I| (K)", m.lumped_jump, 1e-6),
        ("AL nested: max |ϑc| (K)", m.pointwise_jump, 1e-6),
        (
            "AL nested: max |θ − θ_exact| (K)",
            m.temperature_error,
            1e-5,
        ),
    ] {
        v.push(Check::absolute(name, q, e, 0.0, tol));
    }
    let mut exact_quadrature = nested.clone();
    exact_quadrature.bulk_points = Some(8);
    let mq = thermal_patch(&exact_quadrature, &mortar_al(), PATCH_FLUX)?;
    v.push(Check::absolute(
        name,
        "AL nested, 8 bulk pts: flux dev.",
        mq.flux_deviation,
        0.0,
        1e-9,
    ));
    let mut s32 = mortar_al();
    s32.interface_points = 32;
    let g32 = thermal_patch(&PatchSetup::new(Interface::Curved), &s32, PATCH_FLUX)?;
    v.push(Check::absolute(
        name,
        "AL non-nested 32 pts: flux dev.",
        g32.flux_deviation,
        0.0,
        1e-6,
    ));
    let c = thermal_patch(&nested, &continuum_penalty(), PATCH_FLUX)?;
    let ratio = c.bulk_flux_deviation / m.bulk_flux_deviation;
    v.push(Check::with_error(
        name,
        &format!(
            "continuum/AL flux dev. ({:.1e}, ϑc {:.2} K)",
            c.bulk_flux_deviation, c.pointwise_jump
        ),
        ratio,
        100.0,
        100.0 / ratio,
        1.0,
    ));
    Ok(v)
}

/// The 3D patch tests (paper Fig. 9; bodies extruded along y, the
/// interface a plane or a circular cylinder): with nested non-matching
/// meshes (the slave's knots refine the master's in x and y) the mortar
/// method with the augmented Lagrangian passes the thermal and mechanical
/// patch tests to round-off; on non-nested meshes the element-based
/// integration error remains (the master's kinks inside slave elements,
/// as in 2D); the continuum penalty method gives the penalty jump `h̄/εθ`
/// and, on the curved interface, a non-uniform bulk flux.
pub fn patch_3d() -> Result<Vec<Check>> {
    let name = "contact_patch_3d";
    let mut v = Vec::new();
    let nested = |interface| {
        let mut s = PatchSetup::new_3d(interface);
        s.upper.elements = 6;
        s
    };
    // (label, computed, tolerance) rows, each an absolute check against 0.
    let push = |v: &mut Vec<Check>, prefix: &str, rows: [(&str, f64, f64); 4]| {
        for (q, e, tol) in rows {
            v.push(Check::absolute(name, &format!("{prefix}{q}"), e, 0.0, tol));
        }
    };
    for interface in [Interface::Flat, Interface::Curved] {
        let m = thermal_patch(&nested(interface), &mortar_al(), PATCH_FLUX)?;
        push(
            &mut v,
            &format!("{interface:?} AL nested: "),
            [
                ("interface flux dev.", m.flux_deviation, 1e-6),
                ("bulk flux dev.", m.bulk_flux_deviation, 1e-6),
                ("max |γθ^I| (K)", m.lumped_jump, 1e-6),
                ("max |ϑc| (K)", m.pointwise_jump, 1e-6),
            ],
        );
        let g = thermal_patch(&PatchSetup::new_3d(interface), &mortar_al(), PATCH_FLUX)?;
        v.push(Check::absolute(
            name,
            &format!("{interface:?} AL non-nested: max |γθ^I| (K)"),
            g.lumped_jump,
            0.0,
            1e-6,
        ));
        v.push(Check::absolute(
            name,
            &format!("{interface:?} AL non-nested 8 pts: flux dev."),
            g.flux_deviation,
            0.0,
            5e-4,
        ));
        let mut clipped = mortar_al();
        clipped.integration = crate::contact::Integration::Segment;
        // On the cylinder the floor is the rational basis's default bulk
        // quadrature (as nested); 8 bulk points remove it.
        let mut general = PatchSetup::new_3d(interface);
        general.bulk_points = Some(8);
        let s = thermal_patch(&general, &clipped, PATCH_FLUX)?;
        push(
            &mut v,
            &format!("{interface:?} AL non-nested, clipped, 8 bulk pts: "),
            [
                ("interface flux dev.", s.flux_deviation, 1e-9),
                ("bulk flux dev.", s.bulk_flux_deviation, 1e-6),
                ("max |γθ^I| (K)", s.lumped_jump, 1e-9),
                ("max |ϑc| (K)", s.pointwise_jump, 1e-6),
            ],
        );
        let c = thermal_patch(&nested(interface), &continuum_penalty(), PATCH_FLUX)?;
        v.push(Check::relative(
            name,
            &format!("{interface:?} continuum penalty: max |γθ^I| (K) vs h̄/εθ"),
            c.lumped_jump,
            PATCH_FLUX / c.penalty,
            0.05,
        ));
    }
    let p = 1.0e4;
    let element = crate::contact::Integration::Element;
    let n = patch::mechanical_patch(&nested(Interface::Flat), p, 4, element)?;
    let g = patch::mechanical_patch(&PatchSetup::new_3d(Interface::Flat), p, 8, element)?;
    let clipped = patch::mechanical_patch(
        &PatchSetup::new_3d(Interface::Flat),
        p,
        8,
        crate::contact::Integration::Segment,
    )?;
    v.push(Check::absolute(
        name,
        "mechanical non-nested, clipped: max |pN^I − p̄|/p̄",
        clipped.pressure_deviation,
        0.0,
        1e-8,
    ));
    v.push(Check::absolute(
        name,
        "mechanical non-nested, clipped: max |g^I| / platen displ.",
        clipped.gap,
        0.0,
        1e-10,
    ));
    v.push(Check::absolute(
        name,
        "mechanical nested: max |pN^I − p̄|/p̄",
        n.pressure_deviation,
        0.0,
        1e-8,
    ));
    v.push(Check::absolute(
        name,
        "mechanical nested: platen displacement rel. error",
        n.displacement_error,
        0.0,
        1e-8,
    ));
    v.push(Check::absolute(
        name,
        "mechanical non-nested 8 pts: max |pN^I − p̄|/p̄",
        g.pressure_deviation,
        0.0,
        1e-3,
    ));
    Ok(v)
}

/// The 3D egg box on a flat ([`egg_box`]) on the default sample, at
/// [`egg_box::RATIOS`] of `p*`.
pub fn egg_box_default() -> Result<Vec<Check>> {
    let rows = egg_box::EggBoxSample::default().rows(&egg_box::RATIOS)?;
    Ok(egg_box::egg_box_checks(
        "contact_egg_box",
        &rows,
        egg_box::DEFAULT_TOLERANCES,
    ))
}

/// Mechanical patch test (flat, LN sides, bottom fixed): the lumped
/// pressures equal `p̄` to round-off with nested meshes; non-nested meshes
/// carry the element-based integration error (2.9e−4 with 8 interface
/// points, 1.2e−6 with 32, 1.7e−7 with 64), which segment-based integration
/// removes.
pub fn mechanical_patch() -> Result<Vec<Check>> {
    let name = "contact_patch_mechanical";
    let p = 1.0e4;
    let element = crate::contact::Integration::Element;
    let n = patch::mechanical_patch(&nested_patch(Interface::Flat), p, 8, element)?;
    let g = patch::mechanical_patch(&PatchSetup::new(Interface::Flat), p, 8, element)?;
    let seg = patch::mechanical_patch(
        &PatchSetup::new(Interface::Flat),
        p,
        8,
        crate::contact::Integration::Segment,
    )?;
    Ok(vec![
        Check::absolute(
            name,
            "non-nested, segments: max |pN^I − p̄|/p̄",
            seg.pressure_deviation,
            0.0,
            1e-8,
        ),
        Check::absolute(
            name,
            "non-nested, segments: max |g^I| / platen displ.",
            seg.gap,
            0.0,
            1e-10,
        ),
        Check::absolute(
            name,
            "nested: max |pN^I − p̄|/p̄",
            n.pressure_deviation,
            0.0,
            1e-8,
        ),
        Check::absolute(
            name,
            "nested: max |g^I| / platen displacement",
            n.gap,
            0.0,
            1e-10,
        ),
        Check::absolute(
            name,
            "nested: platen displacement vs bars (rel)",
            n.displacement_error,
            0.0,
            1e-10,
        ),
        Check::absolute(
            name,
            "non-nested, 8 pts: max |pN^I − p̄|/p̄",
            g.pressure_deviation,
            0.0,
            5e-4,
        ),
    ])
}

/// Tolerances of the Hertz checks for one mesh.
#[derive(Clone, Copy, Debug)]
pub struct HertzTolerances {
    /// Relative half-width error.
    pub half_width: f64,
    /// Pressure error over `|x/a| < 0.5`, relative to `p0`.
    pub pressure: f64,
    /// Cumulative flux error (AL) over `|x/a| < 0.8`.
    pub cumulative: f64,
}

/// The thermal models of the Hertz checks: mortar with `kθ = 1, 1e2, 1e4`,
/// the constraint model (AL), and the continuum method at `kθ = 1, 1e2`.
pub fn hertz_models() -> Vec<ThermalModel> {
    let continuum = |k| ThermalModel {
        conductance_coefficient: Some(k),
        method: ThermalMethod::Continuum,
    };
    vec![
        ThermalModel::mortar(Some(1.0)),
        ThermalModel::mortar(Some(1e2)),
        ThermalModel::mortar(Some(1e4)),
        ThermalModel::mortar(None),
        continuum(1.0),
        continuum(1e2),
    ]
}

/// The Hertz checks for one setup.
pub fn hertz_checks(setup: &HertzSetup, tol: HertzTolerances) -> Result<Vec<Check>> {
    let mesh = if setup.contact_elements[0] > 8 {
        "fine"
    } else {
        "coarse"
    };
    let name = format!("contact_hertz_p{}_{mesh}", setup.degree);
    let r = hertz::hertz(setup, &hertz_models())?;
    let mut v = vec![
        Check::relative(
            &name,
            "contact half-width (m)",
            r.half_width,
            r.hertz_half_width,
            tol.half_width,
        ),
        Check::absolute(
            &name,
            &format!("pressure err/p0 |x/a|<0.5 (<0.8: {:.3})", r.pressure_error),
            r.pressure_error_centre,
            0.0,
            tol.pressure,
        ),
    ];
    let f = &r.fluxes;
    // The cumulative flux error decreases as kθ grows (f[..3]), and the
    // constraint limit (AL, f[3]) is below kθ = 1e2: on a coarse mesh it
    // concentrates its edge fluxes at the computed zone's edges (inside the
    // exact ones by the mechanical edge error), which kθ = 1e4 smooths.
    let pairs = [(&f[0], &f[1]), (&f[1], &f[2]), (&f[1], &f[3])];
    for w in pairs.map(|(a, b)| [a.clone(), b.clone()]) {
        let label = |m: &ThermalModel| match m.conductance_coefficient {
            Some(k) => format!("kθ={k:e}"),
            None => "AL".into(),
        };
        v.push(Check::with_error(
            &name,
            &format!(
                "flux (5.2) cum. err: {} < {}",
                label(&w[1].model),
                label(&w[0].model)
            ),
            w[1].cumulative_error,
            w[0].cumulative_error,
            w[1].cumulative_error / w[0].cumulative_error,
            1.0,
        ));
    }
    v.push(Check::absolute(
        &name,
        &format!("AL: cum. flux err |r/a|<0.8 (nodal {:.2})", f[3].max_error),
        f[3].cumulative_error,
        0.0,
        tol.cumulative,
    ));
    // Mortar and continuum agree at finite kθ (paper Fig. 6).
    for (m, c) in [(0, 4), (1, 5)] {
        v.push(Check::relative(
            &name,
            &format!(
                "heat flow, continuum vs mortar, kθ={:e}",
                f[m].model.conductance_coefficient.unwrap_or(f64::NAN)
            ),
            f[c].heat_flow,
            f[m].heat_flow,
            1e-3,
        ));
    }
    Ok(v)
}

/// The default Hertz case: p = 2, coarse mesh.
pub fn hertz_default() -> Result<Vec<Check>> {
    hertz_checks(
        &HertzSetup::new(2, false),
        HertzTolerances {
            half_width: 0.05,
            pressure: 0.03,
            // Measured 0.055 (the paper's mortar method, nodal supports).
            cumulative: 0.07,
        },
    )
}

/// Tolerances of the 3D Hertz checks for one mesh.
#[derive(Clone, Copy, Debug)]
pub struct Hertz3dTolerances {
    /// Relative contact-radius error, from the area.
    pub radius: f64,
    /// Relative contact-radius error, from the edge's crossing of the x axis.
    pub axis_radius: f64,
    /// Lumped pressures (multipliers) `pN^I` against `p(r)` over `r/a <
    /// 0.8`, relative to `p0` (they carry a checkerboard mode in 3D).
    pub multiplier: f64,
    /// Nodal contact force per lumped area against `p(r)`, over `r/a < 0.8`,
    /// relative to `p0`.
    pub traction: f64,
    /// `F(r)/F` against Hertz over `r/a ≤ 0.8`.
    pub force: f64,
    /// Nodal heat flow per lumped area against `1/√(1 − r²/a²)` (in units
    /// of `h0_min`) over `r/a < 0.5` (away from the edge).
    pub nodal_flux: f64,
    /// `Q(r)/Q` against the isothermal spot over `r/a ≤ 0.8`.
    pub cumulative: f64,
}

/// The 3D Hertz checks (sphere on a flat) for one setup, under `name`.
pub fn hertz_3d_checks(
    name: &str,
    setup: &Hertz3dSetup,
    tol: Hertz3dTolerances,
) -> Result<(Vec<Check>, hertz3d::Hertz3dResult)> {
    let r = hertz3d::hertz_3d(setup)?;
    let v = vec![
        Check::relative(
            name,
            &format!(
                "contact radius, area (m) [{} unkn., {} its]",
                r.unknowns[0], r.iterations[0]
            ),
            r.radius,
            r.hertz_radius,
            tol.radius,
        ),
        Check::relative(
            name,
            "contact radius, x-axis crossing (m)",
            r.axis_radius,
            r.hertz_radius,
            tol.axis_radius,
        ),
        Check::absolute(
            name,
            &format!("pN^I err/p0 r/a<0.8 (<0.5: {:.3})", r.pressure.centre),
            r.pressure.interior,
            0.0,
            tol.multiplier,
        ),
        Check::absolute(
            name,
            &format!(
                "⟨N^I p⟩/⟨N^I⟩ err/p0 r/a<0.8 (<0.5: {:.3})",
                r.nodal_traction.centre
            ),
            r.nodal_traction.interior,
            0.0,
            tol.traction,
        ),
        Check::absolute(name, "F(r)/F err r/a<=0.8", r.force_error, 0.0, tol.force),
        Check::absolute(
            name,
            &format!(
                "AL: ⟨N^I h0⟩/⟨N^I⟩ (5.2) err r/a<0.5 (<0.8: {:.2}; h0^I {:.1})",
                r.nodal_flux.interior, r.flux.centre
            ),
            r.nodal_flux.centre,
            0.0,
            tol.nodal_flux,
        ),
        Check::absolute(
            name,
            "AL: Q(r)/Q err r/a<=0.8",
            r.cumulative_error,
            0.0,
            tol.cumulative,
        ),
        Check::absolute(
            name,
            &format!("AL: max |γθ^I| active (K) [{} its]", r.iterations[1]),
            r.max_jump,
            0.0,
            1e-6,
        ),
    ];
    Ok((v, r))
}

/// The default 3D Hertz case: p = 2, 6/5 elements over `1.25 a` (4.8
/// across `a` on the slave), 7 539 unknowns. Tolerances: the measured
/// figures with a margin (see [`hertz3d`] and `docs/validation.md`).
pub fn hertz_3d_default() -> Result<Vec<Check>> {
    Ok(hertz_3d_checks(
        "contact_hertz_3d",
        &Hertz3dSetup::new(6),
        Hertz3dTolerances {
            // Measured −0.23 % and +0.97 % (stop 23, the edge fitted to the
            // point gaps; +1.9 / +4.3 % fitted to the weighted nodal gaps).
            radius: 0.01,
            axis_radius: 0.02,
            multiplier: 0.8,
            traction: 0.06,
            force: 0.03,
            nodal_flux: 0.5,
            cumulative: 0.04,
        },
    )?
    .0)
}

/// The long 3D Hertz runs (`TCGEN_LONG_TESTS=1`): the meshes `n = 8, 10,
/// 12` with their tolerances (the contact radius's error, with the edge
/// fitted to the point gaps outside it, is not monotone in `n`: −0.23,
/// −1.14, −0.66, −0.54 % on n = 6, 8, 10, 12 from the area, +0.97, −1.49,
/// −1.51, −0.53 % from the x axis; fitted to the weighted nodal gaps
/// (stop 22) +1.9, −1.2, −0.28, −0.28 % from the area; with the
/// indicator's crossings −6.6, −4.6, −3.7, −3.0 %, first order),
/// the modelling errors at `n = 8` (normal-fixed lateral
/// faces, `W = H = 20 a`, `a/R = 0.015`: the change of the radius), and the
/// default mesh solved without the Hertz predictor (the same state).
pub fn hertz_3d_long() -> Result<Vec<Check>> {
    let mut v = Vec::new();
    let mut base = None;
    for (n, tol) in [
        (
            8,
            Hertz3dTolerances {
                radius: 0.02,
                axis_radius: 0.02,
                multiplier: 0.5,
                traction: 0.035,
                force: 0.01,
                nodal_flux: 0.3,
                cumulative: 0.07,
            },
        ),
        (
            10,
            Hertz3dTolerances {
                radius: 0.01,
                axis_radius: 0.02,
                multiplier: 0.25,
                traction: 0.035,
                force: 0.01,
                nodal_flux: 0.3,
                cumulative: 0.04,
            },
        ),
        (
            12,
            Hertz3dTolerances {
                radius: 0.008,
                axis_radius: 0.008,
                multiplier: 0.3,
                traction: 0.025,
                force: 0.005,
                nodal_flux: 0.3,
                cumulative: 0.06,
            },
        ),
    ] {
        let setup = Hertz3dSetup::new(n);
        let (checks, r) = hertz_3d_checks(&format!("contact_hertz_3d_n{n}"), &setup, tol)?;
        v.extend(checks);
        if n == 8 {
            base = Some(r.radius / r.hertz_radius);
        }
    }
    let base = base.expect("n = 8 solved above");
    let mut fixed = Hertz3dSetup::new(8);
    fixed.lateral = hertz3d::LateralFaces::FixedNormal;
    let mut wide = Hertz3dSetup::new(8);
    wide.width_over_a = 20.0;
    wide.height_over_a = 20.0;
    let mut small = Hertz3dSetup::new(8);
    small.a_over_r = 0.015;
    // Measured 1.3e-5, 1.1e-4 and 6.3e-4 with the edges fitted to the point
    // gaps (stop 49; 1.3e-4, 1.7e-5 and 2.9e-4 before them, 5.6e-6, 1.7e-5
    // and 6.6e-4 at the indicator's crossings): they include the change of
    // the fit with the mesh, small against the radius's own error (1.2 %).
    for (what, setup, tol) in [
        ("lateral faces normal-fixed", fixed, 3e-4),
        ("W = H = 20 a", wide, 3e-4),
        ("a/R = 0.015", small, 2e-3),
    ] {
        let r = hertz3d::hertz_3d(&setup)?;
        let ratio = r.radius / r.hertz_radius;
        v.push(Check::with_error(
            "contact_hertz_3d_modelling",
            &format!("a/a_H, {what} (n = 8: {base:.5})"),
            ratio,
            base,
            (ratio - base).abs(),
            tol,
        ));
    }
    let mut unseeded = Hertz3dSetup::new(6);
    unseeded.seed = false;
    let seeded = hertz3d::hertz_3d(&Hertz3dSetup::new(6))?;
    let r = hertz3d::hertz_3d(&unseeded)?;
    v.push(Check::relative(
        "contact_hertz_3d_predictor",
        &format!(
            "radius without the Hertz predictor ({} vs {} its)",
            r.iterations[0], seeded.iterations[0]
        ),
        r.radius,
        seeded.radius,
        1e-6,
    ));
    Ok(v)
}

/// The default wavy sample: 32/28 elements along x.
pub fn wavy_default_sample() -> WavySample {
    WavySample {
        elements_x: [32, 28],
        ..WavySample::default()
    }
}

/// Westergaard and the strip constriction on one mesh: the contact fraction
/// within `0.75` slave elements of Westergaard's (observed on 32 elements:
/// 0.02–0.25 at 5–70 % of `p*`, 0.52 at 90 %, the zone's edges fitted to the
/// near-edge asymptotics; 0.34–0.53 inside before stop 21), the strips of
/// the conductance within 0.3 elements of the contact zone's width
/// (0.01–0.21: the thermal contact is integrated over the zone) and within
/// 0.75 of Westergaard's (0.03–0.53); Barber's analogy with the computed
/// stiffness is reported.
pub fn wavy_case(s: &WavySample) -> Result<Vec<Check>> {
    let rows = wavy::wavy_rows(s, &WESTERGAARD_LEVELS)?;
    let mut v = wavy::westergaard_checks("contact_westergaard", s, &rows, 0.75);
    // The thermal contact is integrated over the zone: its strips are the
    // zone's to a fraction of an element (observed 0.05–0.18 on 32).
    v.extend(wavy::constriction_checks(
        "contact_constriction",
        s,
        &rows,
        (0.3, 0.75),
    ));
    Ok(v)
}

/// The robustness path of the Sect. 5.7 sinusoid (two-phase, log-spaced
/// pressures from 100 Pa to 0.35 MPa, stopping at 95 % contact): every point
/// converged and 95 % reached. Returns the checks and the path.
pub fn robustness_checks(
    degree: usize,
    lateral: LateralCondition,
    elements_upper: [usize; 2],
    elements_lower: [usize; 2],
) -> Result<(Vec<Check>, Vec<robustness::PathPoint>)> {
    let lat = match lateral {
        LateralCondition::Periodic => "pr",
        LateralCondition::Linear => "ln",
    };
    let name = format!("contact_robustness_p{degree}_{lat}");
    let case = robustness::sinusoid_case(
        degree,
        lateral,
        elements_upper,
        elements_lower,
        robustness::log_path(1.0e2, 3.5e5, 20),
        Method::TwoPhase,
    );
    let path = robustness::run_path(&case, 0.95)?;
    let last = path.last().map_or(0.0, |p| p.contact_fraction);
    let cutbacks: usize = path.iter().map(|p| p.cutbacks).sum();
    let iterations: usize = path.iter().map(|p| p.iterations[0]).sum();
    let checks = vec![Check::with_error(
        &name,
        &format!(
            "contact ≥ 0.95: {} pts, {iterations} its, {cutbacks} cutb.",
            path.len()
        ),
        last,
        0.95,
        (0.95 - last).max(0.0),
        0.0,
    )];
    Ok((checks, path))
}

/// The default robustness case: p = 1, 2 and 3, PR, and p = 1 with LN, on
/// half the meshes of `tables/sinusoid_on_flat.toml` (p = 1: the master has
/// C0 corners, so the default integration is segment-based).
pub fn robustness_default() -> Result<Vec<Check>> {
    let mut v = Vec::new();
    for degree in [1, 2, 3] {
        v.extend(robustness_checks(degree, LateralCondition::Periodic, [16, 8], [14, 7])?.0);
    }
    v.extend(robustness_checks(1, LateralCondition::Linear, [16, 8], [14, 7])?.0);
    Ok(v)
}

/// Determinism: the `tcgen solve` pipeline (self-consistent two-phase) on a
/// small sinusoid sample gives bit-identical jumps and contact fractions on
/// 1 and 2 rayon threads.
pub fn determinism() -> Result<Vec<Check>> {
    let case = robustness::sinusoid_case(
        2,
        LateralCondition::Periodic,
        [16, 8],
        [14, 7],
        vec![1.0e3, 3.0e4],
        Method::TwoPhaseSelfConsistent,
    );
    let one = robustness::solve_with_threads(&case, 1)?;
    let two = robustness::solve_with_threads(&case, 2)?;
    let mut v = Vec::new();
    for (a, b) in one.iter().zip(&two) {
        for (q, x, y) in [
            ("jump (K)", a.jump, b.jump),
            (
                "contact fr.",
                a.interface.contact_fraction,
                b.interface.contact_fraction,
            ),
        ] {
            let differ = f64::from(u8::from(x.to_bits() != y.to_bits() || !x.is_finite()));
            v.push(Check::with_error(
                "contact_determinism",
                &format!("{q} at {:e} Pa, 1 vs 2 thr. (bits)", a.pressure),
                y,
                x,
                differ,
                0.0,
            ));
        }
    }
    Ok(v)
}

/// The contact verification cases.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "contact_patch_thermal_flat",
            description: "thermal patch test, flat, non-matching",
            run: thermal_patch_flat,
        },
        Case {
            name: "contact_patch_thermal_curved",
            description: "thermal patch test, NURBS arc, non-matching",
            run: thermal_patch_curved,
        },
        Case {
            name: "contact_patch_mechanical",
            description: "uniform pressure through a non-matching interface",
            run: mechanical_patch,
        },
        Case {
            name: "contact_patch_3d",
            description: "3D patch tests (Fig. 9): flat and cylindrical, non-matching",
            run: patch_3d,
        },
        Case {
            name: "contact_egg_box",
            description: "3D egg box on a flat: JGH asymptotes, Barber (small strain)",
            run: egg_box_default,
        },
        Case {
            name: "contact_hertz",
            description: "thermoelastic Hertz, p=2 coarse: a, p, flux (5.2)",
            run: hertz_default,
        },
        Case {
            name: "contact_hertz_3d",
            description: "Hertz sphere on flat (3D), p=2: a, p, spot flux",
            run: hertz_3d_default,
        },
        Case {
            name: "contact_wavy",
            description: "Westergaard, strip constriction, Barber (32 el.)",
            run: || wavy_case(&wavy_default_sample()),
        },
        Case {
            name: "contact_robustness",
            description: "Sect. 5.7 sinusoid to 95 % contact, p=2,3 (half mesh)",
            run: robustness_default,
        },
        Case {
            name: "contact_determinism",
            description: "micro-solve bit-identical on 1 and 2 threads",
            run: determinism,
        },
    ]
}
