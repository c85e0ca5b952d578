#!/usr/bin/env python3
"""Independent boundary-element reference for the 3D egg box on a flat (issue 12).

Frictionless periodic contact of the egg-box sinusoid
f(x, y) = 2 rms cos(2 pi x/lambda) cos(2 pi y/lambda) (rms = 10 nm,
Delta = 2 rms, Delta/lambda = 0.002) against a flat, one wavelength
lambda = 10 um per square cell, in the small-strain limit, as
generator/src/verify/contact/egg_box.rs poses it, by tamaas (PyPI,
`model_type.basic_2d`, Polonsky-Keer-Rey): a rigid surface on an elastic
half-space of modulus E* = 1/(2(1 - nu^2)/E) (both bodies deformable and
equal; tamaas takes E/(1 - nu^2), so nu = 0 and E = E*), with the
conventions of scripts/tamaas_reference_3d.py. The surface is the exact
sinusoid sampled on n x n points (not tcgen's fit). The pressures are
p/p* = 0.02 ... 0.9 of the full-contact pressure
p* = sqrt(2) pi E* Delta/lambda (analytical::egg_box::full_contact_pressure;
4882.29 Pa here). For each it writes the contact fraction, the mean gap,
the incremental stiffness K = -dp/dgap (central differences at
p(1 +- 1e-3)) and Barber's conductance C = (k_s/E*) K, k_s = k for equal
bodies (as analytical::constriction::barber_conductance_from_stiffness
computes it). Material: Table I (E = 1 MPa, nu = 0.3, k = 1 W/(m K),
conductivity_slope = 0: verify::contact::benchmark_material).

Grid convergence (tamaas 2.9.0, tolerance 1e-10; differences relative to
1024^2, the committed grid; 2048^2 only for the contact fraction, by
--contact-check):

    grid    p/p*  contact   non-contact  mean gap   K (and C)
    128^2   0.02  +3.00 %   -0.19 %      -0.001 %   +0.75 %
    128^2   0.20  -1.26 %   +0.67 %      -0.036 %   -3.38 %
    128^2   0.50  +0.33 %   -0.79 %      +0.012 %   -0.10 %
    128^2   0.90  +0.13 %   -2.49 %      -0.161 %   -0.00 %
    256^2   0.02  +0.57 %   -0.04 %      +0.001 %   -0.23 %
    256^2   0.05  +1.12 %   -0.14 %      +0.000 %   +0.49 %
    256^2   0.10  +0.77 %   -0.18 %      +0.000 %   +0.29 %
    256^2   0.20  +0.09 %   -0.05 %      +0.007 %   -0.57 %
    256^2   0.30  +0.55 %   -0.59 %      -0.001 %   +0.51 %
    256^2   0.50  +0.22 %   -0.53 %      +0.003 %   +0.21 %
    256^2   0.70  +0.04 %   -0.24 %      -0.004 %   -0.27 %
    256^2   0.90  +0.04 %   -0.69 %      +0.002 %   -0.46 %
    512^2   0.02  +0.27 %   -0.02 %      -0.000 %   -0.04 %
    512^2   0.05  +0.08 %   -0.01 %      +0.000 %   -0.12 %
    512^2   0.10  +0.19 %   -0.05 %      +0.000 %   +0.05 %
    512^2   0.20  +0.19 %   -0.10 %      -0.001 %   +0.07 %
    512^2   0.30  +0.08 %   -0.08 %      -0.001 %   -0.02 %
    512^2   0.50  +0.07 %   -0.17 %      +0.000 %   +0.06 %
    512^2   0.70  +0.00 %   -0.02 %      -0.000 %   -0.13 %
    512^2   0.90  +0.03 %   -0.55 %      -0.004 %   +0.08 %
    2048^2  0.02  -0.04 %   +0.00 %
    2048^2  0.05  -0.16 %   +0.02 %
    2048^2  0.10  -0.04 %   +0.01 %
    2048^2  0.20  -0.10 %   +0.05 %
    2048^2  0.30  -0.04 %   +0.04 %
    2048^2  0.50  -0.03 %   +0.07 %
    2048^2  0.70  -0.03 %   +0.14 %
    2048^2  0.90  -0.01 %   +0.11 %

The contact fraction (a count of grid points with positive traction; the
count is the same above 1e-3 p on 256^2, so the threshold does not
matter)
converges from above, about linearly in the spacing but irregularly (the
lattice count of curved spot boundaries; between 0.2 and 0.3 p* the spots
merge at the saddles, where 128^2 is poor). Taking the 1024^2 error as
about twice the 1024^2-to-2048^2 change, the committed contact fractions
are about 0.1 % above their limit (at most 0.3 %, at 0.05 p*). Near full
contact the non-contact fraction converges too, from below: at 0.9 p* it
is 0.04797, 0.04886, 0.04893, 0.04920, 0.04925 on 128^2 ... 2048^2, so
the committed 0.04920 is within about 0.2 % (0.3 % at 0.7 p*). The mean
gap is converged to 0.005 % from 512^2 (0.9 p*, where it is smallest, is
the slowest). K converges irregularly (the discrete active set moves by a
fraction of a point between p(1 - 1e-3) and p(1 + 1e-3)): 0.13 % at most
between 512^2 and 1024^2, so the 1024^2 values are within about 0.1 %;
at 1024^2 a central step of 1e-2 gives K within 0.04 % of the 1e-3 one
(0.12 % at 0.9 p*, its own truncation error). A one-sided step of 1.01
(as verify::contact::egg_box takes it) exceeds the central K on 1024^2 by
+0.28, +0.30, +0.48, +0.87, +0.70, +1.05, +2.04 and +7.4 % at the eight
ratios. Each solve takes about 0.3 s at 256^2, 2 s at 512^2, 9-16 s at
1024^2 and 60-110 s at 2048^2; the whole run (with --contact-check 2048)
18 minutes on 2 cores, one of them shared with another job. Tolerance:
as in scripts/tamaas_reference_3d.py, 1e-10; 1e-12 moves the mean gap by
at most 1e-7 relative at 256^2 (at 0.9 p*, where it is smallest), i.e. K
by < 1e-5, and did not finish in 10 minutes at 1024^2.

The gap distribution (the fractions of the surface whose gap is at most
0.05 and 0.1 Delta, columns gap_below_0.05 and gap_below_0.1, added in
stop 23 by a run with --grids 512 1024 that reproduced the other columns
to the last digit): 512^2 within 0.14 % of 1024^2 at every ratio.

Usage (the data it writes are committed, so the tests need no tamaas):
    python3 -m venv /tmp/tamenv_egg && /tmp/tamenv_egg/bin/pip install tamaas numpy
    /tmp/tamenv_egg/bin/python scripts/tamaas_egg_box.py \\
        generator/tests/data/egg_box_tamaas.csv --grids 128 256 512 1024 \\
        --contact-check 2048
(--contact-check: the contact fractions only, on finer grids, printed
against the committed grid, not written; 2048^2 takes about 11 of the 18
minutes).
"""

import argparse
import math
import time

import numpy as np
import tamaas as tm

# The material, E*, the tolerance and the boundary-element solve are those
# of the random-surface reference (same cell width).
from tamaas_reference_3d import E_STAR, K_THERMAL, TOLERANCE, WIDTH, solve

WAVELENGTH = WIDTH  # = the cell width
RMS = 1.0e-8
AMPLITUDE = 2.0 * RMS  # Delta
RATIOS = [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9]
STEP = 1e-3  # relative pressure step of the central differences
# Gap levels (fractions of Delta) of the gap distribution: the fraction of the
# surface whose gap is at most 0.05 Delta and 0.1 Delta (1 and 2 nm), a check
# of the contact solution near the spots that needs no contact edge.
GAP_LEVELS = [0.05, 0.1]
# analytical::egg_box::full_contact_pressure: p* = sqrt(2) pi E* Delta/lambda.
P_STAR = math.sqrt(2.0) * math.pi * E_STAR * AMPLITUDE / WAVELENGTH


def ratio_text(r):
    """A ratio as the committed CSV writes it (two decimals, more if needed)."""
    return f"{r:.2f}" if round(r, 2) == r else f"{r:g}"


def hertz_contact_fraction(pressure):
    """analytical::egg_box::hertz_contact_fraction: two spheres of radius
    R = lambda^2/(4 pi^2 Delta) per cell, each pressed by p lambda^2/2."""
    radius = WAVELENGTH**2 / (4.0 * math.pi**2 * AMPLITUDE)
    force = 0.5 * pressure * WAVELENGTH**2
    a = (3.0 * force * radius / (4.0 * E_STAR)) ** (1.0 / 3.0)
    return 2.0 * math.pi * a * a / WAVELENGTH**2


def near_full_contact_fraction(ratio):
    """1 - analytical::egg_box::near_full_gap_fraction (penny-shaped gaps)."""
    return 1.0 - 3.0 / (2.0 * math.pi) * max(1.0 - ratio, 0.0)


def egg_box(n):
    """The egg box on n x n points, (x, y)-indexed, as the upper body's heights (m)."""
    x = np.arange(n) * (WAVELENGTH / n)
    xx, yy = np.meshgrid(x, x, indexing="ij")
    q = 2.0 * math.pi / WAVELENGTH
    return AMPLITUDE * np.cos(q * xx) * np.cos(q * yy)


def indenter(n):
    # The upper body comes down onto the flat: its valleys are the indenter's
    # peaks (for the egg box the same surface shifted by half a wavelength).
    surface = -egg_box(n)
    surface -= surface.mean()
    return surface


def reference(n, ratios):
    """The rows (ratio, pressure, contact fraction, mean gap, K, Barber C) of one grid."""
    surface = indenter(n)
    rows = []
    for r in ratios:
        p = r * P_STAR
        start = time.time()
        fraction, gap, mean_p, below = solve(surface, p, [x * AMPLITUDE for x in GAP_LEVELS])
        assert abs(mean_p / p - 1.0) < 1e-9, (p, mean_p)
        _, g_plus, _ = solve(surface, p * (1 + STEP))
        _, g_minus, _ = solve(surface, p * (1 - STEP))
        stiffness = -(2.0 * STEP * p) / (g_plus - g_minus)
        conductance = K_THERMAL / E_STAR * stiffness
        rows.append((r, p, fraction, gap, stiffness, conductance, *below))
        print(f"  {n}^2 {r:g} p*: {time.time() - start:.1f} s", flush=True)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", help="the CSV to write (the finest of --grids)")
    parser.add_argument("--grids", type=int, nargs="+", default=[128, 256, 512, 1024])
    parser.add_argument("--contact-check", type=int, nargs="*", default=[],
                        help="finer grids on which only the contact fractions are computed")
    parser.add_argument("--ratios", type=float, nargs="+", default=RATIOS,
                        help="the pressures as fractions of p*")
    args = parser.parse_args()
    start = time.time()
    print(f"E* = {E_STAR:.9e} Pa, p* = {P_STAR:.9e} Pa")
    results = [(n, reference(n, args.ratios)) for n in sorted(args.grids)]
    n_fine, fine = results[-1]
    print(f"grid convergence, relative to {n_fine}^2:")
    print("    grid   p/p*  contact    mean gap    K          Barber C   non-contact  "
          "gap <= 0.05, 0.1 Delta")
    for n, rows in results:
        for r, f in zip(rows, fine):
            rel = [100.0 * (r[k] / f[k] - 1.0) for k in (2, 3, 4, 5, 6, 7)]
            gap_rel = 100.0 * ((1.0 - r[2]) / (1.0 - f[2]) - 1.0)
            print(f"    {n}^2 {ratio_text(r[0]):>5}  {rel[0]:+.2f} %    {rel[1]:+.3f} %    "
                  f"{rel[2]:+.2f} %    {rel[3]:+.2f} %    {gap_rel:+.2f} %      "
                  f"{rel[4]:+.2f} %, {rel[5]:+.2f} %")
    for n in args.contact_check:
        surface = indenter(n)
        for r, f in zip(args.ratios, fine):
            t = time.time()
            fraction, _, _ = solve(surface, r * P_STAR)
            print(f"    {n}^2 {ratio_text(r):>5}  contact {fraction:.6f} ({100.0 * (fraction / f[2] - 1.0):+.3f} %), "
                  f"non-contact {100.0 * ((1.0 - fraction) / (1.0 - f[2]) - 1.0):+.3f} % "
                  f"({time.time() - t:.0f} s)", flush=True)
    print("at the committed grid (Hertz and penny-gap asymptotes for comparison):")
    for r, p, fr, g, s, c, *_ in fine:
        h, nf = hertz_contact_fraction(p), near_full_contact_fraction(r)
        print(f"{ratio_text(r)} p* = {p:.6g} Pa: contact {fr:.6f} (Hertz {h:.6f}, {100 * (h / fr - 1):+.1f} %; "
              f"penny {nf:.6f}), mean gap {g:.6e} m, K {s:.6e} Pa/m, Barber C {c:.6e} W/(m2 K)")
    with open(args.out, "w") as f:
        f.write(f"# tamaas {tm.__version__} basic_2d PolonskyKeerRey (tolerance {TOLERANCE:g}), "
                f"{n_fine} x {n_fine} points over {WAVELENGTH} m x {WAVELENGTH} m, E* = {E_STAR:.6e} Pa, "
                f"k = {K_THERMAL} W/(m K); scripts/tamaas_egg_box.py: egg box "
                f"2 rms cos(2 pi x/lambda) cos(2 pi y/lambda) on a flat, p* = {P_STAR:.6e} Pa\n")
        # The inputs, checked by the test against the case.
        f.write(f"# width = {WAVELENGTH:.9e}\n# wavelength = {WAVELENGTH:.9e}\n# rms = {RMS:.9e}\n")
        f.write(f"# e_star = {E_STAR:.9e}\n# p_star = {P_STAR:.9e}\n# conductivity = {K_THERMAL:.9e}\n")
        f.write(f"# grid = {n_fine}\n# tolerance = {TOLERANCE:.1e}\n")
        f.write(f"# gap_levels = {', '.join(f'{x:g}' for x in GAP_LEVELS)} (fractions of Delta = 2 rms)\n")
        f.write("ratio,pressure,contact_fraction,mean_gap,stiffness,barber_conductance,"
                "gap_below_0.05,gap_below_0.1\n")
        for row in fine:
            f.write(",".join([ratio_text(row[0])] + [f"{v:.8e}" for v in row[1:]]) + "\n")
    print(f"wrote {args.out}; {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
