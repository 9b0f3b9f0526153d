"""In-process runs (docs/python.md, "In-process: Simulation"): one model of a scene stepped by the program's own
run inside this Python process, through the pybind11 module slipfront._slipfront (python/module.cpp)."""
from . import _slipfront
from .scene import ConfigError, Scene


def _scene(scene):
    if isinstance(scene, Scene):
        return scene
    return Scene.from_dict(scene) if isinstance(scene, dict) else Scene.from_toml(scene)


class Simulation(_slipfront._Simulation):
    """`Simulation(scene, model="continuum", checkpoint=None)`: `model` of `scene` (a Scene, a path or a dict),
    validated as `slipfront run` validates it (ConfigError with file, key and reason), ready at t = 0 — or at
    the state of `checkpoint` (bytes of Simulation.checkpoint() or a checkpoint.bin of `slipfront run` of the
    same scene with this model alone).

    advance(until=T) / advance(steps=N)   steps in C++ with the GIL released (Ctrl-C: KeyboardInterrupt
                                           between two steps; the run can go on); returns the steps taken
    x, u, v, A, sigma_bar                  read-only numpy views of the interface fields after the latest
                                           advance, valid as long as any of them exists (each holds the
                                           Simulation alive); refused (ValueError) once it is closed
    set_drive_history(times, rates)        an imposed-rate scene's v(t), piecewise constant, before advancing
    checkpoint() -> bytes                  the state, in the program's checkpoint format
    result() -> dict                       status, message, events, scalars, labels, series (ends the run)
    close()                                frees the run (its views keep their last values)
    """

    def __init__(self, scene, model="continuum", checkpoint=None):
        scene = _scene(scene)
        text = scene.path.read_text() if scene.path is not None else scene.text
        overrides = ["%s=%s" % kv for kv in scene.overrides.items()]
        try:
            super().__init__(text, scene.source, overrides, model, checkpoint)
        except _slipfront.ConfigError as e:
            raise ConfigError.parse(str(e), scene.source) from None
        self.scene = scene

    x = property(lambda self: self.view("x"), doc="node positions")
    u = property(lambda self: self.view("u"), doc="slip u (NaN for an imposed rate)")
    v = property(lambda self: self.view("v"), doc="slip rate v")
    A = property(lambda self: self.view("A"), doc="contact-area fraction A")
    sigma_bar = property(lambda self: self.view("sigma_bar"), doc="interfacial elastic stress")

    def set_drive_history(self, times, rates):
        super().set_drive_history([float(t) for t in times], [float(r) for r in rates])

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        state = "closed" if self.closed else "t = %g / %g, %d steps" % (self.time, self.t_end, self.steps)
        return "<Simulation %s of %s: %s>" % (self.model, self.scene.source, state)
