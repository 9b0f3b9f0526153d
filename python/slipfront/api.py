"""The program's verbs from Python (docs/cli.md): run, study, fronts, report."""
import os
from pathlib import Path

from . import _program, files
from .scene import ConfigError, Scene


class RunError(RuntimeError):
    """The program ended without a file to read (a write error, a crash); `completed` has its output."""

    def __init__(self, message, completed):
        super().__init__(message)
        self.completed = completed


def _scene(scene):
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, dict):
        return Scene.from_dict(scene)
    return Scene.from_toml(scene)


def _out_dir(out, default):
    return Path(out) if out is not None else Path(default)


def _finish(done, file, scene_source, config_file):
    """The file the program wrote, or the exception of why it wrote none."""
    if done.code == 2:
        lines = done.errors() or [done.stderr.strip()]
        raise ConfigError.parse(lines[0], config_file, scene_source)
    if not file.is_file():
        raise RunError("slipfront exited with %d and wrote no %s: %s"
                       % (done.code, file, "; ".join(done.errors()) or done.stderr.strip()), done)
    result = files.open(file)
    result.completed = done
    return result


def run(scene, models=None, out=None, force=False, checkpoint_every=None, restart=None, progress=True,
        program=None, stop_after=None):
    """`slipfront run`: runs `scene` (a Scene, a TOML path or a dict) and returns its Results.

    models           the models to run (overrides `models`), e.g. ["continuum"]
    out              output directory (default out/<scene name>, as the program's)
    force            replace an existing results.h5
    checkpoint_every write out/checkpoint.bin every this much simulated time (docs/cli.md, Checkpoints)
    restart          continue from a checkpoint: True for out/checkpoint.bin, or its path (implies force,
                     since the interrupted results.h5 is there); same scene and overrides as when it was made
    progress         True: tqdm bars when tqdm is installed; a callable: called with each progress dict;
                     False: nothing
    program          the slipfront executable (default: beside the package, or $SLIPFRONT_PROGRAM)

    Ctrl-C (KeyboardInterrupt) stops the program as its own Ctrl-C does: the partial results are written
    and returned with status 'interrupted'. A configuration the program refuses raises ConfigError (file,
    key, reason); a model that fails returns the file with status 'failed'."""
    scene = _scene(scene).copy()
    if models is not None:
        scene.set("models", list(models))
    name = scene.name or "scene"
    out = _out_dir(out, Path("out") / name)
    args = [_program.find_program(program), "run", None, "--out", str(out), "--progress", "json"] + scene.set_args()
    if force or restart:
        args.append("--force")
    if checkpoint_every is not None:
        args += ["--checkpoint-every", repr(float(checkpoint_every))]
    if restart:
        args += ["--restart", str(out / "checkpoint.bin" if restart is True else restart)]
    with scene.file() as f:
        args[2] = f
        done = _program.drive(args, progress=progress, stop_after=stop_after)
        result = _finish(done, out / "results.h5", scene.source, f)
    result.scene, result.out = scene, out
    return result


def resume(results, **kwargs):
    """Continues an interrupted run from its checkpoint (out/checkpoint.bin), with the same scene."""
    if not (results.out / "checkpoint.bin").is_file():
        raise FileNotFoundError("%s: no checkpoint to resume from (run with checkpoint_every=T)" % results.out)
    kwargs.setdefault("checkpoint_every", None)
    return run(results.scene, out=results.out, restart=True, **kwargs)


def study(study_file, out=None, overrides=None, threads=None, force=False, progress=True, program=None):
    """`slipfront study`: runs (or resumes) the study file and returns its Study (study.h5).
    overrides: {key: value} applied to every run (`--set`)."""
    study_file = Path(study_file)
    sets = Scene(path=study_file)
    for k, v in (overrides or {}).items():
        sets.set(k, v)
    import tomllib
    name = tomllib.loads(study_file.read_text()).get("study", "study") if study_file.is_file() else "study"
    out = _out_dir(out, Path("out") / "studies" / name)
    args = [_program.find_program(program), "study", str(study_file), "--out", str(out), "--progress", "json"]
    args += sets.set_args()
    if threads:
        args += ["-j", str(int(threads))]
    if force:
        args.append("--force")
    done = _program.drive(args, progress=progress)
    result = _finish(done, out / "study.h5", str(study_file), str(study_file))
    result.out = out
    return result


def fronts(scene, out=None, scaling=False, force=False, rows=None, intervals=None, program=None):
    """`slipfront fronts`: the steady fronts of a homogeneous scene; returns Fronts (fronts.h5)."""
    scene = _scene(scene).copy()
    out = _out_dir(out, Path("out") / (scene.name or "scene"))
    args = [_program.find_program(program), "fronts", None, "--out", str(out)] + scene.set_args()
    if scaling:
        args.append("--scaling")
    if force:
        args.append("--force")
    if rows is not None:
        args += ["--rows", str(int(rows))]
    if intervals is not None:
        args += ["--intervals", str(int(intervals))]
    with scene.file() as f:
        args[2] = f
        done = _program.drive(args, progress=False)
        result = _finish(done, out / "fronts.h5", scene.source, f)
    result.out = out
    return result


def report(directory, python=None, program=None):
    """`slipfront report DIR`: DIR/report.md and the figures of every file under DIR; returns the path of
    report.md."""
    args = [_program.find_program(program), "report", str(directory)]
    if python:
        args += ["--python", str(python)]
    done = _program.drive(args, progress=False)
    if done.code != 0:
        raise RunError("slipfront report %s failed (exit %d): %s"
                       % (directory, done.code, "; ".join(done.errors()) or done.stderr.strip()), done)
    return Path(directory) / "report.md"
