"""A scene: a configuration file (docs/cli.md) with overrides, validated by the program itself."""
import copy
import json
import math
import os
import re
import tempfile
import tomllib
from contextlib import contextmanager
from pathlib import Path

from . import _program

_KEY = re.compile(r"^(--set )?[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$|^--[a-z][a-z-]*$")


class ConfigError(ValueError):
    """A configuration the program refuses (exit code 2), with the file, the key and the reason of its
    message `<file>: <key>: <reason>` (docs/cli.md "Error messages"); `key` is None for messages without
    one (a TOML syntax error, an unusable file or directory)."""

    def __init__(self, message, file=None, key=None, reason=None):
        super().__init__(message)
        self.message, self.file, self.key, self.reason = message, file, key, reason

    @classmethod
    def parse(cls, message, file, shown_as=None):
        """From a program message about `file` (named `shown_as` to the user, e.g. "<dict>")."""
        shown = shown_as or file
        file = str(file) if file is not None else None
        rest = message
        if file and message.startswith(file + ":"):
            rest = message[len(file) + 1:]
            message = str(shown) + ":" + rest
            rest = rest.lstrip()
        else:
            return cls(message, shown, None, message)
        key, sep, reason = rest.partition(": ")
        if sep and _KEY.match(key):
            return cls(message, shown, key, reason)
        return cls(message, shown, None, rest)


def toml_value(value):
    """A Python value as a TOML value (what `--set key=VALUE` reads)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        text = repr(value)  # shortest round trip; TOML needs a digit after the point and allows 1e-05
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a TOML basic string
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if hasattr(value, "item"):  # numpy scalars
        return toml_value(value.item())
    raise TypeError("no TOML value for %r (%s)" % (value, type(value).__name__))


def dumps(config):
    """A scene dictionary ({key: value, section: {key: value}}) as TOML text."""
    top = [k for k, v in config.items() if not isinstance(v, dict)]
    lines = ["%s = %s" % (k, toml_value(config[k])) for k in top]
    for section, table in config.items():
        if isinstance(table, dict):
            lines += ["", "[%s]" % section] + ["%s = %s" % (k, toml_value(v)) for k, v in table.items()]
    return "\n".join(lines) + "\n"


class Check:
    """What `slipfront check` said of a valid scene: the fully resolved configuration (every key the run
    uses, defaults included: the text stored in /config), the estimate's lines and the notes."""

    def __init__(self, stdout, stderr):
        body, _, estimate = stdout.partition("\n# estimate")
        self.toml = body.rstrip("\n") + "\n"
        self.config = tomllib.loads(self.toml)
        self.estimate = [l[4:].rstrip() for l in estimate.splitlines()[1:] if l.startswith("#   ")]
        self.notes = [l[len("slipfront: note: "):] for l in stderr.splitlines() if l.startswith("slipfront: note: ")]

    def __repr__(self):
        return "<Check %s: %s>" % (self.config.get("scene"), "; ".join(self.estimate[-1:]))


class Scene:
    """A scene configuration: a TOML file (Scene.from_toml) or a dictionary (Scene.from_dict), with
    overrides (set) passed to the program as `--set KEY=VALUE`, so that its messages name the file and
    `--set KEY`. Nothing is validated in Python: check() asks the program."""

    def __init__(self, path=None, text=None, overrides=None):
        self.path = Path(path) if path is not None else None
        self.text = text
        self.overrides = dict(overrides or {})

    @classmethod
    def from_toml(cls, path):
        path = Path(path)
        if not path.is_file():
            raise ConfigError("%s: no such configuration file" % path, str(path), None, "no such configuration file")
        return cls(path=path)

    @classmethod
    def from_dict(cls, config):
        return cls(text=dumps(config))

    @property
    def source(self):
        """How the program's messages name this scene's file ("<dict>" for a scene from a dictionary)."""
        return str(self.path) if self.path is not None else "<dict>"

    def copy(self):
        return Scene(self.path, self.text, copy.deepcopy(self.overrides))

    def set(self, key, value):
        """Override `key` ("bulk.height", top-level keys bare: "models"); returns the scene (chainable)."""
        if not isinstance(key, str) or not key:
            raise TypeError("a key is a non-empty string such as 'bulk.height'")
        self.overrides[key] = toml_value(value)
        return self

    def set_args(self):
        return [a for k, v in self.overrides.items() for a in ("--set", "%s=%s" % (k, v))]

    def to_dict(self):
        """The configuration as written, with the overrides applied (not resolved: see check())."""
        config = tomllib.loads(self.path.read_text() if self.path is not None else self.text)
        for key, value in self.overrides.items():
            *sections, last = key.split(".")
            table = config
            for s in sections:
                table = table.setdefault(s, {})
            table[last] = tomllib.loads("v = " + value)["v"]
        return config

    @property
    def name(self):
        return self.to_dict().get("scene")

    @contextmanager
    def file(self):
        """A path the program can read: the file itself, or the dictionary written to a temporary file."""
        if self.path is not None:
            yield str(self.path)
            return
        with tempfile.TemporaryDirectory(prefix="slipfront-scene-") as d:
            p = os.path.join(d, "scene.toml")
            with open(p, "w") as f:
                f.write(self.text)
            yield p

    def error(self, completed, file):
        """The ConfigError of a refused configuration (the program's first error line)."""
        lines = completed.errors() or [completed.stderr.strip() or "the program refused the configuration"]
        return ConfigError.parse(lines[0], file, self.source)

    def check(self, program=None):
        """Validates the scene exactly as `slipfront run` does (every value, the rules between keys, the
        estimate against [limits]) with `slipfront check`; returns a Check, raises ConfigError."""
        with self.file() as f:
            done = _program.drive([_program.find_program(program), "check", f] + self.set_args(), progress=False)
            if done.code != 0:
                raise self.error(done, f)
        return Check(done.stdout, done.stderr)

    def __repr__(self):
        sets = "".join(" --set %s=%s" % kv for kv in self.overrides.items())
        return "<Scene %s%s>" % (self.source, sets)
