"""slipfront from Python (docs/python.md): scenes, the program's verbs, and every file it writes.

    import slipfront
    scene = slipfront.Scene.from_toml("configs/fig1.toml").set("time.t_end", 40)
    scene.check()                                    # the program's own validation: ConfigError(file, key, reason)
    res = slipfront.run(scene, models=["continuum"], out="out/fig1")
    res["continuum"].events["t_star"], res.to_xarray("snapshots")

Needs numpy and h5py; xarray, pandas and tqdm are used when present. The in-process module
(slipfront.Simulation) is there when the package was built with pybind11.
"""
from .api import RunError, fronts, report, resume, run, study
from .files import ChecksumError, Fronts, Model, Results, Study, Table, open
from .scene import Check, ConfigError, Scene

try:
    from .inprocess import Simulation  # noqa: F401  (the pybind11 module, when it was built: python/CMakeLists.txt)
except ImportError:
    import pathlib as _pathlib
    if list(_pathlib.Path(__file__).parent.glob("_slipfront*.so")):
        raise  # built but not loadable: say why

__all__ = ["Simulation"] * ("Simulation" in globals()) + ["Scene", "Check", "ConfigError", "ChecksumError", "RunError", "Results", "Model", "Study", "Fronts",
           "Table", "run", "resume", "study", "fronts", "report", "open"]
