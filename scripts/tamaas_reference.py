#!/usr/bin/env python3
"""Independent boundary-element reference for a random profile (issue 11 item 7).

Frictionless periodic contact of the upper surface of
generator/tests/data/random_profile.toml (the exact profile, which the adaptive
solve resolves on its refined levels; not the case mesh's fit) against the
flat lower body, in the
small-strain limit, by tamaas (PyPI, `model_type.basic_1d`, Polonsky-Keer-Rey):
a rigid profile on an elastic half-space of plane-strain modulus
E* = 1/(2(1 - nu^2)/E) (both bodies deformable, equal). For each pressure it
writes the contact fraction, the mean gap, the incremental stiffness
K = -dp/dgap (central differences at p(1 +- 1e-3)) and Barber's conductance
C = (k_s/E*) K, k_s = k for equal bodies (the analogy the project's
analytical::constriction::barber_conductance_from_stiffness implements).

Usage (the data it writes are committed, so the tests need no tamaas):
    python3 -m venv /tmp/tamenv && /tmp/tamenv/bin/pip install tamaas numpy
    cargo run --release -p tcgen -- surface generator/tests/data/random_profile.toml \
        -o /tmp/profile.csv --points 16384
    /tmp/tamenv/bin/python scripts/tamaas_reference.py /tmp/profile.csv \
        generator/tests/data/random_profile_tamaas.csv
"""

import sys

import numpy as np
import tamaas as tm

tm.set_log_level(tm.LogLevel.error)

E, NU, K_THERMAL = 1.0e6, 0.3, 1.0  # Table I (scripts and case agree)
WIDTH = 1.0e-5
PRESSURES = [100.0, 300.0, 1000.0, 3000.0]


def solve(surface, pressure):
    """Contact fraction and mean gap at mean pressure `pressure` (Pa)."""
    n = surface.size
    model = tm.ModelFactory.createModel(tm.model_type.basic_1d, [WIDTH], [n])
    model.E = 1.0 / (2.0 * (1.0 - NU**2) / E)  # E* with nu = 0 below
    model.nu = 0.0
    solver = tm.PolonskyKeerRey(model, surface, 1e-10)
    solver.max_iter = 100000
    solver.solve(pressure)
    traction = np.asarray(model.traction).ravel()
    gap = np.asarray(model.displacement).ravel() - surface
    gap -= min(gap.min(), 0.0)
    return float((traction > 0).mean()), float(gap.mean()), float(traction.mean())


def main():
    src, out = sys.argv[1], sys.argv[2]
    data = np.genfromtxt(src, delimiter=",", names=True, comments="#")
    # The upper body comes down onto the flat: its valleys are the indenter's peaks.
    surface = -(data["upper"] - data["lower"])
    surface -= surface.mean()
    e_star = 1.0 / (2.0 * (1.0 - NU**2) / E)
    rows = []
    for p in PRESSURES:
        fraction, gap, mean_p = solve(surface, p)
        _, g_plus, _ = solve(surface, p * (1 + 1e-3))
        _, g_minus, _ = solve(surface, p * (1 - 1e-3))
        stiffness = -(2e-3 * p) / (g_plus - g_minus)
        conductance = K_THERMAL / e_star * stiffness
        rows.append((p, fraction, gap, stiffness, conductance, mean_p))
        print(f"p = {p:g} Pa: contact {fraction:.5f}, mean gap {gap:.5e} m, "
              f"K {stiffness:.5e} Pa/m, Barber C {conductance:.5e} W/(m2 K)")
    with open(out, "w") as f:
        f.write(f"# tamaas {tm.__version__} basic_1d PolonskyKeerRey, {surface.size} points over "
                f"{WIDTH} m, E* = {e_star:.6e} Pa, k = {K_THERMAL} W/(m K)\n")
        # The profile's identity, checked by the test against the case's surface.
        f.write(f"# profile_rms = {surface.std():.9e}\n# profile_lowest = {data['upper'].min():.9e}\n")
        f.write("pressure,contact_fraction,mean_gap,stiffness,barber_conductance\n")
        for p, fr, g, s, c, _ in rows:
            f.write(f"{p:.6e},{fr:.8e},{g:.8e},{s:.8e},{c:.8e}\n")


if __name__ == "__main__":
    main()
