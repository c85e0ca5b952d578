"""scripts/plot_calculix_interface.py on a small synthetic CalculiX model
(the *NODE block of a deck and the nodal temperatures of two steps in the
.dat format of `*NODE PRINT`): the jumps it prints are the temperature
differences at the interface, and it writes a PNG. Run through
tests/python/run.sh."""

import os
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts/plot_calculix_interface.py"
PYTHON = os.environ.get("TCGEN_PYTHON", "python3")


def test_jumps_and_picture(tmp_path):
    # Two blocks of one element layer each, z = 0..1 and 1..2: the upper
    # block's bottom nodes (9..12) coincide with the lower block's top (5..8).
    nodes, z_of = [], {}
    n = 0
    for z in (0.0, 1.0, 1.0, 2.0):
        for x, y in ((0, 0), (1, 0), (1, 1), (0, 1)):
            n += 1
            nodes.append(f"{n}, {x}, {y}, {z}")
            z_of[n] = z
    inp = tmp_path / "m.inp"
    inp.write_text("** model\n*NODE, NSET=NALL\n" + "\n".join(nodes)
                   + "\n*NODE PRINT, NSET=NALL\nNT\n")
    dat = []
    for step, jump in ((1, 1.5), (2, 1.25)):
        dat.append(f" temperatures for set NALL and time  {step:.7E}\n")
        for k in range(1, n + 1):
            t = 293.0 + z_of[k] * 2.0 + (jump if k > 8 else 0.0)
            dat.append(f"      {k}  {t:.6E}\n")
        dat.append("\n")
    (tmp_path / "m.dat").write_text("".join(dat))
    png = tmp_path / "m.png"
    r = subprocess.run([PYTHON, str(SCRIPT), str(inp), "--png", str(png)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert [float(v) for v in r.stdout.split()] == [1.5, 1.25]
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert 1_000 < len(data) < 200_000
