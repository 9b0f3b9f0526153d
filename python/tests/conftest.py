"""Shared fixtures of the Python package's tests (run by ctest: python/CMakeLists.txt sets
SLIPFRONT_PROGRAM to the built program and PYTHONPATH to build/python)."""
import os
from pathlib import Path

import pytest

import slipfront

SOURCE = Path(os.environ.get("SLIPFRONT_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def tiny_config(**changes):
    """fig1's physics on a short interface (L = 60, dx = 1, t_end = 40: 13892 explicit steps, ~0.05 s):
    t* = (K + sqrt(alpha mu)) / (alpha K v_d) = 25.7 falls inside."""
    config = {
        "scene": "tiny", "models": ["continuum"],
        "interface": {"alpha": 1.05, "kappa": 8.0, "eta": 0.1},
        "bulk": {"rho": 0.01, "mu": 300.0, "length": 60.0},
        "drive": {"loading": "edge", "K": 2.5, "v_d": 0.3},
        "grid": {"dx": 1.0},
        "time": {"t_end": 40.0, "cfl": 0.5},
        "output": {"series_dt": 0.5, "snapshot_dt": 5.0},
    }
    for key, value in changes.items():
        section, _, name = key.rpartition("__")
        (config[section] if section else config)[name] = value
    return config


@pytest.fixture
def tiny():
    return slipfront.Scene.from_dict(tiny_config())


@pytest.fixture
def tiny_file(tmp_path):
    """The tiny scene as a TOML file."""
    path = tmp_path / "tiny.toml"
    path.write_text(slipfront.scene.dumps(tiny_config()))
    return path


@pytest.fixture
def long_scene():
    """fig1 with the continuum alone (97107 steps, ~0.5 s): long enough to be stopped midway."""
    return slipfront.Scene.from_toml(SOURCE / "configs" / "fig1.toml").set("models", ["continuum"])
