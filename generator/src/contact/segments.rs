//! Segment-based integration of the mortar integrals (spec §6, the exact
//! alternative to element-based integration): every slave element is split
//! where the projection of its points passes from one master piece to the
//! next (an element of the master, a corner of it, a periodic image), and
//! each segment gets its own Gauss rule.
//!
//! Within a segment the gap and the jump are smooth, so the integrals (4.8)
//! are exact to the Gauss rule's order. The weighted gaps are then C1 in the
//! unknowns even over a master with C0 corners (degree 1), where pointwise
//! gaps at fixed slave points have kinks and Newton would cycle; and a flat
//! non-matching interface passes the patch test to round-off on any mesh.
//!
//! The breakpoints follow the configuration; their motion is not
//! differentiated. First derivatives of the weighted gaps are exact anyway
//! (the integrand is continuous across a breakpoint); the second derivatives
//! miss the jump of the integrand's gradient times the breakpoint motion,
//! which vanishes for a smooth master.

use std::sync::Arc;

use crate::Result;
use crate::basis::{RationalBasis, TensorBasis};
use crate::contact::mortar::SlavePoint;
use crate::geometry::ThbPatch;
use crate::quadrature::GaussLegendre;

/// Which master piece a slave point projects onto: `(element, periodic image, corner)`.
pub type Piece = (usize, i64, bool);

/// A point where the projection passes from one master piece to another
/// inside a slave element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Breakpoint {
    /// Slave face element.
    pub element: usize,
    /// Slave face parameter.
    pub xi: f64,
    /// The pieces before and after it.
    pub pieces: (Piece, Piece),
}

/// Relative width (in the slave parameter) below which a breakpoint is located.
const BREAK_TOLERANCE: f64 = 1e-13;

/// The reference slave face and the rule applied to every segment.
#[derive(Clone, Debug)]
pub struct Segmenter {
    face: Arc<ThbPatch>,
    rule: GaussLegendre,
    /// Samples per element at which the pieces are first looked up.
    samples: usize,
}

impl Segmenter {
    /// Segments of `face` (the slave face curve, reference configuration,
    /// control points in the order of the interface's slave nodes) with
    /// `n_gauss` points each.
    pub fn new(face: Arc<ThbPatch>, n_gauss: usize) -> Self {
        Segmenter {
            face,
            rule: GaussLegendre::new(n_gauss),
            samples: (2 * n_gauss).max(8),
        }
    }

    /// The face curve.
    pub fn face(&self) -> &ThbPatch {
        &self.face
    }

    /// Integration points of the current configuration, and the breakpoints
    /// inside the slave elements. `current`: the face's current control
    /// points; `piece(x)` says which master piece the current point `x`
    /// projects onto.
    pub fn points(
        &self,
        current: &[[f64; 3]],
        mut piece: impl FnMut([f64; 2]) -> Result<Piece>,
    ) -> Result<(Vec<SlavePoint>, Vec<Breakpoint>)> {
        let mut out = Vec::new();
        let mut found = Vec::new();
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        for (e, el) in self.face.elements().iter().enumerate() {
            let (a, b) = (el.lower[0], el.upper[0]);
            let mut at = |xi: f64| -> Result<Piece> {
                self.face
                    .element_basis_into(e, &[xi], 0, &mut scratch, &mut basis);
                let cp = current;
                let mut x = [0.0; 2];
                for (&g, &n) in basis.indices.iter().zip(&basis.values) {
                    x[0] += n * cp[g][0];
                    x[1] += n * cp[g][1];
                }
                piece(x)
            };
            // Breakpoints: where the piece changes between samples, by bisection.
            let mut inner = Vec::new();
            let mut left = (a, at(a)?);
            for k in 1..=self.samples {
                let xi = a + (b - a) * k as f64 / self.samples as f64;
                let right = (xi, at(xi)?);
                bisect(&mut at, left, right, (b - a) * BREAK_TOLERANCE, &mut inner)?;
                left = right;
            }
            let mut breaks = vec![a];
            breaks.extend(inner.iter().map(|&(xi, _)| xi));
            breaks.push(b);
            found.extend(inner.into_iter().map(|(xi, pieces)| Breakpoint {
                element: e,
                xi,
                pieces,
            }));
            for w in breaks.windows(2) {
                if w[1] - w[0] <= (b - a) * BREAK_TOLERANCE {
                    continue;
                }
                interval_points(&self.face, e, (w[0], w[1]), &self.rule, &mut out);
            }
        }
        Ok((out, found))
    }
}

/// Appends to `out` the Gauss points of `rule` on the parameter interval
/// `(a, b)` of element `e` of the slave face curve `face` (weights with the
/// reference line Jacobian).
pub fn interval_points(
    face: &ThbPatch,
    e: usize,
    (a, b): (f64, f64),
    rule: &GaussLegendre,
    out: &mut Vec<SlavePoint>,
) {
    let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
    let cp = face.control_points();
    for (xi, wq) in rule.on_interval(a, b) {
        face.element_basis_into(e, &[xi], 1, &mut scratch, &mut basis);
        let mut t = [0.0; 2];
        for (&g, d) in basis.indices.iter().zip(&basis.d1) {
            t[0] += d[0] * cp[g][0];
            t[1] += d[0] * cp[g][1];
        }
        out.push(SlavePoint {
            element: e,
            conn: basis.indices.clone(),
            basis: basis.values.clone(),
            weight: wq * t[0].hypot(t[1]),
        });
    }
}

/// Appends to `out` the points `(ξ, w)` (parameters and parametric weights)
/// of element `e` of the slave face surface `face` (3D), their weights
/// times the reference area Jacobian `|∂x/∂ξ1 × ∂x/∂ξ2|`.
pub fn cell_points(
    face: &ThbPatch,
    e: usize,
    rule: impl IntoIterator<Item = ([f64; 2], f64)>,
    out: &mut Vec<SlavePoint>,
) {
    let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
    let cp = face.control_points();
    for (xi, wq) in rule {
        face.element_basis_into(e, &xi, 1, &mut scratch, &mut basis);
        let mut t = [nalgebra::Vector3::zeros(); 2];
        for (&g, d) in basis.indices.iter().zip(&basis.d1) {
            for (k, t) in t.iter_mut().enumerate() {
                *t += d[k] * nalgebra::Vector3::from(cp[g]);
            }
        }
        out.push(SlavePoint {
            element: e,
            conn: basis.indices.clone(),
            basis: basis.values.clone(),
            weight: wq * t[0].cross(&t[1]).norm(),
        });
    }
}

/// Appends to `breaks` every change of piece between `left` and `right`.
fn bisect(
    at: &mut impl FnMut(f64) -> Result<Piece>,
    left: (f64, Piece),
    right: (f64, Piece),
    tolerance: f64,
    breaks: &mut Vec<(f64, (Piece, Piece))>,
) -> Result<()> {
    if left.1 == right.1 {
        return Ok(());
    }
    if right.0 - left.0 <= tolerance {
        breaks.push((0.5 * (left.0 + right.0), (left.1, right.1)));
        return Ok(());
    }
    let m = 0.5 * (left.0 + right.0);
    let mid = (m, at(m)?);
    bisect(at, left, mid, tolerance, breaks)?;
    bisect(at, mid, right, tolerance, breaks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Side, ThbPatch, shapes};

    #[test]
    fn segments_split_at_the_pieces_and_integrate_the_length() {
        let face = ThbPatch::from(&shapes::rectangle(0.0, 2.0, 0.0, 1.0).face(1, Side::Low).0);
        let seg = Segmenter::new(Arc::new(face.clone()), 3);
        // Pieces of width 0.3 in x: breakpoints at 0.3, 0.6, ...
        let (pts, breaks) = seg
            .points(face.control_points(), |x| {
                Ok(((x[0] / 0.3).floor() as usize, 0, false))
            })
            .unwrap();
        assert_eq!(breaks.len(), 6);
        for (k, b) in breaks.iter().enumerate() {
            let x = face.point(&[b.xi])[0];
            assert!((x - 0.3 * (k + 1) as f64).abs() < 1e-12, "{b:?}");
            assert_eq!((b.pieces.0.0 + 1, b.pieces.1.0), (k + 1, k + 1));
        }
        let length: f64 = pts.iter().map(|p| p.weight).sum();
        assert!((length - 2.0).abs() < 1e-14);
        // ∫ x² dx over [0, 2] with a 3-point rule per segment: exact.
        let m2: f64 = pts
            .iter()
            .map(|p| {
                let xi: f64 = p
                    .conn
                    .iter()
                    .zip(&p.basis)
                    .map(|(&g, n)| n * face.control_points()[g][0])
                    .sum();
                p.weight * xi * xi
            })
            .sum();
        assert!((m2 - 8.0 / 3.0).abs() < 1e-13);
        // 7 pieces (0.3 × 6 = 1.8 < 2) → 7 segments of 3 points.
        assert_eq!(pts.len(), 21);
    }
}
