#!/usr/bin/python3
"""Check a report.md (the main job runs it after `slipfront report`); exit 1 on any failure:

1. it is non-empty UTF-8 and every image it names exists and is a non-empty PNG;
2. its summary has the table "Limits that must hold", and no row of it with a verdict (pass or FAIL) compares a
   model with a limit it is not supposed to reach. Each such row names its file (relative to the report's
   directory) and its reference; the file is opened and its own config and /compare are read:
   - a scene (results.h5) whose discrete model runs at w > 0 (threshold disorder) may be tested against
     mean_field only (docs/model.md §2.2): against the continuum its difference is an effect, not a test;
   - the row's reference must be the one the file's /compare used (its attribute `reference`, absent for the
     continuum), and its w the file's;
   - a study (study.h5) tested against the continuum must run at w = 0 (its rows at w = 0 only), unless its limit
     is the continuum as w -> 0 (kind threshold_width, docs/model.md §2.1 item 4; kind disorder_limit, mean_field
     -> continuum as w -> 0, docs/model.md §2.2).
3. with `--numbers PAGE` (the main job passes docs/results.md): every number the page quotes from a run (the rows of
   its tables headed "| quoted | value | file | expression |") equals the run's value at the precision quoted. A
   row names a file under the report's directory and a Python expression of it: of an HDF5 file `f` (open, h5py);
   of a CSV file `c` (its numeric columns, numpy arrays) and `rows` (its rows, dicts by column); `np` (numpy). The
   quoted value must lie within half a unit of its last digit of the expression's value. Only on request: the page
   quotes the main job's output, which a test's small report does not have. Other pages cite docs/results.md for
   these numbers instead of repeating them.

   check_report.py REPORT.md [--numbers docs/results.md]
"""
import math
import os
import re
import sys

VERDICTS = ("pass", "FAIL")


def check_images(text, root):
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    bad = []
    for rel in images:
        path = os.path.join(root, rel)
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            bad.append(f"{rel}: missing or empty")
            continue
        with open(path, "rb") as f:
            if f.read(8) != b"\x89PNG\r\n\x1a\n":
                bad.append(f"{rel}: not a PNG")
    if not images:
        bad.append("the report names no plot")
    return images, bad


def table_after(text, heading):
    """The rows of the first markdown table under `heading` as dicts by column name; None without the heading."""
    lines = text.split("\n")
    try:
        k = lines.index(heading)
    except ValueError:
        return None
    k += 1
    while k < len(lines) and not lines[k].startswith("|"):
        if lines[k].startswith("#"):
            return []
        k += 1
    if k >= len(lines):
        return []

    def cells(line):
        parts = re.split(r"(?<!\\)\|", line.strip())[1:-1]
        return [p.strip().replace("\\|", "|") for p in parts]
    head = cells(lines[k])
    rows = []
    for line in lines[k + 2:]:
        if not line.startswith("|"):
            break
        rows.append(dict(zip(head, cells(line))))
    return rows


def as_str(v):
    return v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v)


def discrete_width(cfg):
    d = cfg.get("discrete", {})
    if d.get("threshold", "delta") == "delta":
        return 0.0
    return float(d.get("width", 0.0))


def read_scene(path):
    """(w of the discrete model, the /compare reference, models) of a results.h5."""
    import h5py
    import tomllib
    with h5py.File(path, "r") as f:
        cfg = tomllib.loads(as_str(f["config"].attrs["toml"]))
        ref = as_str(f["compare"].attrs.get("reference", "continuum")) if "compare" in f else None
        models = [m for m in ("continuum", "mean_field", "discrete") if m in f]
    return discrete_width(cfg), ref, models


def read_study(path):
    """(kind, the set of w of its discrete runs) of a study.h5: the varied discrete.width, else every run file's
    resolved config."""
    import h5py
    import tomllib
    with h5py.File(path, "r") as f:
        s = f["study"]
        kind = as_str(s.attrs["kind"])
        runs = [ln.split() for ln in as_str(s["runs"].attrs.get("runs", "")).split("\n") if ln.strip()]
    widths = set()
    for parts in runs:
        point = dict(p.split("=", 1) for p in parts[1:] if "=" in p)
        run = os.path.join(os.path.dirname(path), "runs", parts[0], "results.h5")
        if os.path.isfile(run):
            with h5py.File(run, "r") as f:
                widths.add(discrete_width(tomllib.loads(as_str(f["config"].attrs["toml"]))))
        elif "discrete.width" in point:
            widths.add(float(point["discrete.width"]))
    return kind, widths


def same_w(a, b):
    try:
        return math.isclose(float(a), float(b), rel_tol=1e-9, abs_tol=0.0)
    except ValueError:
        return False


def check_limits(text, root):
    """Errors of the limits table (rule 2 of the module's text)."""
    rows = table_after(text, "### Limits that must hold")
    if rows is None:
        return ["the report has no table \"Limits that must hold\" (report.py writes it in its summary)"], 0
    errors, checked = [], 0
    cache = {}
    for r in rows:
        if r.get("verdict") not in VERDICTS:
            continue
        src = r.get("file", "").strip("`")
        what = f"row '{r.get('observable', '')}' ({r.get('limit', '')})"
        path = os.path.join(root, src)
        if not src or not os.path.isfile(path):
            errors.append(f"{what}: its file '{src}' does not exist")
            continue
        ref = r.get("reference", "")
        try:
            if path not in cache:
                cache[path] = ("scene", read_scene(path)) if src.endswith("results.h5") else \
                    ("study", read_study(path)) if src.endswith("study.h5") else ("other", None)
        except (OSError, KeyError, ValueError) as e:
            errors.append(f"{what}: cannot read '{src}': {e}")
            continue
        checked += 1
        kind, info = cache[path]
        if kind == "scene":
            w, file_ref, models = info
            if ref == "continuum" and w > 0:
                errors.append(f"{what}: tests the discrete model at w = {w:g} ({src}) against the continuum, a limit "
                              "it is not supposed to reach (its N -> inf limit is mean_field, docs/model.md §2.2)")
            if ref in ("continuum", "mean_field") and file_ref is not None and ref != file_ref:
                errors.append(f"{what}: says it tests against {ref}, but {src} compared the discrete model with "
                              f"{file_ref} (/compare reference)")
            if ref not in models:
                errors.append(f"{what}: its reference {ref} is not a model of {src} ({', '.join(models)})")
            if not same_w(r.get("w", ""), w):
                errors.append(f"{what}: says w = {r.get('w', '')}, but {src} runs w = {w:g}")
        elif kind == "study":
            skind, widths = info
            if ref == "continuum" and any(w > 0 for w in widths):
                towards_zero = skind in ("threshold_width", "disorder_limit") and "w -> 0" in r.get("limit", "")
                at_zero = same_w(r.get("w", ""), 0.0) and 0.0 in widths
                if not (towards_zero or at_zero):
                    errors.append(f"{what}: tests runs at w = {', '.join(f'{w:g}' for w in sorted(widths))} ({src}, "
                                  f"kind {skind}) against the continuum, a limit they are not supposed to reach")
    return errors, checked


def quoted_rows(page):
    """The rows of docs/results.md's tables whose header starts "| quoted | value | file | expression |"."""
    rows, cols = [], None
    with open(page, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line.startswith("|"):
                cols = None
                continue
            cells = [c.strip().strip("`") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
            if cols is None:
                cols = cells if cells[:4] == ["quoted", "value", "file", "expression"] else []
            elif cols and not set(cells[0]) <= set("- "):
                rows.append(dict(zip(cols, [c.replace("\\|", "|") for c in cells])))
    return rows


def half_unit(text):
    """Half a unit of the last digit of a quoted number ("25.71" -> 0.005, "10" -> 0.5, "1.2e-3" -> 5e-5)."""
    mant, _, exp = text.lower().partition("e")
    decimals = len(mant.partition(".")[2])
    return 0.5 * 10.0 ** (-decimals + (int(exp) if exp else 0))


def evaluate(root, row):
    """The value of a row's expression on its file."""
    import numpy as np
    path = os.path.join(root, row["file"])
    if path.endswith(".csv"):
        import csv
        with open(path, newline="") as f:
            data = list(csv.DictReader(f))
        c = {}
        for k in (data[0] if data else {}):
            try:
                c[k] = np.array([float(r[k]) for r in data])
            except ValueError:
                pass  # a column of words: in `rows` only
        return float(eval(row["expression"], {"np": np, "c": c, "rows": data}))  # noqa: S307 (the project's own page)
    import h5py
    with h5py.File(path, "r") as f:
        return float(eval(row["expression"], {"np": np, "f": f}))  # noqa: S307 (the project's own page)


def check_numbers(root, page):
    """Errors of rule 3 (each quoted number against the run's files) and the number of rows read."""
    errors, rows = [], quoted_rows(page)
    for r in rows:
        what = f"docs/results.md: '{r['quoted']}' = {r['value']}"
        try:
            v = evaluate(root, r)
        except Exception as e:  # noqa: BLE001 (a missing file, group, column or a bad expression: each is reported)
            errors.append(f"{what}: cannot evaluate `{r['expression']}` on {r['file']}: {type(e).__name__}: {e}")
            continue
        quoted = float(r["value"])
        if not (math.isfinite(v) and abs(v - quoted) <= half_unit(r["value"]) * (1 + 1e-9)):
            errors.append(f"{what}, but {r['file']} gives {v:.6g} (`{r['expression']}`)")
    return errors, len(rows)


def main(argv):
    if len(argv) not in (2, 4) or (len(argv) == 4 and argv[2] != "--numbers"):
        print("usage: check_report.py REPORT.md [--numbers docs/results.md]", file=sys.stderr)
        return 2
    report, page = argv[1], argv[3] if len(argv) == 4 else None
    root = os.path.dirname(os.path.abspath(report))
    with open(report, "rb") as f:
        raw = f.read()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        print(f"check_report: {report} is not UTF-8: {e}", file=sys.stderr)
        return 1
    if not text.strip():
        print(f"check_report: {report} is empty", file=sys.stderr)
        return 1
    images, bad = check_images(text, root)
    for b in bad:
        print(f"check_report: {b}", file=sys.stderr)
    errors, checked = check_limits(text, root)
    for e in errors:
        print(f"check_report: {e}", file=sys.stderr)
    if bad:
        print(f"check_report: {len(bad)} of {len(images)} plots bad")
    else:
        print(f"check_report: {len(images)} plots named in {report}, all present and non-empty")
    print(f"check_report: {checked} verdict rows read against their files; {len(errors)} errors (a model tested against "
          "a limit it is not supposed to reach, a misstated reference or w, a missing file or table)")
    numbers = check_numbers(root, page) if page else ([], 0)
    for e in numbers[0]:
        print(f"check_report: {e}", file=sys.stderr)
    if page:
        print(f"check_report: {numbers[1]} numbers quoted in {page} read against the run; {len(numbers[0])} differ")
    return 1 if bad or errors or numbers[0] else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
