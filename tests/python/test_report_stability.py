"""scripts/report.py's section for `slipfront stability` (issue 40 item 5, the growth-rate plot; docs/output.md
"stability.h5"): the figure from growth_rates.csv, one verdict per channel and one effect row per coupled channel, every
number read from the files, no row in the limits table; check_report.py accepts the report.

The files are fixtures written here in the verb's layout (a stability.h5 with /meta and /stability, and the CSV beside
it), so every rate is known; the report runs as `slipfront report` runs it (scripts/report.py DIR, one worker)."""
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
REPORT = os.path.join(ROOT, "scripts", "report.py")
CHECK = os.path.join(ROOT, "scripts", "check_report.py")
KH = np.array([0.5, 1.0, 2.0])
H, CP = 4.0, 200.0


def channel(fastest, resolved, check, converged, roundoff=1e-5, label=None, scene=0, length=0.0):
    """One /stability/<group> of the verb: rates per kH (complex), the row check on 16, 32, 64 rows at the fastest kH."""
    f, r, c = (np.asarray(v, dtype=complex) for v in (fastest, resolved, check))
    return {"fastest": f, "resolved": r, "check": c, "converged": converged, "roundoff": np.full(KH.size, roundoff),
            "label": label, "scene": scene, "length": length, "check_kH": float(KH[int(np.argmax(f.real))])}


def fixture_channels(inst_top=1.5):
    """The four channels: uncoupled and re-attachment stable (Re s within round-off), instantaneous growing at `inst_top`
    (kH = 2, not converged), regularised at 0.6 (kH = 0.5, the waveguide mode, converged)."""
    w = 1.6 * CP / H  # omega H/c_p = 1.6
    return {
        "uncoupled": channel([-1e-7 + 1j * w, -2e-6, -3e-6], [-0.3, -0.2, -1e-4 + 97j], [-1e-7, 1e-6, 2e-6], 0),
        "reattachment": channel([-2e-7 + 1j * w, 3e-6 + 95j, -1e-6], [-0.31, -0.19, -2e-4 + 97j], [3e-6, 1e-6, 4e-6], 0,
                                scene=1),
        "instantaneous": channel([0.9 + 400j, 1.2 + 500j, inst_top + 400j], [0.02, 0.9, 0.7],
                                 [inst_top + 400j, 1.3 + 700j, 1.0 + 1000j], 0),
        "regularised": channel([0.6 + 1j * w, 0.1, 0.02], [0.6 + 1j * w, 0.1, 0.02],
                               [0.6 + 1j * w, 0.59 + 1j * w, 0.588 + 1j * w], 1, label="instantaneous L=0.03",
                               length=0.03),
    }


def write_fixture(d, channels, status="complete", csv=True):
    """DIR/inplane_stability/stability.h5 and growth_rates.csv as `slipfront stability` writes them."""
    os.makedirs(d, exist_ok=True)
    with h5py.File(os.path.join(d, "stability.h5"), "w") as f:
        meta = f.create_group("meta")
        for k, v in (("git_commit", "0123456789ab"), ("created_utc", "2026-11-28T00:00:00Z"), ("status", status),
                     ("scene", "inplane_stability")):
            meta.attrs[k] = v
        f.create_group("config").attrs["toml"] = 'scene = "inplane_stability"\n'
        s = f.create_group("stability")
        for k, v in (("v0", 2.0), ("v_m", 1.0206), ("normal_load", 0.3), ("exponent", 1.0),
                     ("coupling_coefficient", 0.2059), ("height", H), ("shear_speed", 100.0), ("pressure_speed", CP),
                     ("max_frequency", 4 * CP / H), ("rows", 16)):
            s.attrs[k] = v
        s.attrs["scene_channel"] = "reattachment"
        s["kH"] = KH
        for g, c in channels.items():
            grp = s.create_group(g)
            grp.attrs["label"] = c["label"] or g
            for k in ("scene", "converged"):
                grp.attrs[k] = c[k]
            grp.attrs["coupled"] = int(g != "uncoupled")
            grp.attrs["instantaneous"] = int(g in ("instantaneous", "regularised"))
            grp.attrs["relaxation_length"] = c["length"]
            grp.attrs["check_kH"] = c["check_kH"]
            for name in ("fastest", "resolved", "check"):
                grp[f"{name}_re"], grp[f"{name}_im"] = c[name].real, c[name].imag
            grp["roundoff"] = c["roundoff"]
            grp["check_rows"] = np.array([16.0, 32.0, 64.0])
    if csv:
        with open(os.path.join(d, "growth_rates.csv"), "w") as f:
            f.write("channel,kH,kind,re_s,im_s\n")
            for g, c in channels.items():
                for k, kh in enumerate(KH):
                    for kind, name in (("theory_resolved", "resolved"), ("theory_max", "fastest")):
                        s = c[name][k]
                        f.write(f"{c['label'] or g},{kh!r},{kind},{s.real!r},{s.imag!r}\n")


def report(root):
    env = dict(os.environ, SLIPFRONT_REPORT_JOBS="1")
    subprocess.run([sys.executable, REPORT, str(root)], check=True, env=env, capture_output=True)
    return (root / "report.md").read_text()


def verdict(md, channel_name):
    m = re.search(r"^- \*\*" + re.escape(channel_name) + r"[^*]*\*\*: (.*)$", md, re.M)
    assert m, f"no verdict for {channel_name}"
    return m.group(1)


def test_stability_section_figure_verdicts_and_effect_rows(tmp_path):
    write_fixture(tmp_path / "inplane_stability", fixture_channels())
    md = report(tmp_path)
    assert "## Growth rates of homogeneous sliding under the normal-load coupling (`inplane_stability`)" in md
    fig = re.search(r"!\[inplane_growth_rates.png\]\(([^)]+)\)", md)
    assert fig and os.path.getsize(tmp_path / fig.group(1)) > 0
    re_v = verdict(md, "re-attachment channel (the scene's)")
    assert re_v.startswith("homogeneous sliding stable (max Re s over kH = 0.5 .. 2: 3e-06 at kH = 1, omega H/c_p = 1.9, within the eigensolver's round-off 1e-05; least-damped resolved mode -0.0002 at kH = 2)")
    inst = verdict(md, "instantaneous channel")
    assert inst.startswith("unstable, max rate 1.5 at kH = 2, omega H/c_p = 8; ill-posed: the fastest mode moves with the "
                           "rows (on 16, 32, 64 rows at kH = 2: Re s 1.5, 1.3, 1, omega H/c_p 8, 14, 20)")
    reg = verdict(md, "regularised instantaneous channel, L = 0.03")
    assert reg.startswith("unstable, max rate 0.6 at kH = 0.5, omega H/c_p = 1.6; converged in the rows (on 16, 32, 64 "
                          "rows at kH = 0.5: Re s 0.6, 0.59, 0.588")
    # the effects table holds one row per coupled channel; the limits table none (the coupling is an effect)
    assert "### Limits that must hold\n\n0 rows" in md
    effects = [ln for ln in md.split("\n") if ln.startswith("| normal-load coupling")]
    assert len(effects) == 3
    assert "| uncoupled -1e-07 | 1.5 | +1.5 | unstable; ill-posed: not converged in the rows |" in effects[1]
    assert "stable (within round-off)" in effects[0]
    assert "unstable; converged in the rows" in effects[2]
    r = subprocess.run([sys.executable, CHECK, str(tmp_path / "report.md")], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_stability_verdicts_follow_the_file(tmp_path):
    """A faster instantaneous mode and a re-attachment mode above round-off change the verdicts: read, not written in."""
    ch = fixture_channels(inst_top=2.5)
    ch["reattachment"]["fastest"][1] = 0.02 + 95j  # above the round-off 1e-5: grows
    ch["reattachment"]["check"][:] = [0.02 + 95j, 0.0199 + 95j, 0.0198 + 95j]
    ch["reattachment"]["converged"] = 1
    ch["reattachment"]["check_kH"] = 1.0
    write_fixture(tmp_path / "inplane_stability", ch)
    md = report(tmp_path)
    assert verdict(md, "instantaneous channel").startswith("unstable, max rate 2.5 at kH = 2")
    assert verdict(md, "re-attachment channel (the scene's)").startswith(
        "unstable, max rate 0.02 at kH = 1, omega H/c_p = 1.9; converged in the rows")


def test_stability_without_its_csv_says_so(tmp_path):
    """An interrupted computation writes no growth_rates.csv: the section says there is no figure, the rest stands."""
    write_fixture(tmp_path / "inplane_stability", fixture_channels(), status="interrupted", csv=False)
    md = report(tmp_path)
    assert "No `growth_rates.csv` beside it" in md
    assert "status interrupted" in md
    assert "inplane_growth_rates.png" not in md


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
