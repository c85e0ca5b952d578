#!/usr/bin/env python3
"""Two-level preconditioners for the tangent of an adaptive level (docs/3d.md, "Stop 34").

Reads what `TCGEN_DUMP_TWOLEVEL=DIR tcgen solve CASE` writes for every adaptive level L
(`homogenize::adapt::write_two_level_system`): the tangents of level L (fine) and L-1
(coarse) at the solved state of their phase (the mechanical one), and the exact
prolongation P between their equations. Solves A x = b (b random) by right-preconditioned
GMRES to a true relative residual of 1e-8 and prints the iterations of each preconditioner:

  schwarz  boxes of at most --box equations (recursive median bisection of the
           equations' positions along their longest extent), with --overlap layers of
           matrix neighbours (and each multiplier's constrained unknowns), local LU
           (restricted Schwarz);
           alone, + coarse level additively, and smooth-coarse-smooth
  vanka    node-block Gauss-Seidel (the equations of one control point) with a patch per
           active multiplier (its row's unknowns), symmetric sweep, + coarse level
  ilu      SuperLU's ILUTP (--drop, --fill) as the smoother, + coarse level
  sgs      the displacement block alone (the multipliers' rows and columns left out; it
           keeps the augmented Lagrangian's penalty stiffness of the nodes in contact):
           symmetric point Gauss-Seidel, --sweeps forward and as many backward, + the
           Galerkin coarse level of that block (docs/3d.md, "Stop 83"); with --patches W S
           the point sweeps become multiplicative sweeps over overlapping patches: the
           equations whose positions lie in cubes of side W at a stride S (each cube's
           block inverted densely)
  condensed  the whole system (docs/3d.md, "Stop 84"): the active multipliers condensed
           into the displacement block with an augmentation F times the block's scale
           (K + e B^T W^-1 B, W the lumped areas read off the rows of B), solved by a
           cycle of multiplicative sweeps over the cubes of --patches W S (displacement
           unknowns only) and, with --rows, one more patch per active multiplier: the
           unknowns of its constraint row (the patches then hold the local kernel of the
           constraint, so the cycle does not degrade as e grows); the coarse level is
           P^T (K + e B^T W^-1 B) P, or with --own level L-1's own tangent (its
           displacement part)

--modes K (with sgs) also prints, for the K lowest eigenmodes v of the displacement block,
the A-norm error of their best approximation in the coarse space (the A-orthogonal
projection P (P^T A P)^-1 P^T A v) and the height they lie at.

The coarse level is level L-1's own tangent ("re-discretized"), or with --galerkin P^T A P.
Needs numpy and scipy (not part of the test suite's environment):
  python3 -m venv /tmp/venv && /tmp/venv/bin/pip install numpy scipy
  /tmp/venv/bin/python scripts/two_level_prototype.py DIR 3 schwarz --box 3000 --overlap 1
"""
import argparse
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla


def load(directory, level):
    def read(name, dtype):
        return np.fromfile(f"{directory}/L{level}_{name}", dtype=dtype)

    def matrix(name):
        col_ptr = read(f"{name}_colptr.u64", "<u8")
        n = len(col_ptr) - 1
        values = read(f"{name}_values.f64", "<f8")
        return sp.csc_matrix((values, read(f"{name}_rowidx.u64", "<u8"), col_ptr), shape=(n, n))

    fine, coarse = matrix("fine").tocsr(), matrix("coarse").tocsc()
    p = sp.csr_matrix(
        (read("P_vals.f64", "<f8"), (read("P_rows.u64", "<u8"), read("P_cols.u64", "<u8"))),
        shape=(fine.shape[0], coarse.shape[0]),
    )
    positions = read("fine_positions.f64", "<f8").reshape(-1, 3)
    return fine, coarse, p, read("fine_class.u64", "<u8"), positions


def gmres_right(a, prec, b, tol=1e-8, maxit=200):
    """Right-preconditioned GMRES (no restart): the residual it monitors is the true one."""
    nb = np.linalg.norm(b)
    v, z, h = [b / nb], [], np.zeros((maxit + 1, maxit))
    for k in range(maxit):
        z.append(prec(v[k]))
        w = a @ z[k]
        for i in range(k + 1):
            h[i, k] = v[i] @ w
            w = w - h[i, k] * v[i]
        h[k + 1, k] = np.linalg.norm(w)
        v.append(w / h[k + 1, k])
        e1 = np.zeros(k + 2)
        e1[0] = nb
        y, *_ = np.linalg.lstsq(h[: k + 2, : k + 1], e1, rcond=None)
        if np.linalg.norm(h[: k + 2, : k + 1] @ y - e1) / nb < tol:
            break
    return sum(yi * zi for yi, zi in zip(y, z)), k + 1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("level", type=int)
    ap.add_argument("smoother", choices=["schwarz", "vanka", "ilu", "sgs", "condensed"])
    ap.add_argument("--box", type=int, default=3000)
    ap.add_argument("--overlap", type=int, default=1)
    ap.add_argument("--drop", type=float, default=1e-4)
    ap.add_argument("--fill", type=float, default=3.0)
    ap.add_argument("--galerkin", action="store_true")
    ap.add_argument("--sweeps", type=int, default=1)
    ap.add_argument("--modes", type=int, default=0)
    ap.add_argument("--patches", type=float, nargs=2, metavar=("W", "S"))
    ap.add_argument("--factor", type=float, nargs="+", default=[100.0], metavar="F")
    ap.add_argument("--rows", action="store_true")
    ap.add_argument("--own", action="store_true")
    args = ap.parse_args()
    if args.smoother == "condensed" and not args.patches:
        ap.error("condensed needs --patches W S")

    a, coarse, p, classes, x = load(args.dir, args.level)
    if args.smoother == "sgs":
        displacement_block(a, p, classes, x, args.sweeps, args.modes, args.patches)
        return
    if args.smoother == "condensed":
        condensed(a, coarse, p, classes, x, args)
        return
    n = a.shape[0]
    print(f"level {args.level}: {n} equations ({np.count_nonzero(classes >= 2)} multipliers), "
          f"{a.nnz} entries; coarse {coarse.shape[0]}; P {p.nnz} entries")
    if args.galerkin:
        coarse = (p.T @ a @ p).tocsc()
        unseen = np.asarray(abs(p).sum(0)).ravel() == 0  # e.g. the placeholders of periodic copies
        coarse = (coarse + sp.diags(unseen.astype(float))).tocsc()
    coarse_lu = sla.splu(coarse, permc_spec="COLAMD")
    print(f"coarse LU: {coarse_lu.L.nnz + coarse_lu.U.nnz} entries")

    def coarse_correction(r):
        return p @ coarse_lu.solve(p.T @ r)

    t = time.time()
    if args.smoother == "schwarz":
        graph = (abs(a) + abs(a.T)).tocsr()

        def bisect(eqs):
            if len(eqs) <= args.box:
                return [eqs]
            axis = int(np.argmax(x[eqs].max(0) - x[eqs].min(0)))
            eqs = eqs[np.argsort(x[eqs, axis], kind="stable")]
            return bisect(eqs[: len(eqs) // 2]) + bisect(eqs[len(eqs) // 2:])

        boxes = bisect(np.arange(n))
        local, entries = [], 0
        for own in boxes:
            s = own
            for _ in range(args.overlap):
                s = np.unique(graph[s].indices)
            # A multiplier brings the unknowns of its constraint (else a singular box).
            constrained = s[classes[s] >= 2]
            if len(constrained):
                s = np.union1d(s, graph[constrained].indices)
            lu = sla.splu(a[s][:, s].tocsc(), permc_spec="COLAMD")
            entries += lu.L.nnz + lu.U.nnz
            local.append((s, lu, np.isin(s, own)))

        def smooth(r, x):
            r = r - a @ x
            for s, lu, keep in local:
                y = lu.solve(r[s])
                x[s[keep]] += y[keep]
            return x

        smooth_back = smooth
        print(f"{len(local)} boxes, local LU {entries} entries")
    elif args.smoother == "vanka":
        degree = np.diff(a.indptr)
        multipliers = classes >= 2
        active = np.flatnonzero(multipliers & (degree > 1))
        # The equations of one control point share its position.
        bulk = np.flatnonzero(~multipliers)
        _, node = np.unique(np.round(x[bulk] / 1e-12), axis=0, return_inverse=True)
        order = np.argsort(node, kind="stable")
        blocks = np.split(bulk[order], np.flatnonzero(np.diff(node[order])) + 1)
        blocks += [np.unique(np.append(a.indices[a.indptr[i]:a.indptr[i + 1]], i)) for i in active]
        blocks = [(s, a[s], np.linalg.pinv(a[s][:, s].toarray())) for s in blocks]
        inactive = np.flatnonzero(multipliers & (degree == 1))

        def sweep(r, x, order):
            x[inactive] = r[inactive] / a.diagonal()[inactive]
            for s, rows, inverse in order:
                x[s] += inverse @ (r[s] - rows @ x)
            return x

        def smooth(r, x):
            return sweep(r, x, blocks)

        def smooth_back(r, x):
            return sweep(r, x, blocks[::-1])

        print(f"{len(blocks)} blocks ({len(active)} active multiplier patches)")
    else:
        ilu = sla.spilu(a.tocsc(), drop_tol=args.drop, fill_factor=args.fill, permc_spec="COLAMD")
        print(f"ILU {ilu.L.nnz + ilu.U.nnz} entries ({(ilu.L.nnz + ilu.U.nnz) / a.nnz:.1f} x the matrix)")

        def smooth(r, x):
            return x + ilu.solve(r - a @ x)

        smooth_back = smooth
    print(f"smoother set up in {time.time() - t:.1f} s")

    b = np.random.default_rng(0).standard_normal(n)

    def cycle(r):
        x = smooth(r, np.zeros(n))
        x = x + coarse_correction(r - a @ x)
        return smooth_back(r, x)

    for label, prec in [
        ("smoother alone", lambda r: smooth_back(r, smooth(r, np.zeros(n)))),
        ("smoother + coarse, additive", lambda r: smooth(r, np.zeros(n)) + coarse_correction(r)),
        ("smooth, coarse, smooth", cycle),
    ]:
        t = time.time()
        x, its = gmres_right(a, prec, b)
        res = np.linalg.norm(b - a @ x) / np.linalg.norm(b)
        print(f"  {label}: {its} iterations, true relative residual {res:.1e}, {time.time() - t:.1f} s", flush=True)


def patches(a, x, width, stride):
    """Overlapping patches: the equations whose positions `x` lie in each cube of side
    `width` (a whole number of strides) whose corner is on the grid of `stride`; each
    patch with the dense inverse of its block and its rows."""
    lo = x.min(0)
    cells = {}
    for i, key in enumerate(map(tuple, np.floor((x - lo) / stride).astype(int))):
        cells.setdefault(key, []).append(i)
    m = int(round(width / stride))
    out, seen = [], set()
    for c in cells:
        eqs = sorted({i for d in np.ndindex(m, m, m)
                      for i in cells.get((c[0] + d[0], c[1] + d[1], c[2] + d[2]), [])})
        if tuple(eqs) not in seen:
            seen.add(tuple(eqs))
            s = np.array(eqs)
            out.append((s, a[s], np.linalg.inv(a[s][:, s].toarray())))
    return out


def patch_sweep(blocks, r, y):
    """One multiplicative sweep over `blocks` (from `patches`) in their order."""
    for s, rows, inverse in blocks:
        y[s] += inverse @ (r[s] - rows @ y)
    return y


def seen_columns(p):
    """`p` without the columns no row reaches (e.g. the placeholders of periodic copies)."""
    return p[:, np.flatnonzero(np.asarray(abs(p).sum(0)).ravel() > 0)].tocsr()


def condensed(a, coarse_own, p, classes, x, args):
    """The `condensed` experiment: GMRES on the whole system, preconditioned by the
    condensation of the active multipliers with a larger augmentation, whose displacement
    system a patch cycle solves."""
    a = a.tocsr()
    n = a.shape[0]
    multiplier = classes >= 2
    u = np.flatnonzero(~multiplier)
    rows = a[np.flatnonzero(multiplier)][:, u]
    # Active: a multiplier row with a nonzero entry (the others are diagonal:
    # out of contact, or periodic copies).
    constrained = np.asarray(abs(rows).sum(1)).ravel() > 0
    active = np.flatnonzero(multiplier)[constrained]
    diagonal = np.setdiff1d(np.flatnonzero(multiplier), active)
    k = a[u][:, u].tocsr()
    bt, b = a[u][:, active].tocsc(), a[active][:, u].tocsr()
    w = np.asarray(abs(b).sum(1)).ravel() / 2
    btwb = (bt @ sp.diags(1 / w) @ b).tocsr()
    scale = k.diagonal().max() / btwb.diagonal().max()
    if args.own:
        coarse_class = np.fromfile(f"{args.dir}/L{args.level}_coarse_class.u64", dtype="<u8")
        cu = np.flatnonzero(coarse_class < 2)
        pu = p.tocsr()[u][:, cu].tocsr()
        own = sla.splu(coarse_own.tocsc())

        def coarse_solve(r):
            z = np.zeros(coarse_own.shape[0])
            z[cu] = r
            return own.solve(z)[cu]
    else:
        pu = seen_columns(p.tocsr()[u].tocsc())
    print(f"level {args.level}: {n} equations, {len(u)} displacements, {len(active)} active multipliers")
    rhs = np.random.default_rng(0).standard_normal(n)
    d = a.diagonal()[diagonal]
    for factor in args.factor:
        e = factor * scale
        kc = (k + e * btwb).tocsr()
        if not args.own:
            galerkin = sla.splu((pu.T @ kc @ pu).tocsc())
            coarse_solve = galerkin.solve
        blocks = patches(kc, x[u], *args.patches)
        if args.rows:
            for j in range(len(active)):
                s = b.indices[b.indptr[j]:b.indptr[j + 1]][b.data[b.indptr[j]:b.indptr[j + 1]] != 0]
                s = np.unique(s)
                blocks.append((s, kc[s], np.linalg.inv(kc[s][:, s].toarray())))
        storage = sum(len(s) ** 2 for s, _, _ in blocks)

        def cycle(r):
            y = patch_sweep(blocks, r, np.zeros(len(u)))
            y = y + pu @ coarse_solve(pu.T @ (r - kc @ y))
            return patch_sweep(blocks[::-1], r, y)

        def prec(r):
            y = np.zeros(n)
            y[diagonal] = r[diagonal] / d
            yu = cycle(r[u] + e * (bt @ (r[active] / w)))
            y[u] = yu
            y[active] = e * (b @ yu - r[active]) / w
            return y

        t = time.time()
        y, its = gmres_right(a, prec, rhs, maxit=300)
        res = np.linalg.norm(rhs - a @ y) / np.linalg.norm(rhs)
        print(f"  F = {factor:g}: {len(blocks)} patches, {storage / 1e6:.1f} M dense entries "
              f"({storage / a.nnz:.1f} x the matrix); {'own' if args.own else 'Galerkin'} coarse: "
              f"{its} iterations, true relative residual {res:.1e}, {time.time() - t:.1f} s", flush=True)


def displacement_block(a, p, classes, x, sweeps, modes, patch_size=None):
    """The `sgs` experiment: the displacement block, its Galerkin coarse level, symmetric
    Gauss-Seidel (point or patch), and the coarse space's approximation of the lowest
    modes."""
    bulk = np.flatnonzero(classes < 2)
    a = a.tocsr()[bulk][:, bulk].tocsr()
    p = p.tocsr()[bulk].tocsc()
    p = seen_columns(p)
    n = a.shape[0]
    coarse = sla.splu((p.T @ a @ p).tocsc())
    print(f"displacement block: {n} equations, {a.nnz} entries; Galerkin coarse {p.shape[1]}")
    lower, upper = sp.tril(a, format="csr"), sp.triu(a, format="csr")

    def sweep(r, y, triangle, is_lower):
        for _ in range(sweeps):
            y = y + sla.spsolve_triangular(triangle, r - a @ y, lower=is_lower)
        return y

    if patch_size:
        blocks = patches(a, x[bulk], *patch_size)
        storage = sum(len(s) ** 2 for s, _, _ in blocks)
        print(f"{len(blocks)} patches of {np.mean([len(s) for s, _, _ in blocks]):.0f} equations on "
              f"average, {storage / 1e6:.1f} M dense entries ({storage / a.nnz:.1f} x the block), "
              f"{sum(len(s) for s, _, _ in blocks) / n:.1f} patches per equation")

        def sweep(r, y, triangle, is_lower):
            for _ in range(sweeps):
                y = patch_sweep(blocks if is_lower else blocks[::-1], r, y)
            return y

    def cycle(r):
        y = sweep(r, np.zeros(n), lower, True)
        y = y + p @ coarse.solve(p.T @ (r - a @ y))
        return sweep(r, y, upper, False)

    b = np.random.default_rng(0).standard_normal(n)
    t = time.time()
    y, its = gmres_right(a, cycle, b)
    res = np.linalg.norm(b - a @ y) / np.linalg.norm(b)
    print(f"  smooth ({sweeps} sweeps), coarse, smooth: {its} iterations, "
          f"true relative residual {res:.1e}, {time.time() - t:.1f} s")
    if modes:
        values, vectors = sla.eigsh(a.tocsc(), k=modes, sigma=0, which="LM")
        z = x[bulk, 2]
        for i in np.argsort(values):
            v = vectors[:, i]
            e = v - p @ coarse.solve(p.T @ (a @ v))
            w = v * v / (v @ v)
            print(f"  mode {values[i]:.3e}: coarse approximation error {np.sqrt((e @ (a @ e)) / (v @ (a @ v))):.2f} "
                  f"(A-norm); its height (mean weighted by v², the positions as written) {w @ z:+.3f}, "
                  f"share within 0.15 of it {w[np.abs(z - w @ z) < 0.15].sum():.2f}")


if __name__ == "__main__":
    main()
