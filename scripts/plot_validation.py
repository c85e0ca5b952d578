#!/usr/bin/env python3
"""Plots of the verification data written by `tcgen verify --data DATA_DIR`.

    scripts/plot_validation.py DATA_DIR OUT_DIR

DATA_DIR holds `checks.json` and one `<case>.csv` per case that recorded
curves (columns `series,x_label,y_label,x,y`). Every case gets one PNG,
`OUT_DIR/<case>.png`, with a panel per pair of axis labels and a line per
series (generic, so new cases such as `lateral` plot without changes); a few
cases get their reference curves and log axes (CUSTOM below), and the MMS
cases are drawn together in `OUT_DIR/mms.png`. The title says how many of the
case's checks passed (from checks.json), and `OUT_DIR/checks.md` lists every
check as a Markdown table per case. Uses matplotlib only (Agg).
"""

import csv
import json
import math
import sys
from collections import OrderedDict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

DPI = 80
PANEL = (5.2, 3.6)


def read_case(path):
    """Series of one case: {(x_label, y_label): {name: (xs, ys)}} in file order."""
    panels = OrderedDict()
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["x_label"], row["y_label"])
            series = panels.setdefault(key, OrderedDict())
            xs, ys = series.setdefault(row["series"], ([], []))
            xs.append(float(row["x"]))
            ys.append(float(row["y"]))
    return panels


def read_checks(data_dir):
    path = Path(data_dir) / "checks.json"
    if not path.exists():
        return []
    with open(path) as f:
        return json.load(f)


# Cases whose checks a shorter case name also prefixes (their own figures).
OWN_FIGURE = ("contact_hertz_3d",)


def check_summary(checks, case_prefix):
    def mine_(name):
        if not name.startswith(case_prefix):
            return False
        return not any(o != case_prefix and o.startswith(case_prefix) and name.startswith(o)
                       for o in OWN_FIGURE)

    mine = [c for c in checks if mine_(c.get("case", ""))]
    if not mine:
        return ""
    ok = sum(1 for c in mine if c.get("pass"))
    return f" ({ok}/{len(mine)} checks pass)"


def is_reference(name):
    """Closed forms and references are drawn as plain lines."""
    return name.startswith("(") or "Westergaard" in name or "Barber" in name


def draw_series(ax, name, xs, ys, style=None):
    kw = dict(label=name)
    if is_reference(name) or len(xs) > 12:
        kw.update(linestyle="-", marker=None)
    else:
        kw.update(linestyle="-", marker="o", markersize=4)
    if style:
        kw.update(style(name))
    ax.plot(xs, ys, **kw)


# Per-case customisations: axis scales and extra reference curves.
def _hertz(ax, key):
    ax.set_xlim(0.0, 1.2)
    if key[1] == "Q(x)/Q":
        r = [i / 200.0 for i in range(0, 241)]
        q = [2.0 / math.pi * math.asin(min(x, 1.0)) for x in r]
        ax.plot(r, q, "k-", lw=1.5, label="(5.2) integrated: (2/π) arcsin(x/a)")
        return
    r = [i / 200.0 for i in range(0, 195)]
    ax.plot(r, [1.0 / math.sqrt(1.0 - x * x) for x in r], "k-", lw=1.5, label="(5.2)")
    ax.set_ylim(0.0, 4.0)


def _hertz3d(ax, key):
    """Sphere on a flat: Hertz's pressure, the isothermal spot and their integrals."""
    ax.set_xlim(0.0, 1.3)
    r = [i / 400.0 for i in range(0, 400)]
    curves = {
        "pN/p0": ([math.sqrt(1.0 - x * x) for x in r], "Hertz √(1 − r²/a²)"),
        "h0/h0_min": ([1.0 / math.sqrt(1.0 - x * x) for x in r], "(5.2) in 3D: 1/√(1 − r²/a²)"),
        "Q(r)/Q": ([1.0 - math.sqrt(1.0 - x * x) for x in r], "1 − √(1 − r²/a²)"),
        "F(r)/F": ([1.0 - (1.0 - x * x) ** 1.5 for x in r], "1 − (1 − r²/a²)^(3/2)"),
    }
    if key[1] in curves:
        ys, label = curves[key[1]]
        ax.plot(r, ys, "k-", lw=1.2, label=label)
    if key[1] == "h0/h0_min":
        ax.set_ylim(-1.0, 4.0)


def _hertz3d_style(name):
    """Nodal values (scattered in r) as markers, the integrals as lines."""
    if name.startswith(("pN^I", "h0^I")):
        return {"linestyle": "none", "marker": "x", "markersize": 4, "alpha": 0.6}
    if name.startswith("⟨"):
        return {"linestyle": "none", "marker": "o", "markersize": 3}
    return {}


def _westergaard(ax, key):
    if key[1] != "contact fraction":
        return
    p = [i / 200.0 for i in range(0, 201)]
    ax.plot(p, [2.0 / math.pi * math.asin(math.sqrt(x)) for x in p], "k-", lw=1,
            label="(2/π) arcsin √(p/p*)")


def _resistive(ax, key):
    ax.set_xscale("log")
    ax.axhline(10.0, color="grey", lw=0.8, ls=":", label="micro jump 10 K")


def _logx(ax, key):
    ax.set_xscale("log")


def _textured(ax, key):
    ax.set_xscale("log")
    if key[1] == "relative deviation":
        ax.set_yscale("log")
        ax.axhline(1e-3, color="grey", lw=0.8, ls=":", label="1e−3")
    else:
        ax.set_ylim(0.0, 1.1)
        ax.axhline(1.0, color="grey", lw=0.8, ls=":", label="flat interface (3.6)")


def _self_consistency(ax, key):
    if key[1].startswith("|"):
        ax.set_yscale("log")
        ax.axhline(1e-6, color="grey", lw=0.8, ls=":", label="tolerance 1e−6")


def _hbp(ax, key):
    ax.set_xscale("log")
    if "θHBP" in key[1]:
        ax.axhline(0.0, color="grey", lw=0.8)
    else:
        ax.set_yscale("log")


METHOD_COLOURS = {
    "two-phase self-consistent": "C0",
    "two-phase": "C1",
    "coupled (2.14)": "C2",
    "linearized (3.4)": "C3",
}


def _hbp_style(name):
    """`model: method`: colour by method, dashed for the resistive model."""
    model, _, method = name.partition(": ")
    style = {"color": METHOD_COLOURS.get(method, "k")}
    if model == "resistive":
        style.update(linestyle="--", marker="s")
    return style


CUSTOM = {
    "contact_hertz": (_hertz, None),
    "contact_hertz_3d": (_hertz3d, _hertz3d_style),
    "contact_wavy": (_westergaard, None),
    "size_effects_resistive": (_resistive, None),
    "scale_separation": (_logx, None),
    "textured_conforming": (_textured, None),
    "self_consistency": (_self_consistency, None),
    "hbp_validation": (_hbp, _hbp_style),
}


def plot_case(case, panels, checks, out_dir):
    custom, style = CUSTOM.get(case, (None, None))
    n = len(panels)
    fig, axes = plt.subplots(1, n, figsize=(PANEL[0] * n, PANEL[1]), squeeze=False)
    for ax, (key, series) in zip(axes[0], panels.items()):
        for name, (xs, ys) in series.items():
            draw_series(ax, name, xs, ys, style)
        if custom:
            custom(ax, key)
        for axis, scale in ((ax.xaxis, ax.get_xscale()), (ax.yaxis, ax.get_yscale())):
            if scale == "log":
                axis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            else:
                ax.ticklabel_format(axis="x" if axis is ax.xaxis else "y", useOffset=False)
        ax.set_xlabel(key[0])
        ax.set_ylabel(key[1])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(case + check_summary(checks, case), fontsize=10)
    fig.tight_layout()
    out = Path(out_dir) / f"{case}.png"
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
    return out


def plot_mms(cases, checks, out_dir):
    """All MMS cases in one figure: error norms vs h with the expected slopes."""
    names = sorted(cases)
    cols = 3
    rows = (len(names) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.0 * rows), squeeze=False)
    for ax in axes.flat[len(names):]:
        ax.set_visible(False)
    for ax, case in zip(axes.flat, names):
        p = int(case.rsplit("_p", 1)[1]) if "_p" in case else None
        for key, series in cases[case].items():
            for name, (xs, ys) in series.items():
                ax.loglog(xs, ys, "o-", ms=3, label=name)
                if p is not None:
                    # Expected slope through the finest point (dotted).
                    rate = p + 1 if name.startswith("L2") else p
                    h0, e0 = xs[-1], ys[-1]
                    ref = [e0 * (h / h0) ** rate for h in xs]
                    ax.loglog(xs, ref, ":", color="grey", lw=0.8)
            ax.set_xlabel(key[0])
            ax.set_ylabel(key[1])
        ax.set_title(case + check_summary(checks, case), fontsize=8)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=6)
    fig.suptitle("MMS errors; dotted: slopes p+1 (L2) and p (H1)", fontsize=10)
    fig.tight_layout()
    out = Path(out_dir) / "mms.png"
    fig.savefig(out, dpi=70)
    plt.close(fig)
    return out


def fmt(v, none="NaN/∞", digits=4):
    """JSON has no NaN or infinity: serde writes them as null."""
    if v is None:
        return none
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def write_checks_md(checks, out_dir):
    """Every check of checks.json as a Markdown table per case."""
    lines = ["# Verification checks", "", "Generated by scripts/plot_validation.py from checks.json.", ""]
    cases = OrderedDict()
    for c in checks:
        cases.setdefault(c.get("case", "?"), []).append(c)
    for case, rows in cases.items():
        lines += [f"## {case}", "", "| quantity | computed | reference | error | tolerance | result |",
                  "|---|---|---|---|---|---|"]
        for c in rows:
            if "error" in c and "quantity" not in c:
                lines.append(f"| error: {c['error']} | | | | | FAIL |")
                continue
            q = c.get("quantity", "").replace("|", "\\|")
            rate = f" (rate {c['rate']:.3f})" if c.get("rate") is not None else ""
            lines.append(
                f"| {q}{rate} | {fmt(c.get('computed'), digits=7)} | {fmt(c.get('reference'), digits=7)} | "
                f"{fmt(c.get('error'))} | {fmt(c.get('tolerance'), '∞')} | "
                f"{'pass' if c.get('pass') else 'FAIL'} |"
            )
        lines.append("")
    out = Path(out_dir) / "checks.md"
    out.write_text("\n".join(lines))
    return out


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    data_dir, out_dir = Path(argv[1]), Path(argv[2])
    out_dir.mkdir(parents=True, exist_ok=True)
    checks = read_checks(data_dir)
    mms = {}
    written = []
    for path in sorted(data_dir.glob("*.csv")):
        case = path.stem
        panels = read_case(path)
        if not panels:
            continue
        if case.startswith("mms_"):
            mms[case] = panels
            continue
        written.append(plot_case(case, panels, checks, out_dir))
    if mms:
        written.append(plot_mms(mms, checks, out_dir))
    if checks:
        written.append(write_checks_md(checks, out_dir))
    for w in written:
        print(w)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
