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
3. with `--numbers PAGE ...` (pages or directories of them; the main job passes README.md docs): every number a page
   quotes from a run equals the run's value at the precision quoted: the rows of its tables headed
   "| quoted | value | file | expression |", and each number followed by a run marker `<!-- run: FILE EXPRESSION -->`.
   FILE is under the report's directory; EXPRESSION is Python of it: of an HDF5 file `f` (open, h5py) and
   `cell(table, column, **where)` (the one row of a study table with those values); of a CSV file `c` (its numeric
   columns, numpy arrays), `rows` (its rows, dicts by column), `row(observable)` (the one row whose observable starts
   so) and `after(text, name)` (the number after `name` in a cell); `np` (numpy). The quoted value must lie within
   half a unit of its last digit of the expression's value. Only on request: the pages quote the main job's output,
   which a test's small report does not have.
4. with `--numbers`, or alone with `--unmarked PAGE ...` (no run): no page quotes a number that looks copied from a
   run (QUOTED_SHAPES: an event time or speed given a value, a count of tests or of a report's rows, a timing, a
   speed ratio, a fitted exponent) unless it is checked (3), or dated by a marker
   `<!-- measured: COMMIT or DATE ... -->` or `<!-- not from a run: WHY -->` (MARKER says what a marker covers;
   docs/results.md, "Quoting a number").

   check_report.py REPORT.md [--numbers PAGE ...]
   check_report.py --unmarked PAGE ...
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
    """The rows of a page's tables whose header starts "| quoted | value | file | expression |"."""
    with open(page, encoding="utf-8") as f:
        return quoted_rows_in(f.read())


def quoted_rows_in(text):
    """quoted_rows of a page's text, each row with its line number ("line")."""
    rows, cols = [], None
    for number, line in enumerate(text.split("\n"), 1):
        if not line.startswith("|"):
            cols = None
            continue
        cells = [c.strip().strip("`") for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
        if cols is None:
            cols = cells if cells[:4] == ["quoted", "value", "file", "expression"] else []
        elif cols and not set(cells[0]) <= set("- "):
            rows.append(dict(zip(cols, [c.replace("\\|", "|") for c in cells]), line=number))
    return rows


# Rule 4: what looks like a number copied from a run. Five shapes: an event time or a speed given a value
# (`t* = 25.66`, `c_min ≈ 11.28`, `c = 58.74`), a count of tests or of a report's rows (`132 of 132 tests`,
# `10 of 13`, `359 tests`, `13 rows tested`, `135 rows: 124 pass`),
# a timing, a speed ratio (`3 min 29 s`, `0.3 s`, `12×`), and a fitted exponent (`N^-0.55`, `(α − 1)^{−1.23}`; not
# `N^-1/2` or `10^4`). Each must be checked, cited or dated (MARKER).
_NUM = r"[-−]?\d+(?:\.\d+)?(?:[eE][-−+]?\d+)?"
QUOTED_SHAPES = (
    ("an event time or speed", re.compile(
        r"(?<![\w^*])(t\*|t\^|t_star|t_hat|t_arrest|x_arrest|c_transient|c_front|c_min|c_slow|σ_c\^d|sigma_c\^d|v_m|c)"
        r"`?\s*(?:=|≈|~)\s*`?(" + _NUM + r")(?![\w.])")),
    ("a count", re.compile(r"(?<![\w.])(\d+) (?:of|/) ?\d+(?![\w.])|(?<![\w.])\d+/\d+ (?:pass|tests)\b"
                           r"|(?<![\w.])\d+ tests\b|(?<![\w.])\d+ rows(?: tested|: | pass| fail|, \d+ pass)")),
    ("a timing", re.compile(r"(?<![\w.])\d+(?:\.\d+)? ?(?:min|s|ms|µs|μs|h)\b(?! *=)")),
    ("a speed ratio", re.compile(r"(?<![\w.])\d+(?:\.\d+)? ?×(?! ?\d)")),
    ("a fitted exponent", re.compile(r"\^\{?[-−]?\d+\.\d+")),
)
# <!-- run: FILE EXPRESSION --> right after a number: the number is checked like a quoted table's row.
# <!-- measured: ... --> names the past commit or date the numbers it covers were measured at (historical: not the
# run's); <!-- not from a run: ... --> says why they are not a run's (a closed form, a config value, the paper's).
# On a line of its own right under a heading, a marker covers that section (to the next heading of its level or
# higher); on a line of its own elsewhere, the block below it (to the next blank line; a fenced block whole);
# inside a line, that line.
MARKER = re.compile(r"<!--\s*(run|measured|not from a run):\s*(.*?)\s*-->", re.S)
RUN_MARKER = re.compile(r"(" + _NUM + r")[`*)}\]\s]*<!--\s*run:\s*(\S+)\s+(.*?)\s*-->")
DATED = re.compile(r"\b\d{4}-\d{2}-\d{2}\b|\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b")  # a date, a commit


def markdown_lines(text):
    """(line, heading level or 0, inside a fenced block) of each line of a page."""
    fenced, out = False, []
    for line in text.split("\n"):
        if line.lstrip().startswith("```"):
            out.append((line, 0, True))
            fenced = not fenced
            continue
        m = re.match(r"(#{1,6}) ", line)
        out.append((line, len(m.group(1)) if m and not fenced else 0, fenced))
    return out


def block_end(lines, k):
    """The index after the block that starts at line k (a fenced block whole, else up to the next blank line)."""
    if lines[k][0].lstrip().startswith("```"):
        j = k + 1
        while j < len(lines) and not lines[j][0].lstrip().startswith("```"):
            j += 1
        return min(j + 1, len(lines))
    while k < len(lines) and lines[k][0].strip():
        k += 1
    return k


def marker_scope(lines, k):
    """The lines [a, b) a marker alone on line k covers."""
    prev = next((j for j in range(k - 1, -1, -1) if lines[j][0].strip()), None)
    if prev is not None and lines[prev][1]:
        level, j = lines[prev][1], k + 1
        while j < len(lines) and not (lines[j][1] and lines[j][1] <= level):
            j += 1
        return k, j
    start = next((j for j in range(k + 1, len(lines)) if lines[j][0].strip()), len(lines))
    return k, block_end(lines, start)


def in_code(line, pos):
    """Whether position `pos` of a line is inside an inline code span (a marker there is an example, not a marker)."""
    return any(m.start() < pos < m.end() for m in re.finditer(r"(`+).+?\1", line))


def live_markers(line, fenced):
    """The markers of a line that are markers: not in a fenced block, not inside a code span."""
    return [] if fenced else [m for m in MARKER.finditer(line) if not in_code(line, m.start())]


def run_markers(page, k, line, markers):
    """The checked numbers of a line [(line, value, file, expression)], and an error if a run marker follows none."""
    found = [(k + 1, m.group(1).replace("−", "-"), m.group(2).strip("`"), m.group(3).strip("`"))
             for m in RUN_MARKER.finditer(line) if not in_code(line, m.start(2))]
    if len(found) == sum(m.group(1) == "run" for m in markers):
        return found, []
    return found, [f"{page}:{k + 1}: a 'run' marker not right after a number (a number, then only `, *, ), }}, ] or "
                   "spaces, then the marker)"]


def scan_page(page, text):
    """(run markers [(line, value, file, expression)], marker errors, unmarked numbers [(line, shape, text)])."""
    lines = markdown_lines(text)
    covered = [False] * len(lines)
    for r in quoted_rows_in(text):
        covered[r["line"] - 1] = True
    runs, errors = [], []
    for k, (line, _, fenced) in enumerate(lines):
        markers = live_markers(line, fenced)
        for m in markers:
            kind, what = m.group(1), m.group(2)
            if kind == "measured" and not DATED.search(what):
                errors.append(f"{page}:{k + 1}: a 'measured' marker names no commit or date: '{what}'")
            if kind == "not from a run" and not what:
                errors.append(f"{page}:{k + 1}: a 'not from a run' marker says not why")
            if kind != "run" and not MARKER.sub("", line).strip():
                a, b = marker_scope(lines, k)
                covered[a:b] = [True] * (b - a)
            elif kind != "run":
                covered[k] = True
        found, bad = run_markers(page, k, line, markers)
        runs, errors = runs + found, errors + bad
    unmarked = []
    for k, (line, _, _) in enumerate(lines):
        bare = MARKER.sub("", RUN_MARKER.sub("", line))
        unmarked += [] if covered[k] else [(k + 1, shape, m.group(0)) for shape, pattern in QUOTED_SHAPES
                                           for m in pattern.finditer(bare)]
    return runs, errors, unmarked


def pages_of(paths):
    """The Markdown files of a list of files and directories (a directory: its *.md, sorted)."""
    out = []
    for p in paths:
        out += sorted(os.path.join(p, n) for n in os.listdir(p) if n.endswith(".md")) if os.path.isdir(p) else [p]
    return out


def check_marked(pages):
    """Errors of rule 4 (every number quoted from a run checked, cited or dated), without a run; the counts of
    (quoted-table rows, run markers) read."""
    errors, rows, runs = [], 0, 0
    for page in pages:
        with open(page, encoding="utf-8") as f:
            marked, bad, unmarked = scan_page(page, f.read())
        rows += len(quoted_rows(page))
        runs += len(marked)
        errors += bad
        errors += [f"{page}:{k}: {shape} quoted without a check, a citation or a date: '{text}' (docs/results.md, "
                   "\"Quoting a number\")" for k, shape, text in unmarked]
    return errors, rows, runs


def half_unit(text):
    """Half a unit of the last digit of a quoted number ("25.71" -> 0.005, "10" -> 0.5, "1.2e-3" -> 5e-5)."""
    mant, _, exp = text.lower().partition("e")
    decimals = len(mant.partition(".")[2])
    return 0.5 * 10.0 ** (-decimals + (int(exp) if exp else 0))


def row_of(rows, observable):
    """The one row of a CSV file (the report's summary_*.csv) whose `observable` starts with the given text."""
    found = [r for r in rows if r.get("observable", "").startswith(observable)]
    if len(found) != 1:
        raise KeyError(f"{len(found)} rows whose observable starts with '{observable}'")
    return found[0]


def number_after(text, name):
    """The number right after `name` in a cell of the report ("KS distance 0.0286; ... p = 2.2e-05": 'p =' gives
    2.2e-05)."""
    m = re.search(re.escape(name) + r"\s*([-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)", text)
    if not m:
        raise KeyError(f"no number after '{name}' in '{text}'")
    return float(m.group(1))


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
        names = {"np": np, "c": c, "rows": data, "row": lambda o: row_of(data, o), "after": number_after}
        return float(eval(row["expression"], names))  # noqa: S307 (the project's own pages)
    import h5py
    with h5py.File(path, "r") as f:
        names = {"np": np, "f": f, "cell": lambda table, column, **where: table_cell(f, table, column, where)}
        return float(eval(row["expression"], names))  # noqa: S307 (the project's own pages)


def table_cell(f, table, column, where):
    """The one value of `column` in a study table (`study/tables/<table>`, or a path) on the row whose columns equal
    `where` (cell('validity_fig1', 'fraction', alpha_minus_1=0.03, N=100))."""
    import numpy as np
    g = f[table if "/" in table else f"study/tables/{table}"]
    keep = np.ones(len(g[column]), dtype=bool)
    for name, value in where.items():
        keep &= np.isclose(g[name][()], value, rtol=1e-9, atol=1e-12)
    if keep.sum() != 1:
        raise KeyError(f"{int(keep.sum())} rows of {table} with {where}")
    return g[column][()][keep][0]


def check_value(root, what, quoted, file, expression):
    """An error (starting with `what`) if the value `quoted` (text) is not the expression's on the run's file at the
    precision quoted; None if it is."""
    try:
        v = evaluate(root, {"file": file, "expression": expression})
    except Exception as e:  # noqa: BLE001 (a missing file, group, column or a bad expression: each is reported)
        return f"{what}: cannot evaluate `{expression}` on {file}: {type(e).__name__}: {e}"
    return None if math.isfinite(v) and abs(v - float(quoted)) <= half_unit(quoted) * (1 + 1e-9) else \
        f"{what}, but {file} gives {v:.6g} (`{expression}`)"


def check_numbers(root, pages):
    """Errors of rules 3 and 4 (each quoted number against the run's files; none unmarked) and the numbers read."""
    errors, n = [], 0
    for page in pages:
        for r in quoted_rows(page):
            errors.append(check_value(root, f"{page}:{r['line']}: '{r['quoted']}' = {r['value']}", r["value"],
                                      r["file"], r["expression"]))
        with open(page, encoding="utf-8") as f:
            runs = scan_page(page, f.read())[0]
        for line, value, file, expression in runs:
            errors.append(check_value(root, f"{page}:{line}: {value} (run marker)", value, file, expression))
        n += len(quoted_rows(page)) + len(runs)
    return [e for e in errors if e] + check_marked(pages)[0], n


def arguments(argv):
    import argparse
    p = argparse.ArgumentParser(prog="check_report.py", description="Check a report and the numbers docs quote from "
                                "its run (rules 1-4 of this script's text).")
    p.add_argument("report", nargs="?", help="the report.md of a run (its directory holds the run's files)")
    p.add_argument("--numbers", nargs="+", metavar="PAGE", help="pages (or directories of pages) whose quoted numbers "
                   "are read against the run: their tables and run markers, and no number unmarked")
    p.add_argument("--unmarked", nargs="+", metavar="PAGE", help="without a run: only that every number these pages "
                   "quote from a run is checked, cited or dated (rule 4)")
    a = p.parse_args(argv[1:])
    if (a.report is None) == (a.unmarked is None) or (a.unmarked and a.numbers):
        p.error("give REPORT.md [--numbers PAGE ...], or --unmarked PAGE ...")
    return a


def main_unmarked(paths):
    pages = pages_of(paths)
    errors, rows, runs = check_marked(pages)
    for e in errors:
        print(f"check_report: {e}", file=sys.stderr)
    print(f"check_report: {len(pages)} pages read: {rows} quoted-table rows and {runs} run markers (checked against a "
          f"run with --numbers); {len(errors)} numbers quoted without a check, a citation or a date, or bad markers")
    return 1 if errors else 0


def main(argv):
    a = arguments(argv)
    if a.unmarked:
        return main_unmarked(a.unmarked)
    report = a.report
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
    numbers = check_numbers(root, pages_of(a.numbers)) if a.numbers else ([], 0)
    for e in numbers[0]:
        print(f"check_report: {e}", file=sys.stderr)
    if a.numbers:
        print(f"check_report: {numbers[1]} numbers quoted in {' '.join(a.numbers)} read against the run; "
              f"{len(numbers[0])} differ or are quoted unmarked")
    return 1 if bad or errors or numbers[0] else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
