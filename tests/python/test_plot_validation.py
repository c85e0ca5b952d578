"""scripts/plot_validation.py on a small synthetic data directory (the
format `tcgen verify --data` writes: checks.json and `<case>.csv` with
columns series,x_label,y_label,x,y), and end to end on the data of one fast
case written by tcgen. Run through tests/python/run.sh."""

import csv
import json
import os
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts/plot_validation.py"
TCGEN = os.environ.get("TCGEN_BIN", str(ROOT / "target/release/tcgen"))
PYTHON = os.environ.get("TCGEN_PYTHON", "python3")


def write_case(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["series", "x_label", "y_label", "x", "y"])
        for r in rows:
            w.writerow(r)


def run_script(data, out):
    r = subprocess.run(
        [PYTHON, str(SCRIPT), str(data), str(out)], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stderr
    return r.stdout.split()


def assert_png(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    assert 1_000 < len(data) < 100_000, (path, len(data))


def test_every_case_gets_a_png(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    checks = [
        {"case": "mms_conduction_p1", "pass": True},
        {"case": "hbp_validation", "pass": True},
        {"case": "hbp_validation", "pass": False},
        {"case": "broken", "error": "boom", "pass": False},
    ]
    (data / "checks.json").write_text(json.dumps(checks))
    hs = [0.25, 0.125, 0.0625]
    write_case(
        data / "mms_conduction_p1.csv",
        [("L2 temperature", "h = 1/n", "error norm", h, h**2) for h in hs]
        + [("H1 temperature", "h = 1/n", "error norm", h, h) for h in hs],
    )
    ps = [1e3, 1e4, 1e5]
    write_case(
        data / "hbp_validation.csv",
        [("constraint: two-phase", "pressure (Pa)", "macroscopic jump (K)", p, 1e5 / p) for p in ps]
        + [("resistive: two-phase", "pressure (Pa)", "θHBP(1) − θ(1) (K)", p, 0.1) for p in ps],
    )
    # A case the script knows nothing about (e.g. `lateral`): plotted generically,
    # names with commas survive the CSV quoting.
    write_case(
        data / "lateral.csv",
        [("PR, free", "height (μm)", "jump (K)", h, 2 * h) for h in (1, 2, 4)],
    )
    out = tmp_path / "png"
    written = run_script(data, out)
    names = sorted(pathlib.Path(w).name for w in written)
    assert names == ["checks.md", "hbp_validation.png", "lateral.png", "mms.png"]
    for n in names[1:]:
        assert_png(out / n)
    table = (out / "checks.md").read_text()
    assert "## hbp_validation" in table and "| FAIL |" in table and "boom" in table


def test_tcgen_data_plots(tmp_path):
    data, out = tmp_path / "data", tmp_path / "png"
    r = subprocess.run(
        [TCGEN, "verify", "--filter", "mms_conduction_p3", "--data", str(data)],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stdout + r.stderr
    checks = json.loads((data / "checks.json").read_text())
    assert checks and all(c["case"] == "mms_conduction_p3" and c["pass"] for c in checks)
    with open(data / "mms_conduction_p3.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert {r["series"] for r in rows} == {"L2 temperature", "H1 temperature"}
    assert all(float(r["y"]) > 0 for r in rows)
    run_script(data, out)
    assert_png(out / "mms.png")
