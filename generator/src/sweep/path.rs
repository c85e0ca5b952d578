//! The paths of a sweep: one sample, flux and contact temperature, all
//! pressures in increasing order by continuation through
//! [`crate::homogenize::path::PathSolver`]; the fluxes of one
//! sample and contact temperature share one solver ([`solve_flux_group`]).
//!
//! With `[sweep] continuation = false` every pressure is solved from zero
//! load with a fresh model instead.
//!
//! A point that fails is recorded with its reason and the path goes on; if
//! the solver's state is lost the next pressure is approached from zero load
//! (the failed state is not trusted). A panic inside the solver is caught
//! and recorded as a failure of that point.

use std::ops::Range;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use rayon::prelude::*;

use crate::homogenize::path::{LevelObserver, PathSolver, PointResult, Status};
use crate::io::table::{PointRecord, PointValues, SampleSurfaces};
use crate::sample::Case;
use crate::sample::case::Method;
use crate::surface::Surface;
use crate::surface::areal::ArealSurface;

/// A piece of one path: the records of the pressures `from..from + points.len()`.
#[derive(Clone, Debug, PartialEq)]
pub struct PathPiece {
    /// Index of the first pressure.
    pub from: usize,
    /// One record per pressure.
    pub points: Vec<PointRecord>,
    /// The sample's surface measures (`None` if the surfaces could not be built).
    pub surfaces: Option<SampleSurfaces>,
    /// Time in building models (surface fits, meshes, contact set-up) (s).
    pub setup_seconds: f64,
    /// Time in the micro-solves (s).
    pub solve_seconds: f64,
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// The table record of a solver result.
pub fn record(r: &PointResult) -> PointRecord {
    match &r.status {
        Status::Converged if r.converged && r.jump.is_finite() => {
            PointRecord::converged(PointValues {
                jump: r.jump,
                conductance: r.conductance,
                contact_fraction: r.interface.contact_fraction,
                mean_gap: r.interface.mean_gap,
                self_consistency_iterations: r.self_consistency_iterations as u32,
                newton_iterations: r.newton_iterations as u32,
                jump_error: r.jump_error,
                error_target_met: r.error_target_met,
                dofs: r.dofs.min(u32::MAX as usize) as u32,
            })
        }
        Status::Converged => PointRecord::failed(format!(
            "the solver reported convergence with a non-finite jump ({})",
            r.jump
        )),
        Status::Failed(m) => PointRecord::failed(m.clone()),
    }
}

/// RMS of a periodic surface over one period, from 4096 samples (exact for
/// trigonometric polynomials of fewer than 2048 modes).
pub fn surface_rms(s: &dyn Surface, width: f64) -> f64 {
    let n = 4096;
    rms_of_samples((0..n).map(|i| s.height(width * i as f64 / n as f64)))
}

/// RMS of a periodic areal surface over the cell, from a 512 × 512 grid
/// (exact for trigonometric polynomials of fewer than 256 modes along each
/// direction).
pub fn areal_surface_rms(s: &dyn ArealSurface, width: f64) -> f64 {
    let n = 512;
    let h = width / n as f64;
    let rows: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|j| {
            (0..n)
                .map(|i| s.height(h * i as f64, h * j as f64))
                .collect()
        })
        .collect();
    rms_of_samples(rows.into_iter().flatten())
}

/// Root mean square about the mean of equally weighted samples.
fn rms_of_samples(samples: impl Iterator<Item = f64>) -> f64 {
    let (mut n, mut sum, mut sq) = (0usize, 0.0, 0.0);
    for z in samples {
        n += 1;
        sum += z;
        sq += z * z;
    }
    let mean = sum / n as f64;
    (sq / n as f64 - mean * mean).max(0.0).sqrt()
}

/// The surface measures of a case's sample: RMS and NURBS fit errors at the
/// case's discretization, profiles in 2D and areal surfaces in 3D (`None` if
/// a surface fails to build).
pub fn sample_surfaces(case: &Case) -> Option<SampleSurfaces> {
    let w = case.sample.width;
    if case.dimension() == 3 {
        let (up, lo) = case.areal_surfaces().ok()?;
        let geo = crate::sample::micro::sample_geometry_3d(case, up.as_ref(), lo.as_ref()).ok()?;
        return Some(SampleSurfaces {
            upper_rms: areal_surface_rms(up.as_ref(), w),
            lower_rms: areal_surface_rms(lo.as_ref(), w),
            upper_fit_error: geo.fit_upper.max_error(),
            lower_fit_error: geo.fit_lower.max_error(),
        });
    }
    let (up, lo) = case.surfaces().ok()?;
    let geo = crate::sample::micro::sample_geometry(case, up.as_ref(), lo.as_ref());
    Some(SampleSurfaces {
        upper_rms: surface_rms(up.as_ref(), w),
        lower_rms: surface_rms(lo.as_ref(), w),
        upper_fit_error: geo.fit_upper.max_error(),
        lower_fit_error: geo.fit_lower.max_error(),
    })
}

/// Solves the pressures `range` of `case.load.pressures` for the case's flux
/// and contact temperature one by one with [`PathSolver::solve_pressure`], by
/// continuation (or each from zero load with a fresh model if `continuation`
/// is false); used for the coupled identifications. `on_point` sees every
/// record as it is made.
pub fn solve_path(
    case: &Case,
    range: Range<usize>,
    continuation: bool,
    on_point: &(dyn Fn(&PointRecord) + Sync),
) -> PathPiece {
    let t = Instant::now();
    let surfaces = catch_unwind(AssertUnwindSafe(|| sample_surfaces(case)))
        .ok()
        .flatten();
    let mut out = PathPiece {
        from: range.start,
        points: Vec::with_capacity(range.len()),
        surfaces,
        setup_seconds: t.elapsed().as_secs_f64(),
        solve_seconds: 0.0,
    };
    let mut solver: Option<PathSolver> = None;
    for &p in &case.load.pressures[range] {
        if solver.is_none() {
            let t = Instant::now();
            let built = catch_unwind(AssertUnwindSafe(|| PathSolver::new(case)));
            out.setup_seconds += t.elapsed().as_secs_f64();
            match built {
                Ok(Ok(s)) => solver = Some(s),
                Ok(Err(e)) => {
                    let r = PointRecord::failed(format!("set-up failed: {e}"));
                    on_point(&r);
                    out.points.push(r);
                    continue;
                }
                Err(panic) => {
                    let r = PointRecord::failed(format!(
                        "set-up failed: internal error (panic): {}",
                        panic_message(panic.as_ref())
                    ));
                    on_point(&r);
                    out.points.push(r);
                    continue;
                }
            }
        }
        let s = solver.as_mut().expect("built above");
        let t = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| s.solve_pressure(p)));
        out.solve_seconds += t.elapsed().as_secs_f64();
        let r = match result {
            Ok(Ok(r)) => record(&r),
            Ok(Err(e)) => PointRecord::failed(e.to_string()),
            Err(panic) => PointRecord::failed(format!(
                "internal error (panic): {}",
                panic_message(panic.as_ref())
            )),
        };
        if r.values.is_none() || !continuation {
            // Never continue from a failed state: the next pressure starts afresh.
            solver = None;
        }
        on_point(&r);
        out.points.push(r);
    }
    out
}

/// Solves the paths of one sample and contact temperature for several
/// fluxes (`cases[j]` differ only in `load.flux`) over the pressures `range`.
///
/// Two-phase identifications go through one [`PathSolver`] and
/// [`PathSolver::solve_pressure_fluxes`]: the mechanical phase and the first
/// thermal phase are shared by the fluxes, each flux then iterates to
/// self-consistency from that state. A flux that fails at one pressure is
/// recorded and the others go on; a failure of the shared phases fails every
/// flux at that pressure and the next pressure starts afresh from zero load.
/// A flux's results do not depend on which other fluxes share its solver, so
/// shards and thread counts give the same table. Coupled identifications
/// solve each flux on its own ([`solve_path`]). `on_level` sees every
/// adaptive level as it ends.
pub fn solve_flux_group(
    cases: &[Case],
    range: Range<usize>,
    continuation: bool,
    on_point: &(dyn Fn(&PointRecord) + Sync),
    on_level: Option<&LevelObserver>,
) -> Vec<PathPiece> {
    let Some(case) = cases.first() else {
        return Vec::new();
    };
    if matches!(
        case.homogenization.method,
        Method::Coupled | Method::Linearized
    ) {
        return cases
            .iter()
            .map(|c| solve_path(c, range.clone(), continuation, on_point))
            .collect();
    }
    let fluxes: Vec<f64> = cases.iter().map(|c| c.load.flux).collect();
    let n = fluxes.len();
    let t = Instant::now();
    let surfaces = catch_unwind(AssertUnwindSafe(|| sample_surfaces(case)))
        .ok()
        .flatten();
    let (mut setup, mut solve) = (t.elapsed().as_secs_f64(), 0.0);
    let mut points: Vec<Vec<PointRecord>> = vec![Vec::with_capacity(range.len()); n];
    let mut solver: Option<PathSolver> = None;
    for &p in &case.load.pressures[range.clone()] {
        let records: Vec<PointRecord> = 'point: {
            if solver.is_none() {
                let t = Instant::now();
                let built = catch_unwind(AssertUnwindSafe(|| PathSolver::new(case)));
                setup += t.elapsed().as_secs_f64();
                match built {
                    Ok(Ok(mut s)) => {
                        s.observe_levels(on_level.cloned());
                        solver = Some(s);
                    }
                    Ok(Err(e)) => {
                        break 'point vec![PointRecord::failed(format!("set-up failed: {e}")); n];
                    }
                    Err(panic) => {
                        break 'point vec![
                            PointRecord::failed(format!(
                                "set-up failed: internal error (panic): {}",
                                panic_message(panic.as_ref())
                            ));
                            n
                        ];
                    }
                }
            }
            let s = solver.as_mut().expect("built above");
            let t = Instant::now();
            let result = catch_unwind(AssertUnwindSafe(|| s.solve_pressure_fluxes(p, &fluxes)));
            solve += t.elapsed().as_secs_f64();
            match result {
                Ok(Ok(rs)) if rs.len() == n => rs.iter().map(record).collect(),
                Ok(Ok(rs)) => {
                    solver = None;
                    vec![
                        PointRecord::failed(format!(
                            "internal error: {} results for {n} fluxes",
                            rs.len()
                        ));
                        n
                    ]
                }
                Ok(Err(e)) => {
                    // The shared phases failed: never continue from that state.
                    solver = None;
                    vec![PointRecord::failed(e.to_string()); n]
                }
                Err(panic) => {
                    solver = None;
                    vec![
                        PointRecord::failed(format!(
                            "internal error (panic): {}",
                            panic_message(panic.as_ref())
                        ));
                        n
                    ]
                }
            }
        };
        if !continuation {
            solver = None;
        }
        for (j, r) in records.into_iter().enumerate() {
            on_point(&r);
            points[j].push(r);
        }
    }
    points
        .into_iter()
        .map(|points| PathPiece {
            from: range.start,
            points,
            surfaces,
            setup_seconds: setup / n as f64,
            solve_seconds: solve / n as f64,
        })
        .collect()
}
