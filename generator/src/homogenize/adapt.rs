//! Adaptive local refinement at the contact interface (issue 11): mark the
//! elements at the contact edges, refine them (truncated hierarchical
//! B-splines, [`ThbPatch::refined`]), and carry the solved state over to the
//! refined bodies exactly (nested spaces, [`ThbPatch::prolongate`]).
//!
//! **Marking (contact-edge indicator).** The jump is limited by the
//! constriction of the heat flow through the contact spots, whose flux is
//! singular at the spot edges (`~ d^(−1/2)`, Hertz/Westergaard), and by the
//! position of the edges themselves (the contact zone is located to a
//! fraction of an element). Both errors live in the elements at the edges:
//! the slave face elements whose control points are partly in and partly out
//! of contact (the pressure indicator `λN − εN g` changes sign among them),
//! with their neighbours, and the master elements their points project onto,
//! with theirs; and the elements out of contact where the surfaces already
//! interpenetrate at an integration point (a spot narrower than the nodal
//! supports, not yet in the active set); and, every [`INTERIOR_LEVEL_RATIO`]
//! levels, the elements inside the contact, whose smooth fields converge
//! faster than the edges'. Where no edge exists (no or full contact) the whole
//! interface layer is marked. **Surface resolution** ([`surface_misfit_marks`]):
//! the elements out of contact whose gap is below the faces' height error
//! against the exact surfaces, where the fits may hide a touch (a narrow
//! asperity that the case mesh flattens). **Bulk resolution** (degree 1,
//! [`bulk_marks`]): the bulk elements that carry half of the recovered-gradient
//! error ([`crate::homogenize::recovery`]) while its estimate of the
//! approach's relative error ([`bulk_approach_error`]) exceeds the target.
//! Each volume element at a marked face element
//! is halved in every direction, with the elements below it down to about its
//! width ([`column()`]: a refined region as deep as wide on case cells wider
//! than tall); class-2 admissibility grades the mesh through the height.
//!
//! Dimension-generic: faces are THB patches of dimension `d − 1`, the
//! neighbours are the face elements whose parametric boxes touch.
//!
//! **Prolongation between levels** ([`equation_prolongation`]): the matrix
//! that carries a vector of the coarse model's equations (an increment) to
//! the refined model's, the operator of a two-level preconditioner.
//! `TCGEN_DUMP_TWOLEVEL=dir` writes it with both levels' tangents
//! ([`write_two_level_system`]; docs/3d.md, "Stop 34").

use std::collections::BTreeSet;

use crate::contact::ContactInterface;
use crate::geometry::{Cell, Side, ThbPatch};
use crate::homogenize::recovery::RecoveredErrors;
use crate::sample::micro::{Bodies, Height, LOWER, UPPER};
use crate::solve::Model;
use crate::{Error, Result};

/// Volume cells to refine in each body.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Marks {
    /// Cells of the lower body.
    pub lower: Vec<Cell>,
    /// Cells of the upper body.
    pub upper: Vec<Cell>,
}

impl Marks {
    /// Adds the cells of `other` (a cell marked twice is refined once).
    pub fn extend(&mut self, other: Marks) {
        self.lower.extend(other.lower);
        self.upper.extend(other.upper);
    }

    fn of(&mut self, body: usize) -> &mut Vec<Cell> {
        if body == LOWER {
            &mut self.lower
        } else {
            &mut self.upper
        }
    }
}

/// The contact's interior is refined to level `L / INTERIOR_LEVEL_RATIO`
/// when the edges reach level `L` (levels 3–5: 1; 6–8: 2). Inside a wide
/// contact the fields are smooth, and where their error is largest it falls
/// about 6.5-fold per halving of the elements (Westergaard at 0.9 `p*`, deep
/// adaptive from 16, 32 and 64 elements: changes 0.67 % and 0.10 %; 2.3–2.9
/// fold at 0.5–0.7 `p*`), where the edges' falls 2-fold per level (a rule
/// chosen from these measurements); refined at the edges only, the interior kept the case
/// mesh's error, which the differences between levels do not contain
/// (0.7 % from 16 elements at 0.9 `p*`, each solve estimated near 1e-4).
pub const INTERIOR_LEVEL_RATIO: usize = 3;

/// The face elements of `face` whose parametric boxes touch one of `set`
/// (the set included).
fn with_neighbours(face: &ThbPatch, set: &BTreeSet<usize>) -> BTreeSet<usize> {
    let els = face.elements();
    let dims = face.param_dim();
    let tol = 1e-12;
    let mut out = set.clone();
    for &e in set {
        let a = &els[e];
        for (f, b) in els.iter().enumerate() {
            if (0..dims).all(|d| b.lower[d] <= a.upper[d] + tol && b.upper[d] >= a.lower[d] - tol) {
                out.insert(f);
            }
        }
    }
    out
}

/// How deep a marked column reaches, as a share of its face cell's widest
/// tangential extent ([`column()`]): as deep as wide, to within a quarter.
pub const COLUMN_DEPTH_SHARE: f64 = 0.75;

/// The volume cell `c` at the face where direction `normal` is at its `side`
/// end, and the cells of its level below it (towards the body's interior)
/// until the column is [`COLUMN_DEPTH_SHARE`] of `c`'s widest tangential
/// extent deep (physical lengths, [`ThbPatch::cell_extent`]). THB halves a
/// marked cell in every direction, so marking the face cell alone refines a
/// layer as deep as the case mesh's cell is tall: on cells wider than tall the
/// levels then settle on a biased value that the differences between levels
/// do not see (the 3D benchmark's egg box on `[8, 8, 16]` cells, 0.44 μm tall
/// and 1.25 μm wide: 7.6 % above a mesh finer in every direction at
/// 1.842 kPa; docs/3d.md, "Stop 51" and "Stop 52"). On cells at least 3/4
/// as tall as wide the column is the face cell alone.
pub fn column(patch: &ThbPatch, c: Cell, normal: usize, side: Side) -> Vec<Cell> {
    let width = (0..patch.param_dim())
        .filter(|&d| d != normal)
        .map(|d| patch.cell_extent(c, d))
        .fold(0.0, f64::max);
    let n = patch.mesh().n_cells(c.level, normal);
    let mut column = vec![c];
    let mut depth = patch.cell_extent(c, normal);
    let mut below = c;
    while depth < COLUMN_DEPTH_SHARE * width {
        match side {
            Side::Low if below.index[normal] + 1 < n => below.index[normal] += 1,
            Side::High if below.index[normal] > 0 => below.index[normal] -= 1,
            _ => break,
        }
        depth += patch.cell_extent(below, normal);
        column.push(below);
    }
    column
}

/// The contact-edge marks of a solved model whose contact interface is
/// prepared at the current state (point projections up to date); `slave`
/// the index of the slave body ([`LOWER`] or [`UPPER`]).
///
/// `misfit`: slave face elements out of contact to mark as well
/// ([`surface_misfit_marks`]: where the fitted faces may hide a touch of the
/// exact surfaces). `neighbours`: the marked slave elements' neighbours and
/// those of the master elements their points see are marked too
/// (`[discretization] edge_neighbours`).
pub fn mark_contact_edges(
    model: &Model,
    slave: usize,
    misfit: &BTreeSet<usize>,
    neighbours: bool,
) -> Result<Marks> {
    let c: &ContactInterface = model
        .contact
        .as_ref()
        .ok_or_else(|| Error::Geometry("adaptivity needs a contact interface".into()))?;
    let master = if slave == UPPER { LOWER } else { UPPER };
    let (sface, mface) = (c.slave_face(), c.master_face());
    let indicator: Vec<f64> = (0..c.n_slave()).map(|i| c.indicator(i)).collect();
    // Elements out of contact in which the surfaces already interpenetrate
    // at an integration point: a spot narrower than the nodal supports,
    // which the lumped active set does not see yet.
    let penetrating: BTreeSet<usize> = c
        .points
        .iter()
        .zip(&c.state)
        .filter(|(_, st)| st.gap.value < 0.0)
        .map(|(p, _)| p.element)
        .collect();
    // The level the edge elements reach with this refinement, and the one
    // the contact's interior keeps up to ([`INTERIOR_LEVEL_RATIO`]).
    let cycle = sface.mesh().cycle();
    let next_level = sface
        .elements()
        .iter()
        .map(|e| e.cell.level)
        .max()
        .unwrap_or(0)
        .div_ceil(cycle)
        + 1;
    let interior_level = next_level / INTERIOR_LEVEL_RATIO * cycle;
    let edges: BTreeSet<usize> = sface
        .elements()
        .iter()
        .enumerate()
        .filter(|(e, el)| {
            let inside = el.functions.iter().filter(|&&i| indicator[i] > 0.0).count();
            (inside > 0 && inside < el.functions.len())
                || (inside == 0 && penetrating.contains(e))
                || (inside == el.functions.len() && el.cell.level < interior_level)
                || misfit.contains(e)
        })
        .map(|(e, _)| e)
        .collect();
    let (slave_set, master_set) = if edges.is_empty() {
        (
            (0..sface.n_elements()).collect(),
            (0..mface.n_elements()).collect(),
        )
    } else {
        let ring = |face: &ThbPatch, set: BTreeSet<usize>| {
            if neighbours {
                with_neighbours(face, &set)
            } else {
                set
            }
        };
        let slave_set = ring(sface, edges);
        let seen: BTreeSet<usize> = c
            .points
            .iter()
            .zip(&c.state)
            .filter(|(p, _)| slave_set.contains(&p.element))
            .map(|(_, st)| st.master_element())
            .collect();
        (slave_set, ring(mface, seen))
    };
    let mut marks = Marks::default();
    for (body, face, set) in [(slave, sface, slave_set), (master, mface, master_set)] {
        let patch = &model.bodies[body].patch;
        let normal = patch.param_dim() - 1;
        let side = contact_face_side(body);
        let cells = marks.of(body);
        for e in set {
            let c = patch.face_volume_cell(face.elements()[e].cell, normal, side);
            cells.extend(column(patch, c, normal, side));
        }
    }
    Ok(marks)
}

/// The bulk-resolution indicator's threshold, as a share of the target
/// error: while the bulk's estimated relative error of the approach
/// ([`bulk_approach_error`]) exceeds `BULK_TARGET_SHARE · target_error`, the
/// levels mark the bulk ([`bulk_marks`]) and a level that meets the target
/// does not end the refinement. The jump moves by less than the approach
/// (degree 1 on the egg box at 11.5 kPa: 2.4 % against 4.7 %; docs/3d.md,
/// "Stop 74"), so the whole target is left to it.
pub const BULK_TARGET_SHARE: f64 = 1.0;

/// Dörfler's parameter of [`bulk_marks`]: the marked elements carry this
/// share of `Σ η_K,u²`.
pub const BULK_MARKING_SHARE: f64 = 0.5;

/// Whether the bulk-resolution indicator applies to `model`: bodies of
/// degree 1, whose recovered gradients estimate their error
/// ([`crate::homogenize::recovery`]; effectivity 1.01–1.06 on the
/// manufactured solutions). On degree 2 the lumped projection's own error
/// at the boundaries exceeds the error it would estimate (effectivity 10.7
/// and 15.2 on 8 and 16 elements of the annulus, growing), and the
/// smoother bulk of degrees 2 and 3 has shown no such offset (their
/// approaches agree within 7e-5 on the egg box).
pub fn bulk_indicator_applies(model: &Model) -> bool {
    model
        .bodies
        .iter()
        .all(|b| b.patch.degrees().iter().all(|&p| p == 1))
}

/// The bulk's estimated relative error of the approach under the pressure
/// `pressure` (Pa): `Σ η_K,u² / (p̄ |A| δ)`, `|A|` the cell's projected
/// area (`width` m; per metre of depth in 2D), `δ` the approach (m); for a
/// linear problem under a prescribed load the work's error is the squared
/// energy error (module [`crate::homogenize::recovery`]). `None` where the
/// approach or the pressure vanishes.
pub fn bulk_approach_error(
    model: &Model,
    recovered: &RecoveredErrors,
    pressure: f64,
    width: f64,
    approach: f64,
) -> Option<f64> {
    let s = model.scales;
    let energy = recovered.mechanical_total() * s.stress * s.length.powi(model.dim as i32);
    let work = pressure * width.powi(model.dim as i32 - 1) * approach;
    (work > 0.0).then(|| energy / work)
}

/// The bulk-resolution marks (Dörfler): the fewest volume elements, largest
/// indicators first, whose `η_K,u²` add up to [`BULK_MARKING_SHARE`] of the
/// bodies' total.
pub fn bulk_marks(model: &Model, recovered: &RecoveredErrors) -> Marks {
    let mut all: Vec<(f64, usize, usize)> = recovered
        .mechanical
        .iter()
        .enumerate()
        .flat_map(|(b, eta)| eta.iter().enumerate().map(move |(e, &v)| (v, b, e)))
        .collect();
    all.sort_by(|a, b| b.0.total_cmp(&a.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let total = recovered.mechanical_total();
    let mut marks = Marks::default();
    let mut sum = 0.0;
    for (v, b, e) in all {
        if sum >= BULK_MARKING_SHARE * total {
            break;
        }
        sum += v;
        marks.of(b).push(model.bodies[b].patch.elements()[e].cell);
    }
    marks
}

/// Points per direction and face element at which [`surface_misfit_marks`]
/// compares a face with its exact surface (as the fits' own error sample).
pub const MISFIT_SAMPLES: usize = 8;

/// The slave face elements out of contact where the fitted faces may hide a
/// touch of the exact surfaces (the surface-resolution indicator): the gap
/// at the element's integration points is below the faces' height error
/// there, `min g < max |e_s| + max |e_m|`, with `e_s` the slave face's
/// error on the element and `e_m` the master's on the elements its points
/// see (each sampled at [`MISFIT_SAMPLES`] points per direction). A refined
/// level resolves its faces on the exact surfaces
/// ([`crate::sample::micro::Bodies::resolved`]), but only where it refines:
/// an asperity narrower than the case mesh, which its fit flattens, would
/// otherwise stay out of contact on every level, its contact spot missed
/// and the differences between levels blind to it. `heights` are the exact
/// surfaces `(f1, f2)` (m), the upper face at `f1 + g0`; `bound` (m) a bound
/// on the faces' error (the case fits', with a margin): elements whose gap
/// exceeds it are not sampled. The model's contact is prepared at its
/// solved state.
pub fn surface_misfit_marks(
    model: &Model,
    slave: usize,
    heights: &(Height, Height),
    g0: f64,
    bound: f64,
) -> Result<BTreeSet<usize>> {
    let c: &ContactInterface = model
        .contact
        .as_ref()
        .ok_or_else(|| Error::Geometry("adaptivity needs a contact interface".into()))?;
    let master = if slave == UPPER { LOWER } else { UPPER };
    let l = model.scales.length;
    let vertical = model.dim - 1;
    let target = |body: usize, x: &[f64; 3]| {
        let y = if model.dim == 3 { x[1] } else { 0.0 };
        if body == UPPER {
            (heights.0)(x[0], y) + g0
        } else {
            (heights.1)(x[0], y)
        }
    };
    // The largest height error of a face element (m), on a grid of samples.
    let misfit = |face: &ThbPatch, body: usize, e: usize| -> f64 {
        let el = &face.elements()[e];
        let dims = face.param_dim();
        let n = MISFIT_SAMPLES;
        let count = n.pow(dims as u32);
        (0..count)
            .map(|k| {
                let mut xi = [0.0; 2];
                let mut rest = k;
                for (d, v) in xi.iter_mut().enumerate().take(dims) {
                    let t = ((rest % n) as f64 + 0.5) / n as f64;
                    rest /= n;
                    *v = el.lower[d] + t * (el.upper[d] - el.lower[d]);
                }
                let x = face.point(&xi[..dims]).map(|v| v * l);
                (target(body, &x) - x[vertical]).abs()
            })
            .fold(0.0, f64::max)
    };
    let (sface, mface) = (c.slave_face(), c.master_face());
    let indicator: Vec<f64> = (0..c.n_slave()).map(|i| c.indicator(i)).collect();
    // Per slave element out of contact: its smallest gap (m) and the master
    // elements its points see.
    let mut near: std::collections::BTreeMap<usize, (f64, BTreeSet<usize>)> = Default::default();
    for (p, st) in c.points.iter().zip(&c.state) {
        let g = st.gap.value * l;
        if g >= bound {
            continue;
        }
        let entry = near
            .entry(p.element)
            .or_insert((f64::INFINITY, BTreeSet::new()));
        entry.0 = entry.0.min(g);
        entry.1.insert(st.master_element());
    }
    let candidates: Vec<(usize, f64, BTreeSet<usize>)> = near
        .into_iter()
        .filter(|(e, (g, _))| {
            *g > 0.0
                && sface.elements()[*e]
                    .functions
                    .iter()
                    .all(|&i| indicator[i] <= 0.0)
        })
        .map(|(e, (g, seen))| (e, g, seen))
        .collect();
    use rayon::prelude::*;
    let seen: BTreeSet<usize> = candidates
        .iter()
        .flat_map(|(_, _, s)| s.iter().copied())
        .collect();
    let master_misfit: std::collections::BTreeMap<usize, f64> = seen
        .into_par_iter()
        .map(|m| (m, misfit(mface, master, m)))
        .collect();
    Ok(candidates
        .into_par_iter()
        .filter(|(e, g, seen)| {
            let em = seen.iter().map(|m| master_misfit[m]).fold(0.0, f64::max);
            *g < misfit(sface, slave, *e) + em
        })
        .map(|(e, _, _)| e)
        .collect())
}

/// The end of the height direction at which body `body` ([`LOWER`] or
/// [`UPPER`]) meets the contact interface: the upper body's low end, the
/// lower body's high end.
pub fn contact_face_side(body: usize) -> Side {
    if body == UPPER { Side::Low } else { Side::High }
}

/// A refined body's elements by cell level: per level, the elements and
/// those of them below the level's first two cell layers from the contact
/// face (the face where direction `normal` is at its `side` end). A marked
/// face cell's children fill the first two layers of the next level; the
/// elements deeper down are there for the mesh's admissibility (class 2:
/// the grading through the height) or for a marked column.
/// `TCGEN_ADAPT_TRACE` prints it per adaptive level (docs/3d.md, "Stop 99": on the 3D
/// benchmark's fifth level at 6.25 kPa 42 % of the elements are below the
/// first two layers of their level).
pub fn level_census(patch: &ThbPatch, normal: usize, side: Side) -> Vec<[usize; 2]> {
    let mut census: Vec<[usize; 2]> = Vec::new();
    for el in patch.elements() {
        let level = el.cell.level;
        if census.len() <= level {
            census.resize(level + 1, [0, 0]);
        }
        let n = patch.mesh().n_cells(level, normal) as usize;
        let i = el.cell.index[normal] as usize;
        let depth = match side {
            Side::Low => i,
            Side::High => n - 1 - i,
        };
        census[level][0] += 1;
        census[level][1] += usize::from(depth >= 2);
    }
    census
}

/// The bodies (SI units, as built for the model) with the marked cells refined
/// (same geometry; [`Bodies::resolved`] then moves the refined faces onto the
/// exact surfaces). The two bodies at once: each one's hierarchical basis and
/// prolongation are built in one thread (the 3D benchmark's 72 kPa point:
/// level 4's refinement 2.4 → 1.7 s, level 3's 1.1 → 0.5 s; docs/3d.md,
/// "Stop 56").
pub fn refine_bodies(bodies: &Bodies, marks: &Marks) -> Bodies {
    let (lower, upper) = rayon::join(
        || bodies.lower.refined(&marks.lower),
        || bodies.upper.refined(&marks.upper),
    );
    Bodies { lower, upper }
}

/// Carries the state of `from` (displacements, temperatures, contact
/// multipliers) over to `to`, built on refinements of its bodies: the
/// fields exactly, the lumped multipliers as coefficients on the refined
/// slave face (a starting guess for Newton). The prescribed components
/// then take their values exactly: the prolongation leaves round-off on
/// them (5.6e-22 on a held zero in 3D), which made a re-solve at the same
/// loads a varying load, cut back on failure to the same failure.
pub fn transfer_state(from: &Model, to: &mut Model) {
    let nf = from.dim + 1;
    for (old, new) in from.bodies.iter().zip(&to.bodies) {
        let n = old.patch.n_control_points();
        let values = &from.state[old.node_offset * nf..(old.node_offset + n) * nf];
        let fine = old.patch.prolongate(&new.patch, values, nf);
        to.state[new.node_offset * nf..new.node_offset * nf + fine.len()].copy_from_slice(&fine);
    }
    if let (Some(a), Some(b)) = (from.contact.as_ref(), to.contact.as_mut()) {
        let (old, new) = (a.slave_face(), b.slave_face().clone());
        // The periodic copies carry their node's multipliers while the field
        // is prolongated (it is continuous across the seams), and none after.
        let on_copies = |lambda: &[f64]| -> Vec<f64> {
            (0..lambda.len()).map(|i| lambda[a.copy_of(i)]).collect()
        };
        b.lambda_n = old.prolongate(&new, &on_copies(&a.lambda_n), 1);
        b.lambda_t = old.prolongate(&new, &on_copies(&a.lambda_t), 1);
        for i in 0..b.n_slave() {
            if b.is_copy(i) {
                (b.lambda_n[i], b.lambda_t[i]) = (0.0, 0.0);
            }
        }
    }
    to.hold_prescribed();
}

/// Moves the transferred state of `model`, whose bodies are those of
/// `unresolved` (their control points, SI, per body [`LOWER`], [`UPPER`]) with
/// the faces moved onto the exact surfaces ([`Bodies::resolved`]), back onto
/// the configuration that was solved: each control point's free displacement
/// components take the change of its reference position,
/// `u ← u + X_unresolved − X_resolved`. Geometry and displacements share the
/// basis, so every point is where the coarser level left it (the gaps and the
/// contact unchanged), and the resolution's change of shape is a strain from
/// the new reference instead of an overlap of the other body (which the fit
/// error at a narrow asperity can make large enough to invert an element in
/// the first increments). Prescribed components (the faces opposite the rough
/// ones, whose positions the resolution keeps) are left as they are.
pub fn keep_transferred_configuration(model: &mut Model, unresolved: &[Vec<[f64; 3]>; 2]) {
    let nf = model.dim + 1;
    let mut shifts = Vec::new();
    for k in [LOWER, UPPER] {
        let body = &model.bodies[k];
        for (i, (x0, x1)) in unresolved[k]
            .iter()
            .zip(body.patch.control_points())
            .enumerate()
        {
            for d in 0..model.dim {
                let node = body.node_offset + i;
                if model.dofs().eq(node, d).is_some() {
                    shifts.push((node * nf + d, model.scales.len(x0[d]) - x1[d]));
                }
            }
        }
    }
    for (i, du) in shifts {
        model.state[i] += du;
    }
}

/// The prolongation from the equations of `from` to those of `to` (built on
/// refinements of its bodies, both in the same phase) as `(fine, coarse,
/// value)` entries: what [`transfer_state`] does to the fields and the
/// multipliers, on equation vectors. A tied group of nodes (periodic seams,
/// platens) is one equation, read at one of its nodes; prescribed values
/// are left out (an increment vanishes there); each periodic copy's
/// multiplier is read at its node's and prolongated to none.
pub fn equation_prolongation(from: &Model, to: &Model) -> Vec<(usize, usize, f64)> {
    use std::collections::{BTreeMap, HashMap};
    let nf = from.dim + 1;
    let mut entries: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    // Each fine equation is read at the first of its nodes met.
    let mut reader: HashMap<usize, usize> = HashMap::new();
    for (old, new) in from.bodies.iter().zip(&to.bodies) {
        for (a, g, v) in old.patch.prolongation_entries(&new.patch) {
            let node = new.node_offset + a;
            for f in 0..nf {
                let (Some(fine), Some(coarse)) = (
                    to.dofs().eq(node, f),
                    from.dofs().eq(old.node_offset + g, f),
                ) else {
                    continue;
                };
                if *reader.entry(fine).or_insert(node) == node {
                    *entries.entry((fine, coarse)).or_default() += v;
                }
            }
        }
    }
    if let (Some(a), Some(b)) = (from.contact.as_ref(), to.contact.as_ref()) {
        let (coarse, fine) = (from.multiplier_equations(), to.multiplier_equations());
        for (c0, f0) in [(coarse.0, fine.0), (coarse.1, fine.1)] {
            let (Some(c0), Some(f0)) = (c0, f0) else {
                continue;
            };
            for (i, g, v) in a.slave_face().prolongation_entries(b.slave_face()) {
                if !b.is_copy(i) {
                    *entries.entry((f0 + i, c0 + a.copy_of(g))).or_default() += v;
                }
            }
        }
    }
    entries
        .into_iter()
        .filter(|&(_, v)| v != 0.0)
        .map(|((fine, coarse), v)| (fine, coarse, v))
        .collect()
}

/// Writes, for the two-level preconditioner's study (docs/3d.md, "Stop
/// 34"), the tangents of `from` and `to` in their current phase and state
/// and [`equation_prolongation`] as little-endian arrays in `dir`:
/// `L{level}_{coarse,fine}_{colptr,rowidx}.u64` (CSC pattern),
/// `_values.f64`, `_residual.f64`, `_class.u64` (the field class of each
/// equation: 0 displacement, 1 temperature, 2 λN, 3 λθ), `_positions.f64`
/// (x, y, z of each equation's node, scaled units), and
/// `L{level}_P_{rows,cols}.u64`, `_vals.f64`.
pub fn write_two_level_system(
    from: &mut Model,
    to: &mut Model,
    dir: &std::path::Path,
    level: usize,
) -> Result<()> {
    use crate::solve::NonlinearProblem;
    let put = |name: String, bytes: Vec<u8>| -> Result<()> {
        let path = dir.join(name);
        std::fs::write(&path, bytes).map_err(|e| Error::Io {
            path: path.display().to_string(),
            source: e,
        })
    };
    let indices =
        |v: &[usize]| -> Vec<u8> { v.iter().flat_map(|&x| (x as u64).to_le_bytes()).collect() };
    let reals = |v: &[f64]| -> Vec<u8> { v.iter().flat_map(|&x| x.to_le_bytes()).collect() };
    std::fs::create_dir_all(dir).map_err(|e| Error::Io {
        path: dir.display().to_string(),
        source: e,
    })?;
    for (model, name) in [(&mut *from, "coarse"), (&mut *to, "fine")] {
        model.prepare()?;
        let mut values = vec![0.0; model.pattern().row_idx().len()];
        let mut residual = vec![0.0; model.n_eq()];
        model.assemble(Some(&mut values), &mut residual)?;
        // Both triangles (a symmetric tangent's assembly stores the lower one).
        let (col_ptr, row_idx, values) = {
            let full = model.full_tangent(&values);
            let p = full.symbolic();
            (
                p.col_ptr().to_vec(),
                p.row_idx().to_vec(),
                full.val().to_vec(),
            )
        };
        put(format!("L{level}_{name}_colptr.u64"), indices(&col_ptr))?;
        put(format!("L{level}_{name}_rowidx.u64"), indices(&row_idx))?;
        put(format!("L{level}_{name}_values.f64"), reals(&values))?;
        put(format!("L{level}_{name}_residual.f64"), reals(&residual))?;
        put(
            format!("L{level}_{name}_class.u64"),
            indices(model.eq_fields()),
        )?;
        let positions: Vec<f64> = model
            .equation_positions()
            .iter()
            .flatten()
            .copied()
            .collect();
        put(format!("L{level}_{name}_positions.f64"), reals(&positions))?;
    }
    let p = equation_prolongation(from, to);
    put(
        format!("L{level}_P_rows.u64"),
        indices(&p.iter().map(|e| e.0).collect::<Vec<_>>()),
    )?;
    put(
        format!("L{level}_P_cols.u64"),
        indices(&p.iter().map(|e| e.1).collect::<Vec<_>>()),
    )?;
    put(
        format!("L{level}_P_vals.f64"),
        reals(&p.iter().map(|e| e.2).collect::<Vec<_>>()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{cuboid, rectangle};

    fn cell(level: usize, index: [u32; 3]) -> Cell {
        Cell { level, index }
    }

    #[test]
    fn the_level_census_counts_every_element_and_the_grading_below_the_face_layers() {
        // A p = 2 block of 4 × 4 × 4 cells refined twice at its top face
        // (z at its high end): the census sums to the elements, and the
        // deeper layers are counted per level.
        let mut p = cuboid([0.0; 3], [1.0; 3]);
        for d in 0..3 {
            p = p.elevate_degree(d, 1).refine_uniform(d, 4);
        }
        let thb = ThbPatch::from_nurbs(&p).refined_at_face(2, Side::High, 2);
        let census = level_census(&thb, 2, Side::High);
        let total: usize = census.iter().map(|c| c[0]).sum();
        assert_eq!(total, thb.n_elements());
        // Count by hand from the cells.
        for (level, c) in census.iter().enumerate() {
            let n = thb.mesh().n_cells(level, 2);
            let deep = thb
                .elements()
                .iter()
                .filter(|e| e.cell.level == level && e.cell.index[2] + 3 <= n)
                .count();
            assert_eq!(c[1], deep, "level {level}");
        }
        // The finest level fills the two layers under the face only. Its
        // parents' support extensions reach two cells of level 1 deeper, so
        // admissibility refines the second layer of level 0 too: level 1
        // keeps 64 of its face layer's 128 cells and the 128 below them.
        assert_eq!(census, vec![[32, 32], [192, 128], [512, 0]]);
        // The other face sees the layers the other way round.
        let low = level_census(&thb, 2, Side::Low);
        assert_eq!(low.iter().map(|c| c[0]).sum::<usize>(), total);
        assert!(low[2][1] > 0);
    }

    /// Columns reach 3/4 of the widest tangential extent, from either side,
    /// bounded by the patch, and keep their length on the next level.
    #[test]
    fn a_column_is_as_deep_as_its_face_cell_is_wide() {
        // 2D, 4 × 16 cells on the unit square: 0.25 wide, 0.0625 tall.
        let square = ThbPatch::from_nurbs(
            &rectangle(0.0, 1.0, 0.0, 1.0)
                .refine_uniform(0, 4)
                .refine_uniform(1, 16),
        );
        let low = column(&square, cell(0, [1, 0, 0]), 1, Side::Low);
        assert_eq!(low, (0..3).map(|j| cell(0, [1, j, 0])).collect::<Vec<_>>());
        let high = column(&square, cell(0, [2, 15, 0]), 1, Side::High);
        assert_eq!(
            high,
            (13..16)
                .rev()
                .map(|j| cell(0, [2, j, 0]))
                .collect::<Vec<_>>()
        );
        // On the next level the cells keep their shape, and so the column its length.
        let refined = square.refined(&[cell(0, [1, 0, 0])]);
        assert_eq!(column(&refined, cell(1, [2, 0, 0]), 1, Side::Low).len(), 3);
        // Cells across the normal, 0.0625 wide and 0.25 tall: the face cell alone.
        assert_eq!(column(&square, cell(0, [0, 3, 0]), 0, Side::Low).len(), 1);
        // A thin layer: 4 × 4 cells on 1 × 0.125 need 6 cells, 4 exist.
        let thin = ThbPatch::from_nurbs(
            &rectangle(0.0, 1.0, 0.0, 0.125)
                .refine_uniform(0, 4)
                .refine_uniform(1, 4),
        );
        assert_eq!(column(&thin, cell(0, [3, 0, 0]), 1, Side::Low).len(), 4);
        // 3D: 2 × 4 × 16 cells on the unit cube; the widest extent (0.5) sets
        // the depth, 0.375 / 0.0625 = 6 cells.
        let cube = ThbPatch::from_nurbs(
            &cuboid([0.0; 3], [1.0; 3])
                .refine_uniform(0, 2)
                .refine_uniform(1, 4)
                .refine_uniform(2, 16),
        );
        let top = column(&cube, cell(0, [1, 2, 15]), 2, Side::High);
        assert_eq!(
            top,
            (10..16)
                .rev()
                .map(|k| cell(0, [1, 2, k]))
                .collect::<Vec<_>>()
        );
        // Cubic cells: the face cell alone.
        let cubes = ThbPatch::from_nurbs(
            &cuboid([0.0; 3], [1.0; 3])
                .refine_uniform(0, 4)
                .refine_uniform(1, 4)
                .refine_uniform(2, 4),
        );
        assert_eq!(column(&cubes, cell(0, [0, 0, 0]), 2, Side::Low).len(), 1);
    }
}
