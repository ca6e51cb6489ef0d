"""docs/examples/table2.py runs against the test daemon: Laine & Aila's Table 2 within the
rounding of the printed digits, and its figures."""

import csv
import os
import subprocess
import sys

from PIL import Image

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "examples",
                      "table2.py")


def test_table2_example(daemon, tmp_path):
    out = subprocess.run([sys.executable, SCRIPT, "--socket", daemon.socket_path, "--out",
                          str(tmp_path)], capture_output=True, text=True, timeout=240)
    assert out.returncode == 0, out.stdout + out.stderr
    with open(tmp_path / "table2.csv") as f:
        rows = list(csv.DictReader(f))
    assert {r["pattern"] for r in rows} == {"grid-2x2", "rgss", "quincunx", "flipquad", "fliptri"}
    for r in rows:
        assert abs(float(r["e2"]) - float(r["published_e2"])) <= 5e-4
    assert "P(4,1+,2)" in out.stdout
    for name in ("e2_vs_spp.png", "trace.png"):
        with Image.open(tmp_path / name) as im:
            assert im.size == (960, 600)
