//! h- and p-refinement: knot insertion (A5.4 RefineKnotVectCurve) and degree elevation
//! (A5.9 DegreeElevateCurve), applied row by row along one direction on homogeneous
//! (weighted) control points `Pw = (w x, w y, w z, w)`. The geometry is unchanged.
#![allow(clippy::needless_range_loop)]

use super::knots::KnotVector;
use super::nurbs::NurbsPatch;

/// A homogeneous control point `(w x, w y, w z, w)`.
type Hom = [f64; 4];

fn lerp(alpha: f64, a: Hom, b: Hom) -> Hom {
    // alpha * a + (1 - alpha) * b
    let mut out = [0.0; 4];
    for i in 0..4 {
        out[i] = alpha * a[i] + (1.0 - alpha) * b[i];
    }
    out
}

impl NurbsPatch {
    /// Inserts the knots `new_knots` (any order, repetitions allowed) in direction `dir`.
    /// A value within the knot tolerance of an existing knot is snapped onto it.
    ///
    /// Panics if a knot lies outside the open parameter range or an interior multiplicity would
    /// exceed the degree.
    #[track_caller]
    pub fn insert_knots(&self, dir: usize, new_knots: &[f64]) -> NurbsPatch {
        assert!(
            dir < self.param_dim(),
            "insert_knots: direction {dir} out of range"
        );
        if new_knots.is_empty() {
            return self.clone();
        }
        let kv = &self.knots()[dir];
        let tol = kv.tolerance();
        let breaks = kv.breaks();
        let mut x: Vec<f64> = new_knots
            .iter()
            .map(|&u| {
                assert!(
                    u.is_finite() && u > kv.first() + tol && u < kv.last() - tol,
                    "insert_knots: knot {u} outside the open parameter range ({}, {})",
                    kv.first(),
                    kv.last()
                );
                breaks
                    .iter()
                    .copied()
                    .find(|b| (b - u).abs() <= tol)
                    .unwrap_or(u)
            })
            .collect();
        x.sort_by(f64::total_cmp);
        let mut i = 0;
        while i < x.len() {
            let count = x.iter().filter(|&&v| v == x[i]).count();
            let total = count + kv.multiplicity(x[i]);
            assert!(
                total <= kv.degree(),
                "insert_knots: knot {} would get multiplicity {total} > degree {}",
                x[i],
                kv.degree()
            );
            i += count;
        }
        self.map_rows(dir, |pw| refine_knot_vector_curve(kv, pw, &x))
    }

    /// Elevates the degree in direction `dir` by `t` (A5.9); every distinct knot's multiplicity
    /// grows by `t`, so the continuity is unchanged.
    #[track_caller]
    pub fn elevate_degree(&self, dir: usize, t: usize) -> NurbsPatch {
        assert!(
            dir < self.param_dim(),
            "elevate_degree: direction {dir} out of range"
        );
        if t == 0 {
            return self.clone();
        }
        let kv = &self.knots()[dir];
        self.map_rows(dir, |pw| degree_elevate_curve(kv, pw, t))
    }

    /// Splits every element in direction `dir` into `subdivisions` equal parts (`1` = no change).
    #[track_caller]
    pub fn refine_uniform(&self, dir: usize, subdivisions: usize) -> NurbsPatch {
        assert!(
            dir < self.param_dim(),
            "refine_uniform: direction {dir} out of range"
        );
        assert!(
            subdivisions >= 1,
            "refine_uniform: subdivisions must be >= 1, got 0"
        );
        let breaks = self.knots()[dir].breaks();
        let mut x = Vec::with_capacity((breaks.len() - 1) * (subdivisions - 1));
        for w in breaks.windows(2) {
            for s in 1..subdivisions {
                x.push(w[0] + (w[1] - w[0]) * s as f64 / subdivisions as f64);
            }
        }
        self.insert_knots(dir, &x)
    }

    /// Applies a curve algorithm to every row of homogeneous control points along `dir`.
    fn map_rows(&self, dir: usize, f: impl Fn(&[Hom]) -> (KnotVector, Vec<Hom>)) -> NurbsPatch {
        let n = self.n_per_dir();
        let cp = self.control_points();
        let w = self.weights();
        let n_rows = self.n_control_points() / n[dir];
        // Stride of direction dir and of the block above it.
        let stride: usize = n[..dir].iter().product();
        let row_start = |r: usize| (r % stride) + (r / stride) * stride * n[dir];
        let mut new_kv = None;
        let mut new_n = 0;
        let mut rows = Vec::with_capacity(n_rows);
        for r in 0..n_rows {
            let start = row_start(r);
            let pw: Vec<Hom> = (0..n[dir])
                .map(|i| {
                    let a = start + i * stride;
                    [w[a] * cp[a][0], w[a] * cp[a][1], w[a] * cp[a][2], w[a]]
                })
                .collect();
            let (kv, q) = f(&pw);
            new_n = q.len();
            new_kv.get_or_insert(kv);
            rows.push(q);
        }
        let total = n_rows * new_n;
        let mut points = vec![[0.0; 3]; total];
        let mut weights = vec![0.0; total];
        for (r, q) in rows.iter().enumerate() {
            let start = (r % stride) + (r / stride) * stride * new_n;
            for (i, h) in q.iter().enumerate() {
                let a = start + i * stride;
                weights[a] = h[3];
                points[a] = [h[0] / h[3], h[1] / h[3], h[2] / h[3]];
            }
        }
        let mut knots = self.knots().to_vec();
        knots[dir] = new_kv.expect("a patch has at least one row");
        NurbsPatch::from_parts(knots, points, weights)
    }
}

/// A5.4: inserts the sorted knots `x` into the curve `(kv, pw)`.
fn refine_knot_vector_curve(kv: &KnotVector, pw: &[Hom], x: &[f64]) -> (KnotVector, Vec<Hom>) {
    let p = kv.degree();
    let u = kv.knots();
    let n = pw.len() - 1;
    let m = n + p + 1;
    let r = x.len() - 1;
    let a = kv.find_span(x[0]);
    let b = kv.find_span(x[r]) + 1;
    let mut qw = vec![[0.0; 4]; n + r + 2];
    let mut ubar = vec![0.0; m + r + 2];
    qw[..=a - p].copy_from_slice(&pw[..=a - p]);
    for j in b - 1..=n {
        qw[j + r + 1] = pw[j];
    }
    ubar[..=a].copy_from_slice(&u[..=a]);
    for j in b + p..=m {
        ubar[j + r + 1] = u[j];
    }
    let mut i = b + p - 1;
    let mut k = b + p + r;
    for j in (0..=r).rev() {
        while x[j] <= u[i] && i > a {
            qw[k - p - 1] = pw[i - p - 1];
            ubar[k] = u[i];
            k -= 1;
            i -= 1;
        }
        qw[k - p - 1] = qw[k - p];
        for l in 1..=p {
            let ind = k - p + l;
            let alfa = ubar[k + l] - x[j];
            if alfa == 0.0 {
                qw[ind - 1] = qw[ind];
            } else {
                let alfa = alfa / (ubar[k + l] - u[i + l - p]);
                qw[ind - 1] = lerp(alfa, qw[ind - 1], qw[ind]);
            }
        }
        ubar[k] = x[j];
        k -= 1;
    }
    let kv = KnotVector::new(p, ubar).expect("knot insertion keeps the knot vector valid");
    (kv, qw)
}

fn binomial(n: usize, k: usize) -> f64 {
    let mut b = 1.0;
    for i in 0..k {
        b = b * (n - i) as f64 / (i + 1) as f64;
    }
    b
}

/// A5.9: elevates the curve `(kv, pw)` by `t` degrees (Bézier decomposition, elevation of each
/// segment, removal of the unnecessary knots, all in one pass).
#[allow(clippy::explicit_counter_loop)]
fn degree_elevate_curve(kv: &KnotVector, pw: &[Hom], t: usize) -> (KnotVector, Vec<Hom>) {
    let p = kv.degree();
    let u = kv.knots();
    let n = pw.len() - 1;
    let m = n + p + 1;
    let ph = p + t;
    let ph2 = ph / 2;
    let distinct_interior = kv.breaks().len() - 2;
    let new_len_knots = u.len() + t * (distinct_interior + 2);
    let mut uh = vec![0.0; new_len_knots];
    let mut qw = vec![[0.0; 4]; new_len_knots - ph - 1];
    // Bézier degree elevation coefficients.
    let mut bezalfs = vec![vec![0.0; p + 1]; ph + 1];
    bezalfs[0][0] = 1.0;
    bezalfs[ph][p] = 1.0;
    for i in 1..=ph2 {
        let inv = 1.0 / binomial(ph, i);
        for j in i.saturating_sub(t)..=p.min(i) {
            bezalfs[i][j] = inv * binomial(p, j) * binomial(t, i - j);
        }
    }
    for i in ph2 + 1..ph {
        for j in i.saturating_sub(t)..=p.min(i) {
            bezalfs[i][j] = bezalfs[ph - i][p - j];
        }
    }
    let mut bpts = vec![[0.0; 4]; p + 1];
    let mut ebpts = vec![[0.0; 4]; ph + 1];
    let mut next_bpts = vec![[0.0; 4]; p.saturating_sub(1)];
    let mut alfs = vec![0.0; p.saturating_sub(1)];
    let mut mh = ph;
    let mut kind = ph + 1;
    let mut r: isize = -1;
    let mut a = p;
    let mut b = p + 1;
    let mut cind = 1;
    let mut ua = u[0];
    qw[0] = pw[0];
    for i in 0..=ph {
        uh[i] = ua;
    }
    bpts.copy_from_slice(&pw[..=p]);
    while b < m {
        let i0 = b;
        while b < m && u[b] == u[b + 1] {
            b += 1;
        }
        let mul = b - i0 + 1;
        mh += mul + t;
        let ub = u[b];
        let oldr = r;
        r = p as isize - mul as isize;
        // Insert knot u(b) r times to get the Bézier segment.
        let lbz = if oldr > 0 {
            ((oldr + 2) / 2) as usize
        } else {
            1
        };
        let rbz = if r > 0 {
            ph - ((r + 1) / 2) as usize
        } else {
            ph
        };
        if r > 0 {
            let numer = ub - ua;
            for k in (mul + 1..=p).rev() {
                alfs[k - mul - 1] = numer / (u[a + k] - ua);
            }
            for j in 1..=r as usize {
                let save = r as usize - j;
                let s = mul + j;
                for k in (s..=p).rev() {
                    bpts[k] = lerp(alfs[k - s], bpts[k], bpts[k - 1]);
                }
                next_bpts[save] = bpts[p];
            }
        }
        // Degree-elevate the Bézier segment.
        for i in lbz..=ph {
            let mut e = [0.0; 4];
            for j in i.saturating_sub(t)..=p.min(i) {
                for c in 0..4 {
                    e[c] += bezalfs[i][j] * bpts[j][c];
                }
            }
            ebpts[i] = e;
        }
        if oldr > 1 {
            // Remove knot u = U[a] oldr times.
            let oldr = oldr as usize;
            let mut first = kind - 2;
            let mut last = kind;
            let den = ub - ua;
            let bet = (ub - uh[kind - 1]) / den;
            for tr in 1..oldr {
                let mut i = first;
                let mut j = last;
                let mut kj = j - kind + 1;
                while j - i > tr {
                    if i < cind {
                        let alf = (ub - uh[i]) / (ua - uh[i]);
                        qw[i] = lerp(alf, qw[i], qw[i - 1]);
                    }
                    if j >= lbz {
                        if j - tr <= kind - ph + oldr {
                            let gam = (ub - uh[j - tr]) / den;
                            ebpts[kj] = lerp(gam, ebpts[kj], ebpts[kj + 1]);
                        } else {
                            ebpts[kj] = lerp(bet, ebpts[kj], ebpts[kj + 1]);
                        }
                    }
                    i += 1;
                    j -= 1;
                    kj -= 1;
                }
                first -= 1;
                last += 1;
            }
        }
        if a != p {
            // Load the knot ua.
            for _ in 0..ph - oldr.max(0) as usize {
                uh[kind] = ua;
                kind += 1;
            }
        }
        for j in lbz..=rbz {
            qw[cind] = ebpts[j];
            cind += 1;
        }
        if b < m {
            // Set up for the next pass.
            let r = r as usize;
            bpts[..r].copy_from_slice(&next_bpts[..r]);
            for j in r..=p {
                bpts[j] = pw[b - p + j];
            }
            a = b;
            b += 1;
            ua = ub;
        } else {
            for i in 0..=ph {
                uh[kind + i] = ub;
            }
        }
    }
    let nh = mh - ph - 1;
    debug_assert_eq!(nh + 1, qw.len());
    debug_assert_eq!(cind, qw.len());
    let kv = KnotVector::new(ph, uh).expect("degree elevation keeps the knot vector valid");
    (kv, qw)
}
