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
//! interface layer is marked. Each volume element at a marked face element
//! is halved in every direction; class-2 admissibility grades the mesh
//! through the height.
//!
//! Dimension-generic: faces are THB patches of dimension `d − 1`, the
//! neighbours are the face elements whose parametric boxes touch.

use std::collections::BTreeSet;

use crate::contact::ContactInterface;
use crate::geometry::{Cell, Side, ThbPatch};
use crate::sample::micro::{Bodies, LOWER, UPPER};
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

/// The contact-edge marks of a solved model whose contact interface is
/// prepared at the current state (point projections up to date); `slave`
/// the index of the slave body ([`LOWER`] or [`UPPER`]).
pub fn mark_contact_edges(model: &Model, slave: usize) -> Result<Marks> {
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
    let next_level = sface
        .elements()
        .iter()
        .map(|e| e.cell.level)
        .max()
        .unwrap_or(0)
        + 1;
    let interior_level = next_level / INTERIOR_LEVEL_RATIO;
    let edges: BTreeSet<usize> = sface
        .elements()
        .iter()
        .enumerate()
        .filter(|(e, el)| {
            let inside = el.functions.iter().filter(|&&i| indicator[i] > 0.0).count();
            (inside > 0 && inside < el.functions.len())
                || (inside == 0 && penetrating.contains(e))
                || (inside == el.functions.len() && el.cell.level < interior_level)
        })
        .map(|(e, _)| e)
        .collect();
    let (slave_set, master_set) = if edges.is_empty() {
        (
            (0..sface.n_elements()).collect(),
            (0..mface.n_elements()).collect(),
        )
    } else {
        let slave_set = with_neighbours(sface, &edges);
        let seen: BTreeSet<usize> = c
            .points
            .iter()
            .zip(&c.state)
            .filter(|(p, _)| slave_set.contains(&p.element))
            .map(|(_, st)| st.master_element())
            .collect();
        (slave_set, with_neighbours(mface, &seen))
    };
    let mut marks = Marks::default();
    for (body, face, set) in [(slave, sface, slave_set), (master, mface, master_set)] {
        let patch = &model.bodies[body].patch;
        let normal = patch.param_dim() - 1;
        let side = if body == UPPER { Side::Low } else { Side::High };
        let cells = marks.of(body);
        for e in set {
            cells.push(patch.face_volume_cell(face.elements()[e].cell, normal, side));
        }
    }
    Ok(marks)
}

/// The bodies (SI units, as built for the model) with the marked cells refined
/// (same geometry; [`Bodies::resolved`] then moves the refined faces onto the
/// exact surfaces).
pub fn refine_bodies(bodies: &Bodies, marks: &Marks) -> Bodies {
    Bodies {
        lower: bodies.lower.refined(&marks.lower),
        upper: bodies.upper.refined(&marks.upper),
    }
}

/// Carries the state of `from` (displacements, temperatures, contact
/// multipliers) over to `to`, built on refinements of its bodies: the
/// fields exactly, the lumped multipliers as coefficients on the refined
/// slave face (a starting guess for Newton).
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
}
