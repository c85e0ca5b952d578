#!/usr/bin/env python3
"""Independent boundary-element reference for a random areal surface (issue 12 item 6).

Frictionless periodic contact of the fitted upper surface of
generator/tests/data/random_areal.toml (3D, isotropic Gaussian, RMS 10 nm,
correlation length 2 um, 10 um x 10 um cell, NURBS fit on 16 x 16 elements,
p = 2) against the flat lower body, in the small-strain limit, by tamaas
(PyPI, `model_type.basic_2d`, Polonsky-Keer-Rey): a rigid surface on an
elastic half-space of modulus E* = 1/(2(1 - nu^2)/E) (both bodies deformable
and equal; tamaas takes E/(1 - nu^2), so nu = 0 and E = E*), as
scripts/tamaas_reference.py does in 2D. For each pressure it writes the
contact fraction, the mean gap, the incremental stiffness K = -dp/dgap
(central differences at p(1 +- 1e-3)) and Barber's conductance
C = (k_s/E*) K, k_s = k for equal bodies (as
analytical::constriction::barber_conductance_from_stiffness computes it).

Input: height maps of `tcgen surface` (one line per y row, heights in m),
one per grid; the output holds the finest. The pressures give contact
fractions of about 2 to 20 %.

Grid convergence (tamaas 2.9.0, tolerance 1e-10; the same fitted surface
sampled on n x n points; differences relative to 1024^2, the committed grid):

    grid    p/Pa  contact   mean gap   K (and C)
    128^2     30  +5.51 %   +0.001 %   +0.83 %
    128^2    600  +1.11 %   -0.002 %   +0.07 %
    256^2     30  +1.44 %   -0.000 %   -0.09 %
    256^2    100  +1.02 %   +0.000 %   -0.01 %
    256^2    600  +0.58 %   -0.000 %   +0.03 %
    512^2     30  +0.49 %   +0.000 %   -0.02 %
    512^2    100  +0.30 %   -0.000 %   -0.00 %
    512^2    300  +0.21 %   -0.000 %   +0.02 %
    512^2    600  +0.18 %   -0.000 %   +0.00 %

The contact fraction (a count of grid points in contact) converges about
linearly in the spacing, so the 1024^2 values are within about 0.5 % at
30 Pa and 0.2-0.3 % from 100 Pa; the mean gap and K are converged to 0.02 %
from 512^2. At 1024^2: contact 1.8 %, 5.1 %, 10.2 %, 17.2 % at 30, 100,
300, 600 Pa. Each solve takes about 0.1 s at 128^2, 4 s at 512^2 and the
whole run 4.5 minutes on 2 cores. Tolerance: Polonsky-Keer-Rey stalls near
1e-11 on 512^2 at 300 Pa (1e-12 is not reached in 3 000 iterations); 1e-10 moves the
mean gap by less than 1e-10 relative (checked at 256^2), far below the
1e-3 steps of the central differences.

The exact surface (`tcgen surface --exact`: the spectral sum itself, not its
fit), which the adaptive levels converge to (they resolve the surface where
they refine), gives generator/tests/data/random_areal_exact_tamaas.csv: its
Barber conductance differs from the fit's by -1.17, +0.10, -0.22, -0.04 %
and its contact fraction by -1.09, -0.20, -0.35, -0.05 % at 30, 100, 300,
600 Pa. Grid convergence there (relative to 1024^2):

    grid    p/Pa  contact   mean gap   K (and C)
    256^2     30  +1.71 %   +0.000 %   -0.04 %
    256^2    600  +0.46 %   +0.000 %   -0.03 %
    512^2     30  +0.60 %   +0.000 %   +0.04 %
    512^2    100  +0.20 %   +0.000 %   -0.09 %
    512^2    300  +0.18 %   +0.000 %   +0.00 %
    512^2    600  +0.13 %   -0.000 %   -0.00 %

The self-affine surface of generator/tests/data/random_self_affine.toml (many
small spots; Hurst 0.8, cut-off 1.25 um, RMS 10 nm), its exact surface with
`--pressures 100,300,1000`, gives random_self_affine_exact_tamaas.csv
(contact 3.4, 8.9, 29 %). Grid convergence there (relative to 1024^2):

    grid    p/Pa  contact   mean gap   K (and C)
    256^2    100  +1.31 %   +0.001 %   -0.18 %
    256^2    300  +1.04 %   +0.000 %   -0.14 %
    256^2   1000  +0.90 %   -0.000 %   +0.19 %
    512^2    100  +0.58 %   +0.000 %   +0.01 %
    512^2    300  +0.29 %   -0.000 %   -0.08 %
    512^2   1000  +0.29 %   -0.000 %   +0.01 %

Usage (the data it writes are committed, so the tests need no tamaas):
    python3 -m venv /tmp/tamenv3 && /tmp/tamenv3/bin/pip install tamaas numpy
    for n in 128 256 512 1024; do
        cargo run --release -p tcgen -- surface generator/tests/data/random_areal.toml \
            -o /tmp/areal_$n.csv --points $n
    done
    /tmp/tamenv3/bin/python scripts/tamaas_reference_3d.py /tmp/areal_{128,256,512,1024}.csv \
        generator/tests/data/random_areal_tamaas.csv
and for the exact surface the same with `--exact` in `tcgen surface` and
generator/tests/data/random_areal_exact_tamaas.csv as the output; for the
self-affine surface `random_self_affine.toml`, `--exact`, and
    /tmp/tamenv3/bin/python scripts/tamaas_reference_3d.py --pressures 100,300,1000 \
        /tmp/sa_{256,512,1024}.csv generator/tests/data/random_self_affine_exact_tamaas.csv
(`--pressures`, comma-separated, in Pa; default 30,100,300,600).
"""

import sys

import numpy as np
import tamaas as tm

tm.set_log_level(tm.LogLevel.error)

E, NU, K_THERMAL = 1.0e6, 0.3, 1.0  # Table I with conductivity_slope = 0 (scripts and case agree)
WIDTH = 1.0e-5
PRESSURES = [30.0, 100.0, 300.0, 600.0]
TOLERANCE = 1e-10  # see the docstring
E_STAR = 1.0 / (2.0 * (1.0 - NU**2) / E)


def read_map(path):
    """The height map (m) of `tcgen surface` as an (x, y)-indexed array."""
    z = np.loadtxt(path, delimiter=",", ndmin=2)
    if z.shape[0] != z.shape[1]:
        sys.exit(f"{path}: a square grid expected, got {z.shape}")
    return z.T.copy()  # rows are y in the file; tamaas indexes [x, y]


def solve(surface, pressure, gap_levels=()):
    """Contact fraction, mean gap and mean traction at mean pressure `pressure` (Pa);
    with `gap_levels` (m), also the fractions of the surface whose gap is at most
    each level (a fourth value, a list)."""
    n = surface.shape[0]
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [WIDTH, WIDTH], [n, n])
    model.E = E_STAR  # E* with nu = 0 below
    model.nu = 0.0
    solver = tm.PolonskyKeerRey(model, surface, TOLERANCE)
    solver.max_iter = 100000
    solver.solve(pressure)
    traction = np.asarray(model.traction).reshape(surface.shape)
    gap = np.asarray(model.displacement).reshape(surface.shape) - surface
    gap -= min(gap.min(), 0.0)
    out = float((traction > 0).mean()), float(gap.mean()), float(traction.mean())
    if gap_levels:
        return out + ([float((gap <= level).mean()) for level in gap_levels],)
    return out


def reference(heights, pressures):
    """The rows (pressure, contact fraction, mean gap, K, Barber C) of one grid."""
    # The upper body comes down onto the flat: its valleys are the indenter's peaks.
    surface = -heights
    surface -= surface.mean()
    rows = []
    for p in pressures:
        fraction, gap, mean_p = solve(surface, p)
        assert abs(mean_p / p - 1.0) < 1e-9, (p, mean_p)
        _, g_plus, _ = solve(surface, p * (1 + 1e-3))
        _, g_minus, _ = solve(surface, p * (1 - 1e-3))
        stiffness = -(2e-3 * p) / (g_plus - g_minus)
        conductance = K_THERMAL / E_STAR * stiffness
        rows.append((p, fraction, gap, stiffness, conductance))
    return rows


def main():
    args = sys.argv[1:]
    pressures = PRESSURES
    if len(args) >= 2 and args[0] == "--pressures":
        pressures = [float(p) for p in args[1].split(",")]
        args = args[2:]
    if len(args) < 2:
        sys.exit(__doc__)
    sources, out = args[:-1], args[-1]
    grids = sorted(((read_map(s), s) for s in sources), key=lambda g: g[0].shape[0])
    results = [(h.shape[0], reference(h, pressures)) for h, _ in grids]
    heights, _ = grids[-1]
    n_fine, fine = results[-1]
    print(f"grid convergence, relative to {n_fine}^2:")
    print("    grid    p/Pa  contact    mean gap    K          Barber C")
    for n, rows in results:
        for r, f in zip(rows, fine):
            rel = [100.0 * (r[k] / f[k] - 1.0) for k in (1, 2, 3, 4)]
            print(f"    {n}^2 {r[0]:7g}  {rel[0]:+.2f} %    {rel[1]:+.3f} %    {rel[2]:+.2f} %    {rel[3]:+.2f} %")
    for p, fr, g, s, c in fine:
        print(f"p = {p:g} Pa: contact {fr:.5f}, mean gap {g:.5e} m, "
              f"K {s:.5e} Pa/m, Barber C {c:.5e} W/(m2 K)")
    with open(out, "w") as f:
        f.write(f"# tamaas {tm.__version__} basic_2d PolonskyKeerRey (tolerance {TOLERANCE:g}), "
                f"{n_fine} x {n_fine} points over {WIDTH} m x {WIDTH} m, E* = {E_STAR:.6e} Pa, "
                f"k = {K_THERMAL} W/(m K)\n")
        # The inputs and the surface's identity, checked by the test against
        # the case (its material, cell, and fit on this grid).
        f.write(f"# width = {WIDTH:.9e}\n# e_star = {E_STAR:.9e}\n# conductivity = {K_THERMAL:.9e}\n")
        f.write(f"# grid = {n_fine}\n# surface_rms = {heights.std():.9e}\n"
                f"# surface_lowest = {heights.min():.9e}\n")
        f.write("pressure,contact_fraction,mean_gap,stiffness,barber_conductance\n")
        for p, fr, g, s, c in fine:
            f.write(f"{p:.6e},{fr:.8e},{g:.8e},{s:.8e},{c:.8e}\n")


if __name__ == "__main__":
    main()
