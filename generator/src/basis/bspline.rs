//! B-spline basis functions and their derivatives (Piegl & Tiller A2.2, A2.3).

use crate::geometry::KnotVector;

/// Degrees up to this use stack scratch space in [`basis_ders_into`]; higher degrees allocate.
const STACK_DEGREE: usize = 8;
const STACK_SCRATCH: usize = (STACK_DEGREE + 1) * (STACK_DEGREE + 1) + 4 * (STACK_DEGREE + 1);

/// `ders[k][j]` = k-th derivative of `N_{span−p+j}` at `u`, `k = 0..=n`, `j = 0..=p` (A2.3).
/// Derivatives of order `k > p` are zero. `span` must be a non-empty span (`u_span < u_{span+1}`);
/// `u` may lie anywhere, the polynomial pieces of that span are evaluated (so `u` at either end
/// of the span gives the one-sided limits).
#[track_caller]
pub fn basis_ders(kv: &KnotVector, span: usize, u: f64, n: usize) -> Vec<Vec<f64>> {
    let p1 = kv.degree() + 1;
    let mut flat = vec![0.0; (n + 1) * p1];
    basis_ders_into(kv, span, u, n, &mut flat);
    flat.chunks(p1).map(<[f64]>::to_vec).collect()
}

/// [`basis_ders`] into a flat row-major buffer: `out[k * (p + 1) + j]`, `out.len() == (n + 1)(p + 1)`.
/// Allocation-free for degrees ≤ 8.
#[track_caller]
pub fn basis_ders_into(kv: &KnotVector, span: usize, u: f64, n: usize, out: &mut [f64]) {
    let p = kv.degree();
    assert_eq!(
        out.len(),
        (n + 1) * (p + 1),
        "basis_ders_into: output length must be (n + 1)(p + 1)"
    );
    let k = kv.knots();
    assert!(
        span >= p && span + 1 < k.len() - p && k[span] < k[span + 1],
        "basis_ders: span {span} is not a non-empty span of {k:?}"
    );
    let need = (p + 1) * (p + 1) + 4 * (p + 1);
    if p <= STACK_DEGREE {
        let mut scratch = [0.0; STACK_SCRATCH];
        ders_kernel(k, p, span, u, n, out, &mut scratch[..need]);
    } else {
        let mut scratch = vec![0.0; need];
        ders_kernel(k, p, span, u, n, out, &mut scratch);
    }
}

/// A2.3 on caller-provided scratch of length `(p+1)² + 4(p+1)`.
#[allow(clippy::needless_range_loop)]
fn ders_kernel(
    knots: &[f64],
    p: usize,
    span: usize,
    u: f64,
    n: usize,
    out: &mut [f64],
    scratch: &mut [f64],
) {
    let p1 = p + 1;
    let (ndu, rest) = scratch.split_at_mut(p1 * p1);
    let (left, rest) = rest.split_at_mut(p1);
    let (right, a) = rest.split_at_mut(p1);
    // ndu[j][r] at ndu[j * p1 + r]: upper triangle basis functions, lower triangle knot differences.
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j * p1 + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * p1 + j - 1] / ndu[j * p1 + r];
            ndu[r * p1 + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * p1 + j] = saved;
    }
    out.fill(0.0);
    for j in 0..=p {
        out[j] = ndu[j * p1 + p];
    }
    let nk = n.min(p);
    if nk == 0 {
        return;
    }
    // a: two rows of length p1.
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0] = 1.0;
        for k in 1..=nk {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if rk >= 0 {
                let rk = rk as usize;
                a[s2 * p1] = a[s1 * p1] / ndu[(pk + 1) * p1 + rk];
                d = a[s2 * p1] * ndu[rk * p1 + pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let rkj = (rk + j as isize) as usize;
                a[s2 * p1 + j] = (a[s1 * p1 + j] - a[s1 * p1 + j - 1]) / ndu[(pk + 1) * p1 + rkj];
                d += a[s2 * p1 + j] * ndu[rkj * p1 + pk];
            }
            if r <= pk {
                a[s2 * p1 + k] = -a[s1 * p1 + k - 1] / ndu[(pk + 1) * p1 + r];
                d += a[s2 * p1 + k] * ndu[r * p1 + pk];
            }
            out[k * p1 + r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=nk {
        for j in 0..=p {
            out[k * p1 + j] *= factor;
        }
        factor *= (p - k) as f64;
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    /// Cox–de Boor recursion, the definition, for comparison.
    fn cox_de_boor(k: &[f64], i: usize, p: usize, u: f64, span: usize) -> f64 {
        if p == 0 {
            return if i == span { 1.0 } else { 0.0 };
        }
        let mut v = 0.0;
        if k[i + p] > k[i] {
            v += (u - k[i]) / (k[i + p] - k[i]) * cox_de_boor(k, i, p - 1, u, span);
        }
        if k[i + p + 1] > k[i + 1] {
            v += (k[i + p + 1] - u) / (k[i + p + 1] - k[i + 1])
                * cox_de_boor(k, i + 1, p - 1, u, span);
        }
        v
    }

    #[test]
    fn values_match_cox_de_boor() {
        let kv = KnotVector::new(3, vec![0., 0., 0., 0., 0.3, 0.3, 0.7, 1., 1., 1., 1.]).unwrap();
        for &u in &[0.0, 0.1, 0.3, 0.45, 0.7, 0.99, 1.0] {
            let span = kv.find_span(u);
            let d = basis_ders(&kv, span, u, 4);
            for j in 0..=3 {
                let exact = cox_de_boor(kv.knots(), span - 3 + j, 3, u, span);
                assert!((d[0][j] - exact).abs() < 1e-14, "u = {u}, j = {j}");
            }
            assert!(d[4].iter().all(|&x| x == 0.0));
        }
    }

    #[test]
    fn high_degree_uses_heap_path() {
        let kv = KnotVector::open_uniform(10, 3, 0.0, 1.0);
        let d = basis_ders(&kv, kv.find_span(0.4), 0.4, 2);
        let s: f64 = d[0].iter().sum();
        assert!((s - 1.0).abs() < 1e-13);
        assert!(d[1].iter().sum::<f64>().abs() < 1e-10);
    }
}
