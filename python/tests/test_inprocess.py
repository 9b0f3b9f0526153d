"""The in-process module (slipfront.Simulation): the program's run bit for bit, views that cannot dangle,
Ctrl-C, a drive history from arrays, checkpoints as bytes. Skipped when the module was not built."""
import gc
import os
import signal
import threading
import time
import weakref
from pathlib import Path

import numpy as np
import pytest

import slipfront
from conftest import tiny_config

if not list(Path(slipfront.__file__).parent.glob("_slipfront*.so")):
    pytest.skip("the in-process module was not built (pybind11-dev)", allow_module_level=True)


def test_module_imports_when_built():
    assert hasattr(slipfront, "Simulation")  # an ImportError of a built module is not hidden


def test_advance_equals_the_programs_run_bit_for_bit(tiny, tmp_path):
    for integrator in ("explicit", "implicit", "adaptive"):
        scene = tiny.copy().set("time.integrator", integrator)
        if integrator == "implicit":
            scene.set("time.dt", 0.02)
        res = slipfront.run(scene, out=tmp_path / integrator, progress=False)
        sim = slipfront.Simulation(scene, "continuum")
        assert sim.advance(until=12.5) > 0 and sim.time >= 12.5
        sim.advance(steps=7)
        sim.advance()  # to the end
        assert sim.done and sim.time == pytest.approx(40.0)
        c = res["continuum"]
        last = c.snapshots  # snapshot_dt = 5 divides t_end: the last row is the state at t_end ...
        assert last["t"][-1] == pytest.approx(40.0)
        if integrator != "adaptive":  # ... the stepper's own state (the adaptive one's: its dense output there)
            for name in ("A", "sigma_bar", "u", "v"):
                assert np.array_equal(getattr(sim, name), last[name][-1]), (integrator, name)
        out = sim.result()
        assert out["status"] == "complete" and out["scalars"]["steps"] == c.attrs["steps"] == sim.steps
        assert np.array_equal([out["events"][k] for k in c.events if k in out["events"]],
                              [c.events[k] for k in c.events if k in out["events"]], equal_nan=True)
        for group, columns in (("series", c.series), ("snapshots", c.snapshots)):
            assert out[group].keys() == columns.keys()
            for name, values in columns.items():
                assert np.array_equal(out[group][name], values, equal_nan=True), (integrator, group, name)


def test_views_survive_gc_and_keep_their_memory(tiny):
    sim = slipfront.Simulation(tiny)
    sim.advance(until=30.0)
    A, x = sim.A, sim.x
    ref = weakref.ref(sim)
    expected = A.copy()
    assert not A.flags.writeable
    with pytest.raises(ValueError):
        A[0] = 2.0
    del sim
    gc.collect()
    assert ref() is not None                    # the views hold the Simulation ...
    junk = [np.full(61, 7.0) for _ in range(1000)]  # ... and its memory: new allocations do not reuse it
    assert np.array_equal(A, expected) and x[-1] == 60.0
    del A, x, junk
    gc.collect()
    assert ref() is None                        # gone with its last view


def test_views_follow_advance_and_are_refused_once_closed(tiny):
    sim = slipfront.Simulation(tiny)
    v = sim.v
    assert np.all(v == 0.0)
    sim.advance(until=28.0)                     # after t* = 25.7 the edge slides
    assert v[0] > 0 and np.array_equal(v, sim.v)
    kept = v.copy()
    sim.close()
    assert sim.closed and np.array_equal(v, kept)  # an existing view keeps the last values
    for get in (lambda: sim.A, lambda: sim.advance(steps=1), lambda: sim.checkpoint(), lambda: sim.time):
        with pytest.raises(ValueError, match="gone"):
            get()


def test_errors_name_file_key_and_reason(tiny_file):
    scene = slipfront.Scene.from_toml(tiny_file).set("interface.eta", -1.0)
    with pytest.raises(slipfront.ConfigError) as e:
        slipfront.Simulation(scene)
    assert (e.value.file, e.value.key) == (str(tiny_file), "--set interface.eta")
    assert "got -1" in e.value.reason
    with pytest.raises(ValueError, match="unknown model"):
        slipfront.Simulation(scene.copy().set("interface.eta", 0.1), "quantum")


def test_ctrl_c_stops_between_steps(long_scene):
    sim = slipfront.Simulation(long_scene)
    timer = threading.Timer(0.05, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.advance()
    timer.join()
    t = sim.time
    assert 0 < t < 140.0 and not sim.done and np.isfinite(sim.A).all()
    sim.advance(steps=10)                        # and it goes on
    assert sim.time > t


def test_gil_is_released(long_scene):
    sim = slipfront.Simulation(long_scene)
    ticks = []
    worker = threading.Thread(target=lambda: sim.advance(until=60.0))
    worker.start()
    while worker.is_alive():
        ticks.append(time.monotonic())
        time.sleep(0.001)
    worker.join()
    assert len(ticks) > 10  # this thread ran while C++ stepped
    with pytest.raises(RuntimeError, match="already running"):
        busy = threading.Thread(target=lambda: sim.advance(until=140.0))
        busy.start()
        time.sleep(0.01)
        sim.advance(steps=1)
    busy.join()


def test_checkpoint_bytes_continue_bit_for_bit(tiny, tmp_path):
    whole = slipfront.Simulation(tiny)
    whole.advance()
    a = slipfront.Simulation(tiny)
    a.advance(until=20.0)
    data = a.checkpoint()
    assert data.startswith(b"slipfront-checkpoint 3\n")
    b = slipfront.Simulation(tiny, checkpoint=data)
    assert b.time == a.time and np.array_equal(b.sigma_bar, a.sigma_bar)
    b.advance()
    assert np.array_equal(b.u, whole.u) and np.array_equal(b.A, whole.A)
    # the bytes are a checkpoint file of the program: `slipfront run --restart` continues it to the same end
    (tmp_path / "cp.bin").write_bytes(data)
    res = slipfront.run(tiny, out=tmp_path / "o", restart=tmp_path / "cp.bin", progress=False)
    assert np.array_equal(res["continuum"].snapshots["u"][-1], whole.u)
    flipped = bytearray(data)
    flipped[len(flipped) // 2] ^= 1
    with pytest.raises(ValueError, match="checksum mismatch"):
        slipfront.Simulation(tiny, checkpoint=bytes(flipped))
    with pytest.raises(ValueError, match="another configuration"):
        slipfront.Simulation(tiny.copy().set("interface.kappa", 9.0), checkpoint=data)


VELOCITY_STEP = {
    "scene": "steps", "models": ["continuum"],
    "interface": {"alpha": 1.05, "kappa": 8.0, "eta": 0.1}, "bulk": {"rho": 0.01},
    "drive": {"loading": "imposed_rate", "v": [0.5], "switch_times": [0.0]},
    "time": {"t_end": 12.0, "dt": 0.002}, "output": {"series_dt": 0.002, "snapshot_dt": 0.0},
}


def test_drive_history_from_arrays_equals_the_same_history_in_the_file(tmp_path):
    times, rates = np.array([0.0, 4.0, 8.0]), np.array([0.5, 5.0, 0.5])
    sim = slipfront.Simulation(VELOCITY_STEP)
    A = sim.A
    sim.set_drive_history(times, rates)
    assert "switch_times = [0.0, 4.0, 8.0]" in sim.resolved_toml.replace("0.0, 4.0", "0.0, 4.0")
    sim.advance(until=5.0)
    assert sim.v[0] == 5.0 and A[0] < 0.5      # the view taken before the history follows the run
    sim.advance()
    out = sim.result()
    config = dict(VELOCITY_STEP, drive={"loading": "imposed_rate", "v": list(rates), "switch_times": list(times)})
    res = slipfront.run(config, out=tmp_path / "o", progress=False)
    for col in ("sigma", "A", "sigma_bar"):
        assert np.array_equal(out["series"][col], res["continuum"].series[col]), col
    with pytest.raises(ValueError, match="switch_times"):
        slipfront.Simulation(VELOCITY_STEP).set_drive_history([1.0, 0.5], [1.0, 2.0])
    with pytest.raises(ValueError, match="imposed_rate"):
        slipfront.Simulation(tiny_config()).set_drive_history([0.0], [1.0])


def test_cost_per_call_against_the_cli(tiny, tmp_path):
    """The cost of a call, measured in one run (printed; no bound asserted beyond 'the in-process call is
    cheaper than starting the program'): advance(steps=1) against `slipfront run` of a 1-step scene."""
    one = tiny.copy().set("time.t_end", 0.00288)  # one explicit step
    sim = slipfront.Simulation(tiny)
    n = 2000
    t0 = time.perf_counter()
    for _ in range(n):
        sim.advance(steps=1)
    per_call = (time.perf_counter() - t0) / n
    t0 = time.perf_counter()
    for k in range(5):
        slipfront.run(one, out=tmp_path / str(k), progress=False)
    per_run = (time.perf_counter() - t0) / 5
    print("\nin-process advance(steps=1): %.2f us per call; slipfront.run of one step: %.1f ms per call; ratio %.0f"
          % (per_call * 1e6, per_run * 1e3, per_run / per_call))
    assert per_call < per_run
