//! Gauss–Legendre quadrature rules.

/// An `n`-point Gauss–Legendre rule on `[-1, 1]`: exact for polynomials of degree `2n − 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussLegendre {
    /// Nodes in increasing order, symmetric about 0.
    pub points: Vec<f64>,
    /// Weights (positive, summing to 2).
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The `n`-point rule, any `n ≥ 1`. The nodes are the roots of the Legendre
    /// polynomial `P_n`, found by Newton's method from Tricomi's initial guess to machine
    /// precision; the weights are `2 / ((1 − x²) P_n'(x)²)`.
    ///
    /// Panics if `n == 0`.
    #[track_caller]
    pub fn new(n: usize) -> Self {
        assert!(
            n >= 1,
            "GaussLegendre::new: the number of points must be >= 1, got 0"
        );
        let mut points = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n.div_ceil(2) {
            // Root i counted from x = +1 downwards.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            for _ in 0..100 {
                let (p, d) = legendre_with_derivative(n, x);
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            let dp = legendre_with_derivative(n, x).1;
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            points[i] = -x;
            points[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            points[n / 2] = 0.0;
        }
        GaussLegendre { points, weights }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a rule has at least one point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Nodes and weights mapped affinely onto `[a, b]` (weights scaled by `(b − a)/2`).
    pub fn on_interval(&self, a: f64, b: f64) -> impl Iterator<Item = (f64, f64)> + '_ {
        let half = 0.5 * (b - a);
        let mid = 0.5 * (a + b);
        self.points
            .iter()
            .zip(&self.weights)
            .map(move |(&x, &w)| (mid + half * x, half * w))
    }
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre_with_derivative(n: usize, x: f64) -> (f64, f64) {
    let mut p_prev = 1.0;
    let mut p = x;
    for k in 2..=n {
        let kf = k as f64;
        let p_next = ((2.0 * kf - 1.0) * x * p - (kf - 1.0) * p_prev) / kf;
        p_prev = p;
        p = p_next;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let nf = n as f64;
    let dp = nf * (x * p - p_prev) / (x * x - 1.0);
    (p, dp)
}

/// Default number of Gauss points per direction for bulk integrals of degree-`p` NURBS: `p + 2`.
pub fn default_bulk_points(degree: usize) -> usize {
    degree + 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_sum_to_two_and_nodes_are_symmetric() {
        for n in 1..=40 {
            let g = GaussLegendre::new(n);
            let sum: f64 = g.weights.iter().sum();
            assert!((sum - 2.0).abs() < 1e-13, "n = {n}: sum {sum}");
            for i in 0..n {
                assert_eq!(g.points[i], -g.points[n - 1 - i]);
                assert!(g.weights[i] > 0.0);
            }
            assert!(g.points.windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn nodes_are_roots_of_legendre_polynomial() {
        for n in [1, 2, 5, 12, 30, 64] {
            let g = GaussLegendre::new(n);
            for &x in &g.points {
                assert!(
                    legendre_with_derivative(n, x).0.abs() < 1e-13,
                    "n = {n}, x = {x}"
                );
            }
        }
    }
}
