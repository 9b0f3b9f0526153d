"""Reading every file the program writes (docs/output.md): results.h5 of `run`, study.h5 of `study`,
fronts.h5 of `fronts`. `open(path)` verifies the file's checksum first and refuses a file that is not
intact; what it returns reads the datasets with h5py when asked (the file is opened for each read).

Every dataset of these files carries its `description` attribute (docs/output.md), so the labelled arrays
of to_xarray() take their descriptions from the file itself: there is no second copy of them here.
"""
import tomllib
from pathlib import Path

import h5py
import numpy as np

from . import _checksum

KINDS = {"results.h5": "run", "study.h5": "study", "fronts.h5": "fronts"}


class ChecksumError(OSError):
    """A file whose checksum block does not match its bytes (or that has none): not read."""

    def __init__(self, path, reason):
        super().__init__("%s: %s" % (path, reason))
        self.path, self.reason = str(path), reason


def _text(v):
    return v.decode("utf-8", "replace") if isinstance(v, bytes) else v


def _attrs(obj):
    out = {}
    for k, v in obj.attrs.items():
        v = _text(v)
        if isinstance(v, np.generic):
            v = v.item()
        out[k] = v
    return out


def _description(obj):
    return _text(obj.attrs.get("description", obj.attrs.get("definition", "")))


def open(path, verify=True):
    """The results of any file slipfront writes: a Results (results.h5), a Study (study.h5) or Fronts
    (fronts.h5); `path` may be the output directory holding one of them. The checksum is verified first
    (docs/output.md, "Checksum") and a file not intact raises ChecksumError (verify=False reads it anyway,
    e.g. a file written before checksums)."""
    path = Path(path)
    if path.is_dir():
        found = [path / n for n in KINDS if (path / n).is_file()]
        if len(found) != 1:
            raise FileNotFoundError("%s: expected one of %s in the directory, found %s"
                                    % (path, ", ".join(KINDS), [p.name for p in found] or "none"))
        path = found[0]
    if verify:
        state, detail = _checksum.verify(path)
        if state != "intact":
            raise ChecksumError(path, detail + ("; open(path, verify=False) reads it anyway" if state == "absent" else ""))
    with h5py.File(path, "r") as f:
        kind = "study" if "study" in f else "fronts" if "branch" in f else "run"
    return {"run": Results, "study": Study, "fronts": Fronts}[kind](path)


class File:
    """What every file has: /meta (provenance and status) and /config (the resolved configuration)."""

    def __init__(self, path):
        self.path = Path(path)
        with h5py.File(self.path, "r") as f:
            self.meta = _attrs(f["meta"]) if "meta" in f else {}
            self.config_toml = _text(f["config"].attrs["toml"]) if "config" in f and "toml" in f["config"].attrs else ""
        self.config = tomllib.loads(self.config_toml) if self.config_toml else {}

    @property
    def status(self):
        """complete, interrupted or failed (/meta status)."""
        return self.meta.get("status")

    @property
    def message(self):
        return self.meta.get("message", "")

    @property
    def provenance(self):
        """Who wrote the file, when, with what: the /meta attributes other than the outcome."""
        return {k: v for k, v in self.meta.items() if k not in ("status", "message")}

    def read(self, name):
        """One dataset as a numpy array (a path inside the file: 'continuum/snapshots/A')."""
        with h5py.File(self.path, "r") as f:
            return f[name][()]

    def _group(self, name, arrays=True):
        """{dataset: array} of a group (and its subgroups as nested dicts), {} when absent."""
        with h5py.File(self.path, "r") as f:
            if name not in f:
                return {}
            return _read_group(f[name])

    def __repr__(self):
        return "<%s %s: %s>" % (type(self).__name__, self.path, self.status)


def _read_group(g):
    out = {}
    for k, v in g.items():
        out[k] = _read_group(v) if isinstance(v, h5py.Group) else v[()]
    return out


class Model:
    """One model's group of a results file: status, attributes (scalars and labels), events, x, series,
    snapshots, the strip's bulk fields, cycles, friction law, contact statistics."""

    def __init__(self, results, name):
        self.results, self.name = results, name
        with h5py.File(results.path, "r") as f:
            g = f[name]
            self.attrs = _attrs(g)
            self.events = _attrs(g["events"]) if "events" in g else {}
            self.events.pop("description", None)
            self.x = g["x"][()] if "x" in g else None
            self.groups = [k for k, v in g.items() if isinstance(v, h5py.Group)]

    status = property(lambda self: self.attrs.get("status"))
    message = property(lambda self: self.attrs.get("message", ""))
    series = property(lambda self: self.results._group(self.name + "/series"))
    snapshots = property(lambda self: self.results._group(self.name + "/snapshots"))
    bulk = property(lambda self: self.results._group(self.name + "/bulk"))
    cycles = property(lambda self: self.results._group(self.name + "/cycles"))
    friction_law = property(lambda self: self.results._group(self.name + "/friction_law"))
    contacts = property(lambda self: self.results._group(self.name + "/contacts"))

    def descriptions(self, group):
        """{dataset: description} of a group of this model (from the file's attributes)."""
        with h5py.File(self.results.path, "r") as f:
            g = f[self.name].get(group)
            return {} if g is None else {k: _description(v) for k, v in g.items()}

    def to_xarray(self, group="snapshots"):
        """A group as an xarray.Dataset with named dimensions and each dataset's description as its
        attribute `description`: series (t), snapshots (t, x), bulk (t, y, x), cycles (cycle),
        friction_law (point)."""
        import xarray as xr
        with h5py.File(self.results.path, "r") as f:
            if group not in f[self.name]:
                raise KeyError("%s has no group %s/%s (docs/output.md says when it is written)"
                               % (self.results.path, self.name, group))
            g = f[self.name][group]
            ds = xr.Dataset(attrs={"model": self.name, "group": group, "description": _description(g),
                                   **{k: v for k, v in self.attrs.items() if isinstance(v, (int, float, str))}})
            if group == "series":
                coords = {"t": g["t"][()]}
                dims = {1: ("t",)}
            elif group == "snapshots":
                coords = {"t": g["t"][()], "x": f[self.name]["x"][()]}
                dims = {1: ("t",), 2: ("t", "x")}
            elif group == "bulk":
                coords = {"t": g["t"][()], "y": g["y"][()], "x": g["x"][()]}
                dims = {1: None, 3: ("t", "y", "x")}
            else:
                coords = {}
                dims = {1: ("cycle" if group == "cycles" else "point",)}
            for k, c in coords.items():
                source = g[k] if k in g else f[self.name][k]  # the snapshots' x is the model's
                ds.coords[k] = xr.Variable((k,), c, attrs={"description": _description(source)})
            for k, v in g.items():
                if k in coords or not isinstance(v, h5py.Dataset):
                    continue
                d = dims.get(v.ndim)
                if d is None:
                    continue
                ds[k] = xr.Variable(d, v[()], attrs={"description": _description(v)})
        return ds

    def __repr__(self):
        return "<Model %s: %s>" % (self.name, self.status)


class Results(File):
    """results.h5 of `slipfront run` (docs/output.md): results['continuum'] is a Model."""

    kind = "run"

    def __init__(self, path):
        super().__init__(path)
        models = self.meta.get("models", "")
        self.models = [m for m in models.split(",") if m]
        with h5py.File(self.path, "r") as f:
            self.models = [m for m in self.models if m in f]
        self._models = {}
        self.completed = None  # set by slipfront.run: exit code, stdout, stderr of the program

    def __getitem__(self, model):
        if model not in self.models:
            raise KeyError("%s has no model %r (it has %s)" % (self.path, model, ", ".join(self.models) or "none"))
        if model not in self._models:
            self._models[model] = Model(self, model)
        return self._models[model]

    def __iter__(self):
        return iter(self.models)

    @property
    def events(self):
        """{model: {event: value}}."""
        return {m: self[m].events for m in self.models}

    @property
    def scalars(self):
        """{model: {attribute: number}} (the model's float attributes: dt, steps, t_reached, ...)."""
        return {m: {k: v for k, v in self[m].attrs.items() if isinstance(v, float)} for m in self.models}

    @property
    def compare(self):
        """/compare of an alongside run: {metric: value or array} ({} when absent)."""
        return self._group("compare")

    def to_xarray(self, group="snapshots", models=None):
        """The models' `group` in one xarray.Dataset with a dimension `model` (the models must share the
        group's coordinates: alongside runs of a scene do); one model: Model.to_xarray."""
        import xarray as xr
        models = list(models or self.models)
        parts = [self[m].to_xarray(group) for m in models]
        for m, p in zip(models[1:], parts[1:]):
            for c in parts[0].coords:
                if c not in p.coords or not np.array_equal(p[c].values, parts[0][c].values):
                    raise ValueError("%s: %s/%s and %s/%s do not share the coordinate %s: read them one by one "
                                     "(results[model].to_xarray)" % (self.path, models[0], group, m, group, c))
        ds = xr.concat(parts, dim="model", data_vars="all", coords="minimal", compat="override",
                       combine_attrs="drop_conflicts")
        ds.coords["model"] = ("model", models)
        ds.attrs.pop("model", None)
        ds.attrs.update({"path": str(self.path), "status": self.status, "scene": self.meta.get("scene", "")})
        return ds


class Table(dict):
    """A study table: {column: array} with each column's description; to_pandas() when pandas is there."""

    def __init__(self, name, columns, descriptions):
        super().__init__(columns)
        self.name, self.descriptions = name, descriptions

    def to_pandas(self):
        import pandas as pd
        df = pd.DataFrame({k: v for k, v in self.items() if np.ndim(v) == 1})
        df.attrs["descriptions"] = dict(self.descriptions)
        return df

    def to_records(self):
        """The columns of equal length as one numpy structured array."""
        cols = {k: v for k, v in self.items() if np.ndim(v) == 1}
        return np.rec.fromarrays(list(cols.values()), names=list(cols))


class Study(File):
    """study.h5 of `slipfront study` (docs/studies.md): name, kind, fitted scalars with their definitions,
    tables, the runs."""

    kind = "study"

    def __init__(self, path):
        super().__init__(path)
        with h5py.File(self.path, "r") as f:
            s = f["study"]
            self.info = _attrs(s)
            self.scalars = _attrs(s["scalars"]) if "scalars" in s else {}
            self.definitions = _attrs(s["definitions"]) if "definitions" in s else {}
            for d in (self.scalars, self.definitions):
                d.pop("description", None)
            self.runs_info = _attrs(s["runs"]) if "runs" in s else {}
            self.table_names = list(s["tables"]) if "tables" in s else []

    name = property(lambda self: self.info.get("name"))
    study_kind = property(lambda self: self.info.get("kind"))
    notes = property(lambda self: [l for l in self.info.get("notes", "").splitlines() if l])
    runs = property(lambda self: [l for l in self.runs_info.get("runs", "").splitlines() if l])

    @property
    def tables(self):
        """{table: Table}."""
        out = {}
        with h5py.File(self.path, "r") as f:
            for name in self.table_names:
                g = f["study/tables"][name]
                cols = {k: v[()] for k, v in g.items() if isinstance(v, h5py.Dataset)}
                out[name] = Table(name, cols, {k: _description(v) for k, v in g.items()})
        return out

    def run_files(self):
        """The run files beside study.h5 (runs/<id>/results.h5), in the study's order."""
        ids = [l.split()[0] for l in self.runs]
        return [self.path.parent / "runs" / i / "results.h5" for i in ids]


class Fronts(File):
    """fronts.h5 of `slipfront fronts` (docs/fronts.md): the branch, its profiles, the scaling study."""

    kind = "fronts"

    def __init__(self, path):
        super().__init__(path)
        with h5py.File(self.path, "r") as f:
            self.branch_attrs = _attrs(f["branch"])
            self.profile_names = sorted(f["profiles"], key=int) if "profiles" in f else []

    c_min = property(lambda self: self.branch_attrs.get("c_min"))
    branch = property(lambda self: self._group("branch"))
    scaling = property(lambda self: self._group("scaling"))

    @property
    def profiles(self):
        """[{attribute or dataset: value}] in the file's order."""
        out = []
        with h5py.File(self.path, "r") as f:
            for k in self.profile_names:
                g = f["profiles"][k]
                out.append({**_attrs(g), **{n: v[()] for n, v in g.items()}})
        return out
