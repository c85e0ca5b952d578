#!/usr/bin/env python3
"""Write the steep height map of the robustness test (generator/tests/data/
steep_heightmap.csv; docs/3d.md, "Stop 105"): eight plane waves on a
10 um x 10 um periodic cell, 32 x 32 samples, wave vectors of 3 to 5.7
wavelengths per cell, scaled to an RMS of 0.5 um. Its RMS slope is 1.34 and
its largest slope 3.2: a measured surface's fine scales, steeper than the
shipped example (tables/heightmap_example.csv, RMS slope 0.42). The format
is that of kind = "heightmap" (schemas/case.md): heights in m, one line per
y row, the point at W not repeated.

    python3 scripts/steep_heightmap.py generator/tests/data/steep_heightmap.csv
"""

import sys

import numpy as np


def steep_map(n: int = 32, width: float = 1e-5, rms: float = 0.5e-6) -> np.ndarray:
    rng = np.random.default_rng(102)
    waves = [
        (k1, k2)
        for k1 in range(-6, 7)
        for k2 in range(0, 7)
        if 3.0 <= np.hypot(k1, k2) <= 5.7 and (k2 > 0 or k1 > 0)
    ]
    chosen = rng.choice(len(waves), 8, replace=False)
    x = np.arange(n) * width / n
    X, Y = np.meshgrid(x, x)  # rows are y, columns x
    h = np.zeros((n, n))
    for i in chosen:
        k1, k2 = waves[i]
        amplitude = rng.uniform(0.5, 1.0)
        phase = rng.uniform(0.0, 2.0 * np.pi)
        h += amplitude * np.cos(2.0 * np.pi * (k1 * X + k2 * Y) / width + phase)
    h *= rms / np.sqrt((h**2).mean())
    return h - h.mean()


if __name__ == "__main__":
    np.savetxt(sys.argv[1], steep_map(), delimiter=",", fmt="%.9e")
