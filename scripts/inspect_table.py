#!/usr/bin/env python3
"""Inspect a tcgen table (schemas/table.md): print a summary and plot the
jump (or the conductance) against pressure, one curve per flux, with the
ensemble band (5 %-95 % quantiles and the mean; a single sample gives the
curve alone), for one contact temperature.

Example:
    python3 scripts/inspect_table.py demo.h5 --png demo.png
    python3 scripts/inspect_table.py table.h5 --variable conductance --contact-temperature 353.15
"""

import argparse
import sys

import numpy as np
import xarray as xr


def summary(ds: xr.Dataset) -> str:
    """A text summary of a table: grid, status counts, provenance."""
    lines = [
        f"{ds.attrs.get('schema')} version {ds.attrs.get('schema_version')}, "
        f"{ds.attrs.get('generator')} ({ds.attrs.get('git_revision')}), created {ds.attrs.get('created')}",
        f"source {ds.attrs.get('source')}, config sha256 {ds.attrs.get('config_sha256')}",
        f"identification {ds.attrs.get('identification')}, seed {ds.attrs.get('seed')}, "
        f"wall time {float(np.sum(ds.attrs.get('wall_time', 0.0))):.1f} s on {ds.attrs.get('threads')} threads",
    ]
    for dim in ("pressure", "flux", "contact_temperature", "sample"):
        v = ds[dim].values
        unit = ds[dim].attrs.get("units", "")
        lines.append(f"  {dim:<20} {len(v):>4} values  [{v.min():.4g} .. {v.max():.4g}] {unit}")
    status = ds["status"].values
    names = ds["status"].attrs.get("flag_meanings", "converged failed not_computed").split()
    counts = ", ".join(f"{int((status == i).sum())} {n}" for i, n in enumerate(names))
    lines.append(f"  points: {status.size} ({counts})")
    if "converged_samples" in ds:
        n = ds["converged_samples"].values
        short = int((n < ds.sizes["sample"]).sum())
        if short:
            lines.append(
                f"  {short} grid points rest on fewer than {ds.sizes['sample']} converged samples"
                f" (min {int(n.min())}); their statistics use the converged ones only"
            )
    for name in ("jump", "conductance"):
        v = ds[name].values
        if np.isfinite(v).any():
            lines.append(
                f"  {name:<12} [{np.nanmin(v):.4g} .. {np.nanmax(v):.4g}] {ds[name].attrs.get('units')}"
            )
    if "jump_discretization_error" in ds and np.isfinite(ds["jump_discretization_error"].values).any():
        rel = (ds["jump_discretization_error"] / ds["jump_mean"]).values
        met = ds["error_target_met"].values
        lines.append(
            f"  discretization error of jump_mean: {np.nanmin(rel):.2%} .. {np.nanmax(rel):.2%}"
            f" (target not met at {int(np.nansum(met == 0))} of {int(np.isfinite(met).sum())} points)"
        )
    # The case's known limits, which tcgen sweep printed before it ran.
    for caution in str(ds.attrs.get("cautions", "")).splitlines():
        lines.append(f"  caution: {caution}")
    failed = np.argwhere(status == 1)
    for idx in failed[:5]:
        p, h, t, s = idx
        reason = str(ds["failure_reason"].values[p, h, t, s])
        lines.append(
            f"  failed: p = {ds.pressure.values[p]:.4g} Pa, |h| = {ds.flux.values[h]:.4g} W/m2, "
            f"theta_c = {ds.contact_temperature.values[t]:.5g} K, sample {s}: {reason[:120]}"
        )
    if len(failed) > 5:
        lines.append(f"  ... {len(failed) - 5} more failed points")
    return "\n".join(lines)


def plot(ds: xr.Dataset, variable: str, temperature: float | None, png: str) -> None:
    """Plot `variable` against pressure per flux with the ensemble band."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = ds.contact_temperature.values[0] if temperature is None else temperature
    sel = ds.sel(contact_temperature=t, method="nearest")
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    samples = ds.sizes["sample"]
    for i, h in enumerate(sel.flux.values):
        color = f"C{i}"
        mean = sel[f"{variable}_mean"].sel(flux=h)
        ax.plot(sel.pressure, mean, "o-", color=color, label=f"|h| = {h:.3g} W/m²")
        if samples > 1:
            q = sel[f"{variable}_quantile"].sel(flux=h)
            ax.fill_between(
                sel.pressure,
                q.sel(quantile=0.05),
                q.sel(quantile=0.95),
                color=color,
                alpha=0.25,
                linewidth=0,
            )
            for s in range(samples):
                ax.plot(sel.pressure, sel[variable].sel(flux=h).isel(sample=s), "-", color=color, alpha=0.3, lw=0.6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("pressure p̄N (Pa)")
    ax.set_ylabel(f"{variable} ({sel[variable].attrs.get('units')})")
    band = f", band: 5–95 % of {samples} samples" if samples > 1 else ""
    ax.set_title(f"{variable} at θ̄c = {float(sel.contact_temperature):.5g} K{band}", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("table", help="a table written by tcgen sweep or tcgen merge")
    parser.add_argument("--variable", choices=["jump", "conductance"], default="jump")
    parser.add_argument("--contact-temperature", type=float, default=None, help="K (nearest); default the first")
    parser.add_argument("--png", default=None, help="write the plot to this PNG file")
    args = parser.parse_args(argv)
    with xr.open_dataset(args.table) as ds:
        print(summary(ds))
        if args.png:
            plot(ds, args.variable, args.contact_temperature, args.png)
            print(f"wrote {args.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
