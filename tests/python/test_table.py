"""The table format through the Python stack (schemas/table.md): xarray,
netCDF4 and h5py open the demo table and the committed reference table;
dimensions, coordinates, units and values are checked against the sweep
configuration and against each other; scripts/inspect_table.py,
scripts/nightly.sh and the roles of scripts/slurm_sweep.sh run.

Run through tests/python/run.sh (it builds tcgen and the demo table and
sets TCGEN_BIN, TCGEN_DEMO_TABLE, TCGEN_PYTHON, TCGEN_TEST_DIR)."""

import hashlib
import os
import pathlib
import subprocess
import tomllib

import h5py
import netCDF4
import numpy as np
import pytest
import xarray as xr

ROOT = pathlib.Path(__file__).resolve().parents[2]
TCGEN = os.environ.get("TCGEN_BIN", str(ROOT / "target/release/tcgen"))
DEMO = os.environ.get("TCGEN_DEMO_TABLE", str(ROOT / "target/python-tests/demo.h5"))
WORK = pathlib.Path(os.environ.get("TCGEN_TEST_DIR", str(ROOT / "target/python-tests")))
PYTHON = os.environ.get("TCGEN_PYTHON", "python3")
FILL = 9.969209968386869e36

DIMS = ("pressure", "flux", "contact_temperature", "sample")
UNITS = {
    "pressure": "Pa",
    "flux": "W m-2",
    "contact_temperature": "K",
    "jump": "K",
    "conductance": "W m-2 K-1",
    "mean_gap": "m",
    "contact_fraction": "1",
    "jump_mean": "K",
    "conductance_std": "W m-2 K-1",
}


def axis(spec):
    """The values of a [sweep] axis (number, list or range)."""
    if isinstance(spec, (int, float)):
        return np.array([float(spec)])
    if isinstance(spec, list):
        return np.array(spec, dtype=float)
    n, a, b = spec["count"], spec["from"], spec["to"]
    v = np.geomspace(a, b, n) if spec["spacing"] == "log" else np.linspace(a, b, n)
    v[0], v[-1] = a, b
    return v


def check_table(path, config_path):
    cfg = tomllib.loads(pathlib.Path(config_path).read_text())["sweep"]
    ds = xr.open_dataset(path)
    # Dimensions and coordinates.
    expected = {
        "pressure": axis(cfg["pressures"]),
        "flux": axis(cfg["fluxes"]),
        "contact_temperature": axis(cfg["contact_temperatures"]),
        "sample": np.arange(cfg.get("samples", 1)),
    }
    for d in DIMS:
        assert d in ds.dims and d in ds.coords
        np.testing.assert_allclose(ds[d].values, expected[d], rtol=1e-12)
    assert ds["jump"].dims == DIMS
    assert ds["jump_mean"].dims == DIMS[:3]
    assert ds["jump_quantile"].dims == DIMS[:3] + ("quantile",)
    # CF attributes.
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
        if var.dtype.kind in "fiu":
            assert "units" in var.attrs, name
    for name, unit in UNITS.items():
        assert ds[name].attrs["units"] == unit, name
    assert ds.attrs["Conventions"] == "CF-1.8"
    assert ds.attrs["schema"] == "tcgen-table" and int(ds.attrs["schema_version"]) == 2
    config = str(ds["config"].values)
    assert hashlib.sha256(config.encode()).hexdigest() == ds.attrs["config_sha256"]
    assert tomllib.loads(config)["sweep"]["samples"] == cfg.get("samples", 1)
    assert "jump" in ds.attrs["sign_convention"]
    # Provenance NCO and CF tools expect (issue 14 item 6).
    assert "sweep" in ds.attrs["history"] and "Temizer" in ds.attrs["references"]
    # Values: masks follow the status; conductance = |h|/jump; statistics.
    status = ds["status"].values
    ok = status == 0
    assert ok.any()
    jump = ds["jump"].values
    assert np.all(np.isfinite(jump[ok])) and np.all(jump[ok] > 0)
    assert np.all(np.isnan(jump[~ok]))
    flux = ds["flux"].values[None, :, None, None]
    np.testing.assert_allclose(ds["conductance"].values[ok], (flux / jump)[ok], rtol=1e-12)
    frac = ds["contact_fraction"].values[ok]
    assert np.all((frac >= 0) & (frac <= 1))
    np.testing.assert_allclose(ds["jump_mean"].values, np.nanmean(jump, axis=3), rtol=1e-12)
    np.testing.assert_array_equal(ds["converged_samples"].values, ok.sum(axis=3))
    # No spread from fewer than two converged samples (issue 14 item 7).
    n = ds["converged_samples"].values
    std = ds["jump_std"].values
    assert np.all(np.isnan(std[n < 2]))
    if (n >= 2).any():
        np.testing.assert_allclose(std[n >= 2], np.nanstd(jump, axis=3, ddof=1)[n >= 2], rtol=1e-10)
    np.testing.assert_allclose(
        ds["jump_quantile"].sel(quantile=0.5).values, np.nanmedian(jump, axis=3), rtol=1e-12
    )
    # The jump grows with the flux at every pressure (constraint model).
    jm = ds["jump_mean"].values
    assert np.all(np.diff(jm, axis=1)[np.isfinite(np.diff(jm, axis=1))] > 0)
    ds.close()
    # The raw file: netCDF-4 with fill values (not NaN), HDF5 dimension scales.
    with netCDF4.Dataset(path) as nc:
        assert nc.data_model == "NETCDF4"
        assert nc.variables["jump"].dimensions == DIMS
        assert nc.variables["jump"]._FillValue == FILL
        nc.set_auto_mask(False)
        raw = nc.variables["jump"][:]
        assert not np.isnan(raw).any()
        assert np.all(raw[~ok] == FILL)
    with h5py.File(path, "r") as h:
        assert "DIMENSION_LIST" in h["jump"].attrs
        assert h["pressure"].attrs["CLASS"] == b"DIMENSION_SCALE"


def test_demo_table():
    check_table(DEMO, ROOT / "tables/demo.toml")


def test_reference_table():
    check_table(ROOT / "tables/reference.h5", ROOT / "tables/reference.toml")


def test_inspect_table_prints_a_summary_and_plots():
    png = WORK / "demo.png"
    png.unlink(missing_ok=True)
    out = subprocess.run(
        [PYTHON, str(ROOT / "scripts/inspect_table.py"), DEMO, "--png", str(png)],
        check=True, capture_output=True, text=True,
    ).stdout
    assert "tcgen-table version 2" in out and "points:" in out and "converged" in out
    assert png.stat().st_size > 10_000
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    c = WORK / "demo-conductance.png"
    subprocess.run(
        [PYTHON, str(ROOT / "scripts/inspect_table.py"), DEMO, "--variable", "conductance", "--png", str(c)],
        check=True, capture_output=True,
    )
    assert c.stat().st_size > 10_000


def test_a_table_keeps_its_cautions():
    """A degree-1 3D table (the egg box on 3 x 3 x 1 elements) carries the
    cautions that tcgen sweep printed as the global attribute `cautions`,
    one per line, and scripts/inspect_table.py shows them: degree 1 in 3D,
    and the fixed mesh's fit that misses the egg box (150 % of its RMS);
    the demo table has none."""
    case = (ROOT / "tables/egg_box_on_flat.toml").read_text()
    head = (
        case.split("[load]")[0]
        .replace("elements_upper = [8, 8, 4]", "elements_upper = [3, 3, 1]")
        .replace("elements_lower = [7, 7, 4]", "elements_lower = [2, 2, 1]")
        .replace("degree = 2", "degree = 1", 1)
    )
    sweep = WORK / "degree_1_sweep.toml"
    sweep.write_text(
        head + "[sweep]\npressures = [1.0e5]\nfluxes = 1.0e6\ncontact_temperatures = 293.15\n"
    )
    table = WORK / "degree_1.h5"
    table.unlink(missing_ok=True)
    run = subprocess.run(
        [TCGEN, "sweep", "--progress", "quiet", "-o", str(table), str(sweep)],
        check=True, capture_output=True, text=True,
    )
    printed = [l[len("caution: "):] for l in run.stderr.splitlines() if l.startswith("caution: ")]
    assert [c.split(":")[0] for c in printed] == [
        "degree 1 in 3D",
        "the upper surface's fit on the case mesh misses it by up to 150.0 % of its RMS (1.500e-6 m)",
    ], run.stderr
    with xr.open_dataset(table) as ds:
        assert ds.attrs["cautions"].splitlines() == printed
        assert int(ds.attrs["dimension"]) == 3
    out = subprocess.run(
        [PYTHON, str(ROOT / "scripts/inspect_table.py"), str(table)],
        check=True, capture_output=True, text=True,
    ).stdout
    assert all(f"caution: {c}" in out for c in printed), out
    with xr.open_dataset(DEMO) as ds:
        assert "cautions" not in ds.attrs


def test_nightly_builds_tables_plots_and_laws():
    out = WORK / "nightly"
    subprocess.run(["rm", "-rf", str(out)], check=True)
    env = dict(os.environ, TCGEN=TCGEN, PYTHON=PYTHON)
    subprocess.run(
        ["bash", str(ROOT / "scripts/nightly.sh"), str(out), str(ROOT / "tables/reference.toml")],
        check=True, env=env, capture_output=True,
    )
    for suffix in (".h5", ".png", ".tclaw"):
        assert (out / f"reference{suffix}").stat().st_size > 0
    check_table(out / "reference.h5", ROOT / "tables/reference.toml")


def test_slurm_roles_shard_and_merge():
    out = WORK / "slurm"
    subprocess.run(["rm", "-rf", str(out)], check=True)
    out.mkdir(parents=True)
    table = out / "t.h5"
    base = dict(os.environ, TCGEN=TCGEN, CONFIG=str(ROOT / "tables/reference.toml"), OUTPUT=str(table), SHARDS="2")
    for i in range(2):
        env = dict(base, TCGEN_SLURM_ROLE="shard", SLURM_ARRAY_TASK_ID=str(i))
        subprocess.run(["bash", str(ROOT / "scripts/slurm_sweep.sh")], check=True, env=env, capture_output=True)
    subprocess.run(
        ["bash", str(ROOT / "scripts/slurm_sweep.sh")], check=True, env=dict(base, TCGEN_SLURM_ROLE="merge"),
        capture_output=True,
    )
    check_table(table, ROOT / "tables/reference.toml")
    ref = xr.open_dataset(ROOT / "tables/reference.h5")
    got = xr.open_dataset(table)
    np.testing.assert_allclose(got["jump"].values, ref["jump"].values, rtol=1e-6)
