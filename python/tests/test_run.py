"""run(), progress, Ctrl-C, resume from a checkpoint; open() and to_xarray() on a run's file."""
import os
import signal

import h5py
import numpy as np
import pytest

import slipfront
from conftest import tiny_config


def test_run_returns_its_results(tiny, tmp_path):
    ticks = []
    res = slipfront.run(tiny, out=tmp_path / "o", progress=ticks.append)
    assert res.status == "complete" and res.models == ["continuum"]
    c = res["continuum"]
    # t* of the edge-loaded interface (docs/model.md §1): (K + sqrt(alpha mu)) / (alpha K v_d) = 25.71 on a
    # grid of dx = 1 (the paper's dx = 0.5 gives it within 1%: here within 2%)
    t_star = (2.5 + np.sqrt(1.05 * 300.0)) / (1.05 * 2.5 * 0.3)
    assert abs(c.events["t_star"] - t_star) / t_star < 0.02
    assert c.snapshots["A"].shape == (len(c.snapshots["t"]), len(c.x)) == (9, 61)
    assert np.array_equal(c.series["t"], np.arange(0, 40.0001, 0.5)) or len(c.series["t"]) == 81
    assert res.provenance["scene"] == "tiny" and res.config["bulk"]["length"] == 60.0
    assert res.scalars["continuum"]["steps"] == 13892
    # progress: the program's JSON lines, t growing, of this scene and model
    assert ticks and all(t["model"] == "continuum" and t["t_end"] == 40 for t in ticks)
    assert [t["t"] for t in ticks] == sorted(t["t"] for t in ticks)


def test_models_argument_and_alongside(tmp_path):
    scene = slipfront.Scene.from_dict(tiny_config()).set("discrete.contacts_per_site", 100)
    res = slipfront.run(scene, models=["continuum", "discrete"], out=tmp_path / "o", progress=False)
    assert res.models == ["continuum", "discrete"]
    assert "t_star_rel_diff" in res.compare
    ds = res.to_xarray("snapshots")
    assert ds["A"].dims == ("model", "t", "x") and list(ds["model"].values) == ["continuum", "discrete"]
    with h5py.File(res.path) as f:
        assert np.array_equal(ds["A"].sel(model="discrete").values, f["discrete/snapshots/A"][()])


def test_existing_results_are_kept_unless_force(tiny, tmp_path):
    slipfront.run(tiny, out=tmp_path / "o", progress=False)
    with pytest.raises(slipfront.ConfigError, match="exists"):
        slipfront.run(tiny, out=tmp_path / "o", progress=False)
    assert slipfront.run(tiny, out=tmp_path / "o", force=True, progress=False).status == "complete"


def test_tqdm_bar(tiny, tmp_path, capsys):
    pytest.importorskip("tqdm")
    slipfront.run(tiny, out=tmp_path / "o", progress=True)
    assert "tiny continuum" in capsys.readouterr().err  # the bar's label


def test_sigint_from_python_returns_the_interrupted_result(long_scene, tmp_path):
    """A KeyboardInterrupt in Python (SIGINT to this process, as Ctrl-C in a terminal or a notebook's
    interrupt) is forwarded to the program once: it writes its partial results, run() returns them."""
    def press_ctrl_c(tick):
        if tick["t"] > 0:
            os.kill(os.getpid(), signal.SIGINT)
    res = slipfront.run(long_scene, out=tmp_path / "o", progress=press_ctrl_c)
    assert res.completed.interrupted and res.completed.code == 130
    assert res.status == "interrupted"
    c = res["continuum"]
    assert c.status == "interrupted" and c.message.startswith("stopped at t = ")
    assert 0 < c.attrs["t_reached"] < 140.0


def test_resume_from_checkpoint_equals_the_uninterrupted_run(long_scene, tmp_path):
    # cfl 0.125: ~170 000 steps (~0.8 s), so the stop sent at the first progress line (always printed at once)
    # lands midway on a fast machine too; at t_end = 30 and cfl 0.5 the run could end before a line with t > 12 came
    scene = long_scene.copy().set("time.t_end", 60.0).set("time.cfl", 0.125).set("output.snapshot_dt", 5.0)
    whole = slipfront.run(scene, out=tmp_path / "whole", progress=False)
    part = slipfront.run(scene, out=tmp_path / "part", checkpoint_every=10.0, progress=False,
                         stop_after=lambda tick: True)
    assert part.status == "interrupted" and (part.out / "checkpoint.bin").is_file()
    assert 0 < part["continuum"].attrs["t_reached"] < 60.0
    done = slipfront.resume(part, progress=False)
    assert done.status == "complete"
    for name in ("A", "sigma_bar", "u", "v"):
        assert np.array_equal(done["continuum"].snapshots[name], whole["continuum"].snapshots[name])
    a, b = done["continuum"].events, whole["continuum"].events
    assert a.keys() == b.keys() and np.array_equal([a[k] for k in a], [b[k] for k in a], equal_nan=True)
    assert np.isfinite(a["t_star"])


def test_open_refuses_a_flipped_byte(tiny, tmp_path):
    res = slipfront.run(tiny, out=tmp_path / "o", progress=False)
    data = bytearray(res.path.read_bytes())
    for where in (600, len(data) // 2, len(data) - 1, 20):  # HDF5 part (start, middle, end), the block's text
        flipped = bytearray(data)
        flipped[where] ^= 0x01
        bad = tmp_path / ("bad%d.h5" % where)
        bad.write_bytes(flipped)
        with pytest.raises(slipfront.ChecksumError):
            slipfront.open(bad)
    (tmp_path / "short.h5").write_bytes(data[:-1])
    with pytest.raises(slipfront.ChecksumError, match="checksum fails"):
        slipfront.open(tmp_path / "short.h5")
    assert slipfront.open(res.path).status == "complete"
    assert slipfront.open(tmp_path / "o").path == res.path  # a directory holding one file


def test_open_a_file_without_checksum(tmp_path):
    with h5py.File(tmp_path / "plain.h5", "w") as f:
        f.create_group("meta").attrs["status"] = "complete"
    with pytest.raises(slipfront.ChecksumError, match="no checksum"):
        slipfront.open(tmp_path / "plain.h5")
    assert slipfront.open(tmp_path / "plain.h5", verify=False).status == "complete"


def test_to_xarray_round_trips_the_fields(tiny, tmp_path):
    pytest.importorskip("xarray")
    res = slipfront.run(tiny, out=tmp_path / "o", progress=False)
    c = res["continuum"]
    with h5py.File(res.path) as f:
        g = f["continuum"]
        snaps = c.to_xarray("snapshots")
        assert set(snaps.data_vars) == {k for k in g["snapshots"] if k != "t"}
        for name, var in snaps.data_vars.items():
            assert var.dims == ("t", "x")
            assert np.array_equal(var.values, g["snapshots"][name][()])
            assert var.attrs["description"] == g["snapshots"][name].attrs["description"]
        assert np.array_equal(snaps["t"].values, g["snapshots/t"][()]) and np.array_equal(snaps["x"].values, g["x"][()])
        series = c.to_xarray("series")
        for name, var in series.data_vars.items():
            assert var.dims == ("t",) and np.array_equal(var.values, g["series"][name][()], equal_nan=True)
            assert var.attrs["description"] == g["series"][name].attrs["description"]
    with pytest.raises(KeyError, match="bulk"):
        c.to_xarray("bulk")


def test_strip_bulk_fields_have_y(tmp_path):
    pytest.importorskip("xarray")
    scene = slipfront.Scene.from_dict(tiny_config(time__t_end=2.0)).set("bulk.height", 8.0).set("output.bulk_dt", 1.0)
    res = slipfront.run(scene, out=tmp_path / "o", progress=False)
    ds = res["continuum"].to_xarray("bulk")
    with h5py.File(res.path) as f:
        assert ds["u"].dims == ("t", "y", "x")
        assert np.array_equal(ds["tau_yz"].values, f["continuum/bulk/tau_yz"][()])
        assert np.array_equal(ds["y"].values, f["continuum/bulk/y"][()])
