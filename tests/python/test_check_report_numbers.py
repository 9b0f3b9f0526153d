"""scripts/check_report.py --numbers / --unmarked (docs/results.md, "Quoting a number"): a number a docs page quotes
from a run is checked against the run's files, or dated; a drifted number and an unmarked one both fail.

The run is a fixture written here (an HDF5 scene file, a study table, the report's limits CSV and a minimal
report.md), so the values are known exactly; the pages are small Markdown files."""
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECK = os.path.join(ROOT, "scripts", "check_report.py")
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import check_report  # noqa: E402

T_STAR = 25.6707  # the fixture's fig1 t*: "25.67" is right, "25.68" has drifted


@pytest.fixture()
def run(tmp_path):
    """A run directory: fig1/results.h5, studies/s/study.h5 (a table), summary_limits.csv, report.md."""
    (tmp_path / "fig1").mkdir()
    with h5py.File(tmp_path / "fig1" / "results.h5", "w") as f:
        f.create_group("continuum/events").attrs["t_star"] = T_STAR
    (tmp_path / "studies" / "s").mkdir(parents=True)
    with h5py.File(tmp_path / "studies" / "s" / "study.h5", "w") as f:
        t = f.create_group("study/tables/grid")
        t["N"] = np.array([100.0, 1000.0, 100.0])
        t["alpha_minus_1"] = np.array([0.03, 0.03, 0.05])
        t["fraction"] = np.array([0.0, 0.09375, 0.5])
    (tmp_path / "summary_limits.csv").write_text(
        "limit,observable,statistic,verdict,file\n"
        "agent contact statistics,\"contacts: contact lifetimes, tip\",\"KS distance 0.0286; p = 2.2e-05\",FAIL,x\n"
        "agent contact statistics,\"contacts: contact ages, ahead\",\"KS distance 0.0012; p = 0.6\",pass,x\n")
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "a.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 64)
    (tmp_path / "report.md").write_text("# report\n\n![a](figures/a.png)\n\n### Limits that must hold\n\n"
                                        "| limit | verdict | file |\n| --- | --- | --- |\n")
    return tmp_path


def page(tmp_path, text, name="page.md"):
    p = tmp_path / "docs" / name
    p.parent.mkdir(exist_ok=True)
    p.write_text(text, encoding="utf-8")
    return p


def check(run_dir, *pages):
    out = subprocess.run([sys.executable, CHECK, str(run_dir / "report.md"), "--numbers", *map(str, pages)],
                         capture_output=True, text=True)
    return out.returncode, out.stdout + out.stderr


def unmarked(*pages):
    out = subprocess.run([sys.executable, CHECK, "--unmarked", *map(str, pages)], capture_output=True, text=True)
    return out.returncode, out.stdout + out.stderr


RUN = "<!-- run: fig1/results.h5 f['continuum/events'].attrs['t_star'] -->"


def test_a_checked_number_passes_and_a_drifted_one_fails(run):
    good = page(run, f"# Fig. 1\n\nFirst yield at `t* = 25.67`{RUN}, and 25.7{RUN} rounded.\n")
    code, out = check(run, good)
    assert code == 0, out
    assert "2 numbers quoted in" in out and "0 differ" in out
    drifted = page(run, f"# Fig. 1\n\nFirst yield at `t* = 25.68`{RUN}.\n", "drifted.md")
    code, out = check(run, drifted)
    assert code == 1
    assert "drifted.md:3: 25.68 (run marker), but fig1/results.h5 gives 25.6707" in out


def test_an_unmarked_number_fails_with_and_without_a_run(run):
    p = page(run, "# Fig. 1\n\nFirst yield at `t* = 25.67`; the tier ran 340 tests in 3 min 29 s, 12× faster; "
                  "`N^-0.55`.\n")
    code, out = check(run, p)
    assert code == 1
    for text in ("'t* = 25.67'", "'340 tests'", "'3 min'", "'29 s'", "'12×'", "'^-0.55'"):
        assert text in out, (text, out)
    code, out = unmarked(p)
    assert code == 1 and "an event time or speed quoted without a check, a citation or a date: 't* = 25.67'" in out


def test_markers_date_a_section_a_block_or_a_line(run):
    p = page(run, "# A\n<!-- measured: 1a2b3c4, 2026-11-24 -->\n\nt* = 25.1 and 4 min.\n\n## A.1\n\nc = 58.80\n\n"
                  "# B\n\nc_min = 11.28 <!-- not from a run: an example -->\n\n"
                  "<!-- measured: 2026-11-25 -->\n```\nt_hat = 108.7, 0.3 s\n```\n\nt^ = 99.9\n")
    code, out = unmarked(p)
    assert code == 1
    assert out.count("a date: '") == 1 and "'t^ = 99.9'" in out  # the only number outside every marker


def test_a_bad_marker_fails(run):
    for what in ("last week", "1234567 runs", "acceded"):  # neither a date nor a commit
        no_date = page(run, f"# A\n<!-- measured: {what} -->\n\nt* = 25.1\n", "a.md")
        code, out = unmarked(no_date)
        assert code == 1 and f"names no commit or date: '{what}'" in out
    orphan = page(run, f"# A\n\nfirst yield{RUN} came early\n", "b.md")
    code, out = unmarked(orphan)
    assert code == 1 and "a 'run' marker not right after a number" in out


def test_a_marker_in_code_is_an_example_not_a_marker(run):
    p = page(run, "# A\n\nWrite `` `t* = 25.1`<!-- measured: 2026-11-24 --> `` to date it.\n")
    code, out = unmarked(p)
    assert code == 1 and "'t* = 25.1'" in out


def test_study_tables_and_report_rows_in_expressions(run):
    cell = "<!-- run: studies/s/study.h5 cell('grid', 'fraction', alpha_minus_1=0.03, N=1000) -->"
    p_ks = "<!-- run: summary_limits.csv after(row('contacts: contact lifetimes, tip')['statistic'], 'p =') -->"
    fails = "<!-- run: summary_limits.csv sum(r['verdict'] == 'FAIL' for r in rows) -->"
    total = "<!-- run: summary_limits.csv len(rows) -->"
    p = page(run, f"# A\n\nfraction 0.09{cell}, p = 2.2e-5{p_ks}, 1{fails} of 2{total} rows failing\n")
    code, out = check(run, p)
    assert code == 0, out
    ambiguous = page(run, "# A\n\n0.5<!-- run: studies/s/study.h5 cell('grid', 'fraction', alpha_minus_1=0.03) -->\n",
                     "amb.md")
    code, out = check(run, ambiguous)
    assert code == 1 and "2 rows of grid" in out


def test_the_shapes_leave_ordinary_text_alone():
    text = ("# A\n\nA grid of 601 × 35 nodes on 12 rows, `dx = 0.5`, `N = 10⁴`, `w = 0.2`, `N^-1/2`, `10^4`, "
            "see §3.1 and model.md §10.\n")
    assert check_report.scan_page("x.md", text)[2] == []
