"""`tcgen solve --vtk DIR` read by meshio (issue 14 item 3): the interface
is an unstructured grid of line cells, the bodies of quadrilaterals; every
file carries the applied loads as field data; the written Cauchy stress of
the two-phase self-consistent method balances the applied pressure over
the external faces; series.pvd lists every file with the pressure as time.
3D (issue 12 item 7): hexahedra for the bodies, quadrilaterals for the
interface.
Run through tests/python/run.sh (it sets TCGEN_BIN)."""

import os
import pathlib
import re
import subprocess
import tomllib
import xml.etree.ElementTree as ET

import meshio
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
TCGEN = os.environ.get("TCGEN_BIN", str(ROOT / "target/release/tcgen"))


def run(tmp_path, table, settings):
    """`tcgen solve --vtk` of `tables/<table>` with the lines `key = value` of
    `settings` replaced; the output directory and the case text."""
    text = (ROOT / "tables" / table).read_text()
    for key, value in settings:
        text, n = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value}", text)
        assert n == 1, key
    case = tmp_path / "case.toml"
    case.write_text(text)
    out = tmp_path / "vtk"
    subprocess.run([TCGEN, "solve", str(case), "--vtk", str(out)], check=True, capture_output=True)
    return out, text


def solve(tmp_path):
    """`tcgen solve --vtk` of tables/sinusoid_on_flat.toml on the coarse mesh
    of generator/tests/suite/vtk_output.rs, at 1 and 10 kPa."""
    out, text = run(
        tmp_path,
        "sinusoid_on_flat.toml",
        [
            ("elements_upper", "[12, 6]"),
            ("elements_lower", "[10, 5]"),
            ("pressures", "[1.0e3, 1.0e4]"),
            ("method", '"two-phase-self-consistent"'),
        ],
    )
    return out, tomllib.loads(text)["sample"]["width"]


def row_mean(mesh, values, row):
    """Trapezoidal mean over the deformed x of `values` along grid row `row`."""
    nx = int(mesh.field_data["grid_dimensions"].ravel()[0])
    x = mesh.points[row * nx : (row + 1) * nx, 0]
    v = values[row * nx : (row + 1) * nx]
    return float(np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(x)) / (x[-1] - x[0]))


def test_meshio_reads_every_file_and_the_stress_balances(tmp_path):
    out, width = solve(tmp_path)
    for k, pressure in enumerate([1.0e3, 1.0e4]):
        iface = meshio.read(out / f"p{k:03}_interface.vtu")
        assert [c.type for c in iface.cells] == ["line"]
        n = len(iface.points)
        assert iface.cells[0].data.shape == (n - 1, 2)
        for name in ["contact_pressure", "weighted_gap", "lumped_area", "interface_heat_flux", "thermal_lumped_area", "temperature_jump"]:
            assert iface.point_data[name].size == n, name
        force = np.sum(iface.point_data["contact_pressure"] * iface.point_data["lumped_area"])
        assert abs(force / width - pressure) < 3e-3 * pressure
        for body in ["lower", "upper"]:
            m = meshio.read(out / f"p{k:03}_{body}.vtu")
            assert [c.type for c in m.cells] == ["quad"]
            nx, ny = (int(v) for v in m.field_data["grid_dimensions"].ravel())
            assert m.points.shape == (nx * ny, 3)
            assert m.point_data["cauchy_stress"].shape == (nx * ny, 9)
            for f, value in [("applied_pressure", pressure), ("applied_flux", 1.0e6), ("contact_temperature", 293.15)]:
                assert m.field_data[f].ravel()[0] == value, f
            assert m.field_data["point_index"].ravel()[0] == k
            row = ny - 1 if body == "upper" else 0
            syy = row_mean(m, m.point_data["cauchy_stress"][:, 4], row)
            qy = row_mean(m, m.point_data["heat_flux"][:, 1], row)
            # Measured at most 6.7e-4 and 1.6e-5 (generator/tests/suite/vtk_output.rs).
            assert abs(syy + pressure) < 2e-3 * pressure, (body, syy)
            assert abs(qy + 1.0e6) < 5e-4 * 1.0e6, (body, qy)


def test_collection_lists_every_file(tmp_path):
    out, _ = solve(tmp_path)
    root = ET.parse(out / "series.pvd").getroot()
    assert root.get("type") == "Collection"
    sets = [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]
    assert sets == [
        (p, f"p{k:03}_{b}.vtu") for k, p in enumerate([1.0e3, 1.0e4]) for b in ["lower", "upper", "interface"]
    ]
    assert all((out / f).is_file() for _, f in sets)


def test_meshio_reads_a_3d_case(tmp_path):
    """The coarse egg box on a flat of tables/egg_box_on_flat.toml (3 x 3 x 1
    and 2 x 2 x 1 elements, as generator/tests/suite/sweep_cli.rs) at 100 kPa."""
    out, _ = run(
        tmp_path,
        "egg_box_on_flat.toml",
        [("elements_upper", "[3, 3, 1]"), ("elements_lower", "[2, 2, 1]"), ("pressures", "[1.0e5]")],
    )
    for body in ["lower", "upper"]:
        m = meshio.read(out / f"p000_{body}.vtu")
        assert [c.type for c in m.cells] == ["hexahedron"]
        nx, ny, nz = (int(v) for v in m.field_data["grid_dimensions"].ravel())
        assert m.field_data["dimension"].ravel()[0] == 3
        assert m.points.shape == (nx * ny * nz, 3)
        assert m.cells[0].data.shape == ((nx - 1) * (ny - 1) * (nz - 1), 8)
        assert m.point_data["cauchy_stress"].shape == (nx * ny * nz, 9)
        assert m.point_data["heat_flux"].shape == (nx * ny * nz, 3)
    iface = meshio.read(out / "p000_interface.vtu")
    assert [c.type for c in iface.cells] == ["quad"]
    nu, nv = (int(v) for v in iface.field_data["grid_dimensions"].ravel())
    assert iface.cells[0].data.shape == ((nu - 1) * (nv - 1), 4)
    assert iface.point_data["contact_pressure"].size == nu * nv
    # The lumped heat flow is -|h| W^2 to the solver tolerance.
    assert abs(iface.field_data["interface_heat_flow"].ravel()[0] + 1.0e6 * 1.0e-10) < 1e-9 * 1.0e-4
