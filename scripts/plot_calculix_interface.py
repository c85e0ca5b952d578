"""Plot the temperature field of a CalculiX run across a contact interface.

Reads the node coordinates from the input deck (``*NODE``) and the nodal
temperatures of every step from the ``.dat`` file (``*NODE PRINT`` of ``NT``
for a set holding all nodes), and draws, for each step, the temperature
along the stacking direction ``z``: two straight conduction profiles with the
jump at the interface that the ``*GAP CONDUCTANCE`` block produces. The left
panel shows the last step as a colour map of the two blocks.

Made for the model of ``generator/tests/suite/calculix_end_to_end.rs``, whose files
are in ``target/tmp/calculix-e2e/`` after ``cargo test --release -p tcgen
--test suite calculix_end_to_end::``. The README picture::

    target/python-venv/bin/python scripts/plot_calculix_interface.py \\
        target/tmp/calculix-e2e/blocks_si.inp --png docs/calculix_interface.png \\
        --length-scale 1e3 --length-unit mm --temperature-unit degC \\
        --label "reference table, |h| = 1e6 W/m², p = 1.2, 2.4, 3.5 kPa (SI deck, Celsius)"
"""

import argparse
import pathlib
import re
import sys


def read_nodes(inp):
    """``{node: (x, y, z)}`` from the ``*NODE`` blocks of an input deck."""
    nodes, inside = {}, False
    for line in pathlib.Path(inp).read_text().splitlines():
        s = line.strip()
        if s.startswith("**") or not s:
            continue
        if s.startswith("*"):
            inside = s.upper().startswith("*NODE") and not s.upper().startswith(
                "*NODE PRINT"
            )
            continue
        if inside:
            f = [v.strip() for v in s.split(",")]
            nodes[int(f[0])] = tuple(float(v) for v in f[1:4])
    return nodes


def read_temperatures(dat):
    """``[(time, {node: T})]`` for every ``temperatures for set`` block,
    merged per time (the largest set wins)."""
    steps = {}
    current = None
    header = re.compile(r"temperatures for set (\S+) and time\s+(\S+)")
    for line in pathlib.Path(dat).read_text().splitlines():
        m = header.search(line)
        if m:
            current = steps.setdefault(float(m.group(2)), {})
            continue
        f = line.split()
        if current is not None and len(f) == 2:
            try:
                current[int(f[0])] = float(f[1])
            except ValueError:
                current = None
        elif line.strip() and not f[0].isdigit():
            current = None
    return sorted(steps.items())


def profile(nodes, temps):
    """Mean temperature per (z, block) with the interface nodes split into
    the lower and the upper block: nodes sharing a z are grouped by
    temperature (the jump separates them)."""
    by_z = {}
    for n, t in temps.items():
        if n in nodes:
            by_z.setdefault(round(nodes[n][2], 12), []).append(t)
    lower, upper = [], []
    z_int = None
    for z in sorted(by_z):
        ts = sorted(by_z[z])
        if ts[-1] - ts[0] > 1e-9 * max(1.0, abs(ts[-1])):
            # The interface: the colder half is the lower (master) block.
            half = len(ts) // 2
            lower.append((z, sum(ts[:half]) / half))
            upper.append((z, sum(ts[half:]) / (len(ts) - half)))
            z_int = z
        elif z_int is None:
            lower.append((z, sum(ts) / len(ts)))
        else:
            upper.append((z, sum(ts) / len(ts)))
    return lower, upper, z_int


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("inp", help="the CalculiX input deck (its .dat beside it)")
    ap.add_argument("--png", required=True, help="the picture to write")
    ap.add_argument("--length-unit", default="mm", help="label of z after scaling")
    ap.add_argument("--length-scale", type=float, default=1.0,
                    help="multiply coordinates by this (e.g. 1e3 for m -> mm)")
    ap.add_argument("--temperature-unit", default="K")
    ap.add_argument("--label", default="", help="a line under the title")
    a = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    inp = pathlib.Path(a.inp)
    nodes = {n: tuple(a.length_scale * c for c in xyz)
             for n, xyz in read_nodes(inp).items()}
    steps = read_temperatures(inp.with_suffix(".dat"))
    if not steps:
        sys.exit(f"{inp.with_suffix('.dat')}: no nodal temperatures")
    fig, (ax0, ax1) = plt.subplots(
        1, 2, figsize=(7.5, 3.6), gridspec_kw={"width_ratios": [1, 2.4]}
    )
    jumps = []
    for time, temps in steps:
        lower, upper, z_int = profile(nodes, temps)
        if z_int is None:
            sys.exit(f"step {time}: no interface (no two temperatures at one z)")
        jump = upper[0][1] - lower[-1][1]
        jumps.append(jump)
        line = ax1.plot(*zip(*lower), "o-", ms=3)[0]
        ax1.plot(*zip(*upper), "o-", ms=3, color=line.get_color(),
                 label=f"step {time:g}: jump {jump:.4g} {a.temperature_unit}")
        ax1.plot([z_int, z_int], [lower[-1][1], upper[0][1]], ":",
                 color=line.get_color())
    ax1.axvline(z_int, color="0.6", lw=0.8)
    ax1.set_xlabel(f"z [{a.length_unit}] (lower block | upper block)")
    ax1.set_ylabel(f"temperature [{a.temperature_unit}]")
    ax1.legend(fontsize=7, loc="upper left")
    # The last step as a colour map: each block a strip, T(z).
    lower, upper, _ = profile(nodes, steps[-1][1])
    xs = [0.0, 1.0]
    vmin, vmax = lower[0][1], upper[-1][1]
    for part in (lower, upper):
        zs = [z for z, _ in part]
        ts = [[t, t] for _, t in part]
        m = ax0.pcolormesh(xs, zs, ts, shading="gouraud", vmin=vmin, vmax=vmax,
                           cmap="inferno")
    ax0.axhline(z_int, color="w", lw=1.5)
    ax0.set_xticks([])
    ax0.set_ylabel(f"z [{a.length_unit}]")
    ax0.set_title("last step", fontsize=8)
    fig.colorbar(m, ax=ax0, fraction=0.12, pad=0.04)
    fig.suptitle(
        "CalculiX: temperature across the contact (*GAP CONDUCTANCE from tcgen law)",
        fontsize=9,
    )
    if a.label:
        ax1.set_title(a.label, fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print(" ".join(f"{j:.6g}" for j in jumps))


if __name__ == "__main__":
    main()
