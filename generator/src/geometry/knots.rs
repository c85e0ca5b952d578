//! Open knot vectors (Piegl & Tiller, Sect. 2.2).

use crate::{Error, Result};

/// An open (clamped) knot vector `U = {u_0, ..., u_m}` of degree `p`: both ends repeated
/// exactly `p + 1` times, non-decreasing, interior multiplicities at most `p`, so every
/// B-spline basis function is at least `C^0`.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
}

/// Relative tolerance under which two knot values count as equal in
/// [`KnotVector::multiplicity`] and in knot insertion.
pub const KNOT_TOLERANCE: f64 = 1e-12;

impl KnotVector {
    /// Validates and wraps `knots`: degree ≥ 1, at least `2(p + 1)` finite, non-decreasing
    /// values, `first < last`, both ends of multiplicity exactly `p + 1` and interior
    /// multiplicities ≤ `p`. Returns [`Error::Geometry`] naming the broken condition.
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self> {
        let p = degree;
        let fail = |what: String| {
            Err(Error::Geometry(format!(
                "knot vector {knots:?} of degree {p}: {what}"
            )))
        };
        if p == 0 {
            return fail("the degree must be >= 1".into());
        }
        if knots.len() < 2 * (p + 1) {
            return fail(format!(
                "needs at least 2(p + 1) = {} knots, got {}",
                2 * (p + 1),
                knots.len()
            ));
        }
        if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
            return fail(format!("knot {i} is not finite"));
        }
        if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
            return fail(format!(
                "knots must be non-decreasing, but u_{} > u_{}",
                i,
                i + 1
            ));
        }
        let m = knots.len() - 1;
        let (first, last) = (knots[0], knots[m]);
        if first >= last {
            return fail("the parameter range is empty (first knot == last knot)".into());
        }
        if knots[p] != first || knots[m - p] != last {
            return fail(format!(
                "not open: the end knots must be repeated p + 1 = {} times",
                p + 1
            ));
        }
        if knots[p + 1] == first || knots[m - p - 1] == last {
            return fail(format!(
                "the end knots must be repeated exactly p + 1 = {} times, not more",
                p + 1
            ));
        }
        let mut i = p + 1;
        while i < m - p {
            let mut j = i;
            while knots[j + 1] == knots[i] {
                j += 1;
            }
            let mult = j - i + 1;
            if mult > p {
                return fail(format!(
                    "interior knot {} has multiplicity {mult} > p = {p} (the basis would be discontinuous)",
                    knots[i]
                ));
            }
            i = j + 1;
        }
        Ok(KnotVector { degree, knots })
    }

    /// The open uniform knot vector of `n_elements` equal elements on `[a, b]`.
    ///
    /// Panics on `degree == 0`, `n_elements == 0` or `b <= a`.
    #[track_caller]
    pub fn open_uniform(degree: usize, n_elements: usize, a: f64, b: f64) -> Self {
        assert!(
            degree >= 1,
            "KnotVector::open_uniform: degree must be >= 1, got 0"
        );
        assert!(
            n_elements >= 1,
            "KnotVector::open_uniform: n_elements must be >= 1, got 0"
        );
        assert!(
            a.is_finite() && b.is_finite() && b > a,
            "KnotVector::open_uniform: need finite a < b, got [{a}, {b}]"
        );
        let mut knots = Vec::with_capacity(2 * (degree + 1) + n_elements - 1);
        knots.extend(std::iter::repeat_n(a, degree + 1));
        knots.extend((1..n_elements).map(|i| a + (b - a) * i as f64 / n_elements as f64));
        knots.extend(std::iter::repeat_n(b, degree + 1));
        KnotVector { degree, knots }
    }

    /// The polynomial degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot values `u_0 ≤ ... ≤ u_m`.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Number of basis functions `n + 1 = m − p`.
    pub fn n_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The first knot (start of the parameter range).
    pub fn first(&self) -> f64 {
        self.knots[0]
    }

    /// The last knot (end of the parameter range).
    pub fn last(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// Knot span index `i` with `u_i ≤ u < u_{i+1}` (A2.1), `p ≤ i ≤ n`. `u` is clamped into
    /// `[first, last]`; `u == last` gives the last non-empty span.
    ///
    /// Panics if `u` is NaN.
    #[track_caller]
    pub fn find_span(&self, u: f64) -> usize {
        assert!(!u.is_nan(), "KnotVector::find_span: u is NaN");
        let p = self.degree;
        let n = self.n_basis() - 1;
        if u >= self.knots[n + 1] {
            return n;
        }
        if u <= self.knots[p] {
            return p;
        }
        // Last knot <= u; lies in [p, n] because knots[p] < u < knots[n + 1].
        self.knots.partition_point(|&k| k <= u) - 1
    }

    /// The non-empty spans `i` (`u_i < u_{i+1}`), increasing: one per element.
    pub fn element_spans(&self) -> Vec<usize> {
        (self.degree..self.n_basis())
            .filter(|&i| self.knots[i] < self.knots[i + 1])
            .collect()
    }

    /// Number of elements (non-empty knot spans).
    pub fn n_elements(&self) -> usize {
        (self.degree..self.n_basis())
            .filter(|&i| self.knots[i] < self.knots[i + 1])
            .count()
    }

    /// The distinct knot values (element boundaries), increasing.
    pub fn breaks(&self) -> Vec<f64> {
        let mut b: Vec<f64> = Vec::with_capacity(self.knots.len());
        for &k in &self.knots {
            if b.last() != Some(&k) {
                b.push(k);
            }
        }
        b
    }

    /// Greville abscissae `ū_i = (u_{i+1} + ... + u_{i+p}) / p`, one per basis function.
    /// They satisfy `Σ_i ū_i N_i(u) = u` (linear reproduction).
    pub fn greville(&self) -> Vec<f64> {
        let p = self.degree;
        (0..self.n_basis())
            .map(|i| self.knots[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    }

    /// How many knots equal `u` (within [`KNOT_TOLERANCE`] times the parameter range).
    pub fn multiplicity(&self, u: f64) -> usize {
        let tol = self.tolerance();
        self.knots.iter().filter(|&&k| (k - u).abs() <= tol).count()
    }

    /// Absolute tolerance for knot equality: [`KNOT_TOLERANCE`] × (last − first).
    pub fn tolerance(&self) -> f64 {
        KNOT_TOLERANCE * (self.last() - self.first())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_rejects_ill_formed_knot_vectors() {
        assert!(KnotVector::new(2, vec![0., 0., 0., 1., 1., 1.]).is_ok());
        assert!(KnotVector::new(0, vec![0., 1.]).is_err());
        assert!(KnotVector::new(2, vec![0., 0., 1., 1., 1.]).is_err()); // too short
        assert!(KnotVector::new(1, vec![0., 0., 0.5, 0.4, 1., 1.]).is_err()); // decreasing
        assert!(KnotVector::new(1, vec![0., 0., f64::NAN, 1., 1.]).is_err());
        assert!(KnotVector::new(1, vec![0., 0.5, 1., 1.]).is_err()); // not open
        assert!(KnotVector::new(1, vec![0., 0., 0., 1., 1.]).is_err()); // end multiplicity p + 2
        assert!(KnotVector::new(2, vec![0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1.]).is_err()); // C^-1
        assert!(KnotVector::new(2, vec![0., 0., 0., 0.5, 0.5, 1., 1., 1.]).is_ok());
        assert!(KnotVector::new(1, vec![1., 1., 1., 1.]).is_err()); // empty range
        let err = KnotVector::new(2, vec![0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1.]).unwrap_err();
        assert!(err.to_string().contains("multiplicity 3"), "{err}");
    }

    #[test]
    fn find_span_brackets_u() {
        let kv = KnotVector::new(2, vec![0., 0., 0., 0.25, 0.5, 0.5, 1., 1., 1.]).unwrap();
        assert_eq!(kv.n_basis(), 6);
        assert_eq!(kv.find_span(-1.0), 2);
        assert_eq!(kv.find_span(0.0), 2);
        assert_eq!(kv.find_span(0.1), 2);
        assert_eq!(kv.find_span(0.25), 3);
        assert_eq!(kv.find_span(0.5), 5);
        assert_eq!(kv.find_span(0.7), 5);
        assert_eq!(kv.find_span(1.0), 5);
        assert_eq!(kv.find_span(2.0), 5);
        assert_eq!(kv.element_spans(), vec![2, 3, 5]);
        assert_eq!(kv.n_elements(), 3);
        assert_eq!(kv.multiplicity(0.5), 2);
        assert_eq!(kv.multiplicity(0.0), 3);
        assert_eq!(kv.multiplicity(0.3), 0);
        assert_eq!(kv.breaks(), vec![0., 0.25, 0.5, 1.]);
    }

    #[test]
    fn open_uniform_and_greville() {
        let kv = KnotVector::open_uniform(3, 4, -1.0, 1.0);
        assert_eq!(kv.n_basis(), 7);
        assert_eq!(kv.n_elements(), 4);
        assert_eq!(KnotVector::new(3, kv.knots().to_vec()).unwrap(), kv);
        let g = kv.greville();
        assert_eq!(g.len(), 7);
        assert_eq!(g[0], -1.0);
        assert_eq!(g[6], 1.0);
        assert!(g.windows(2).all(|w| w[0] < w[1]));
    }
}
