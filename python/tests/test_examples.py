"""The examples/ scripts run at their small sizes and produce their figures."""
import os
import subprocess
import sys

import pytest

from conftest import SOURCE


@pytest.mark.parametrize("script,figure", [("fig1.py", "fig1.png"), ("sweep.py", "sweep.png"),
                                           ("study_table.py", "study.png")])
def test_example(script, figure, tmp_path):
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, str(SOURCE / "examples" / script), "--small", "--out", str(out)],
                          cwd=tmp_path, capture_output=True, text=True, env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    png = out / figure
    assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 5000
    assert "figure:" in done.stdout
