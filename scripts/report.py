#!/usr/bin/python3
"""slipfront report: plots and report.md for every results.h5 and study.h5 under DIR.

Run with /usr/bin/python3 (Debian's numpy, h5py, matplotlib). Called by `slipfront report DIR`.
Scene files (results.h5) are plotted with plot.py; studies (study.h5) get their convergence plots,
each with its fitted slope and 95% interval; report.md collects the figures and a summary in three tables: limits
that must hold (each against the model or limit it is supposed to reach, with statistic, threshold and verdict),
effects of a parameter (differences, no verdict) and measurements (docs/studies.md, "The report").
"""
import argparse
import concurrent.futures
import csv
import hashlib
import io
import math
import multiprocessing
import os
import re
import sys
import tempfile
import textwrap

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot  # noqa: E402


def attrs(group):
    return {k: (plot.as_str(v) if isinstance(v, (bytes, str)) else plot.as_float(v)) for k, v in group.attrs.items()}


class Study:
    def __init__(self, path):
        self.path = path
        self.dir = os.path.dirname(os.path.abspath(path))
        self.f = h5py.File(path, "r")
        s = self.f["study"]
        self.name = plot.as_str(s.attrs["name"])
        self.stem = self.name  # the start of its figures' names (main: with the file's figure_key)
        self.kind = plot.as_str(s.attrs["kind"])
        self.description = plot.as_str(s.attrs.get("description", ""))
        self.notes = [n for n in plot.as_str(s.attrs.get("notes", "")).split("\n") if n]
        self.scalars = {k: plot.as_float(v) for k, v in s["scalars"].attrs.items() if k != "description"}
        self.definitions = {k: plot.as_str(v) for k, v in s["definitions"].attrs.items()}
        self.tables = {t: {c: np.asarray(s["tables"][t][c][()], dtype=float) for c in s["tables"][t]}
                       for t in s["tables"]}
        self.runs = []
        for line in plot.as_str(s["runs"].attrs.get("runs", "")).split("\n"):
            if not line.strip():
                continue
            parts = line.split()
            # (a varied array value, e.g. models = ["continuum", "mean_field"], has spaces: its later words are skipped)
            point = dict(p.split("=", 1) for p in parts[1:] if "=" in p)
            self.runs.append((parts[0], point))
        meta = self.f["meta"].attrs
        self.status = plot.as_str(meta.get("status", "unknown"))
        self.wall = plot.as_float(meta.get("wall_seconds", math.nan))
        self.commit = plot.as_str(meta.get("git_commit", "unknown"))
        self.source = path  # the file relative to the report's DIR (main sets it)

    def widths(self):
        """The threshold widths w of the study's discrete runs (the varied discrete.width, else the first run's
        resolved config); {0.0} when none can be read."""
        out = set()
        for run_id, point in self.runs:
            if "discrete.width" in point:
                out.add(float(point["discrete.width"]))
        if not out:
            for run_id, _ in self.runs[:1]:
                try:
                    with h5py.File(self.run_file(run_id), "r") as f:
                        cfg = plot.read_config(f).get("discrete", {})
                    if cfg.get("threshold", "delta") != "delta":
                        out.add(float(cfg.get("width", 0.0)))
                except (OSError, KeyError, ValueError):
                    pass
        return out or {0.0}

    def w_label(self):
        return ", ".join(f"{w:g}" for w in sorted(self.widths()))

    def run_file(self, run_id):
        return os.path.join(self.dir, "runs", run_id, "results.h5")

    def fit_label(self, name):
        p = self.scalars.get(name, math.nan)
        lo, hi = self.scalars.get(name + "_ci_low", math.nan), self.scalars.get(name + "_ci_high", math.nan)
        if not math.isfinite(p):
            return "fit: n/a"
        return f"slope {p:.3f} (95% CI {lo:.3f} .. {hi:.3f})"

    def best_fit(self, name):
        """The mean-field-regime fit (name_from) where the study has one, else the fit over all points."""
        return name + "_from" if math.isfinite(self.scalars.get(name + "_from", math.nan)) else name

    def fit_labels(self, name):
        if name + "_from" in self.scalars and math.isfinite(self.scalars[name + "_from"]):
            return f"{self.fit_label(name + '_from')} for N >= fit_from; all N: {self.fit_label(name)}"
        return self.fit_label(name)

    def title(self, what):
        return f"study {self.name}: {what}   [commit {self.commit[:12]}, {self.status}]"


def loglog_fit(ax, x, y, study, fit_name, label, color="C3", marker="o"):
    x, y = np.asarray(x), np.asarray(y)
    ok = np.isfinite(x) & np.isfinite(y) & (y > 0)
    ax.loglog(x[ok], y[ok], marker=marker, ls="none", color=color, label=label)
    p = study.scalars.get(fit_name, math.nan)
    points = int(study.scalars.get(fit_name + "_points", 0) or 0)
    if fit_name.endswith("_from") and 2 <= points <= ok.sum():
        ok = ok & (x >= np.sort(x[ok])[-points])  # fitted over the largest N only: draw it there
    if math.isfinite(p) and ok.sum() >= 2:
        lx, ly = np.log(x[ok]), np.log(y[ok])
        c = np.mean(ly - p * lx)
        xs = np.linspace(lx.min(), lx.max(), 50)
        ax.loglog(np.exp(xs), np.exp(c + p * xs), "-", color=color, alpha=0.6, label=study.fit_label(fit_name))


def figure_key(root, path):
    """The name of one file's figures (results.h5, study.h5, fronts.h5): the file's path relative to DIR and
    a hash of that path, so two runs of one scene, or two studies of one name, never share figure files.
    ASCII only (it is a link in report.md)."""
    rel = os.path.splitext(os.path.relpath(os.path.abspath(path), root))[0]
    slug = re.sub(r"[^A-Za-z0-9._-]+", "_", rel.replace(os.sep, "__")).strip("._") or "top"
    digest = hashlib.sha1(rel.encode("utf-8", "surrogateescape")).hexdigest()[:8]
    return f"{slug[:80]}-{digest}"


def figure_dir(figdir, root, path):
    """A scene's figures: the directory figures/<figure_key>/ (created)."""
    out = os.path.join(figdir, figure_key(root, path))
    os.makedirs(out, exist_ok=True)
    return out


def write_report(path, text):
    """report.md written to a temporary file beside it and renamed onto it: a failure (a full disk, an error)
    leaves the previous report as it was. Text that is not UTF-8 (paths or metadata read with surrogate
    escapes) is written with U+FFFD."""
    text = text.encode("utf-8", "surrogateescape").decode("utf-8", "replace")
    fd, tmp = tempfile.mkstemp(prefix=".report.md.", suffix=".tmp", dir=os.path.dirname(path))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def save(fig, outdir, name, figures):
    path = os.path.join(outdir, name)
    plot.units_note(fig)
    fig.savefig(path, dpi=110, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)
    figures.append(path)
    return path


# --------------------------------------------------------------------------------------------
# summary rows: each is a limit that must hold (with its statistic, threshold and verdict), an effect of a
# parameter (a difference, no verdict), or a measurement (neither). docs/studies.md "The report".

SCENE_EVENT_TOL = 0.05  # a scene's event within 5 % of its limit's (one run at one N; not a significance test)
IDENTITY_TOL = 1e-12  # noise off, w = 0 (or the mean_field reference): the discrete update is the reference's
CONTACTS_FAMILY_ALPHA = 0.01  # contact-statistics rows: family false-alarm rate, Bonferroni over a scene's rows
NRATE = -0.5  # the random part of the error falls like N^-1/2 (docs/model.md §2.1 item 2)
BIAS_TOL = 0.01  # the validity map's 1 % (docs/model.md §8)
STRIP_THIN_TOL = 0.005  # the strip_height study's H -> 0 check (docs/studies.md)


def limit_row(limit, observable, reference, ref_value, disc_value, statistic, threshold, verdict, source, w="",
              score=None):
    """A limit that must hold: `reference` names the model (or limit) the discrete value is tested against;
    `verdict` is "pass", "FAIL" or "n/a" (no statistic); `source` the file (relative to DIR) it was read from;
    `score` (optional) the statistic over its threshold, >= 1 where it fails: the first screen's digest names the
    row with the largest as its limit's worst."""
    return {"kind": "limit", "limit": limit, "observable": observable, "reference": reference, "ref": ref_value,
            "disc": disc_value, "statistic": statistic, "threshold": threshold, "verdict": verdict,
            "source": source, "w": w, "score": score}


def effect_row(parameter, observable, without, with_, difference, note, source):
    """An effect of a parameter: the value without it (the reference), with it, their difference; no verdict."""
    return {"kind": "effect", "parameter": parameter, "observable": observable, "without": without, "with": with_,
            "difference": difference, "note": note, "source": source}


def answer_row(question, answer, yes=None, short="", figure="", order=99):
    """The answer to one of the paper's questions, from the numbers: on the first screen as "Yes — short" or
    "No — short" (`yes`; None: no answer word) with its figure (an absolute path), in the paper's `order`; the full
    `answer` under "The paper's questions" after it."""
    return {"kind": "answer", "question": question, "answer": answer, "yes": yes, "short": short or answer,
            "figure": figure, "order": order}


def measure_row(observable, c="", d="", diff="", note=""):
    """A measurement (neither a limit tested nor an effect): the report's former five columns."""
    return {"kind": "measure", "cells": (observable, c, d, diff, note)}


def verdict_of(ok):
    return "n/a" if ok is None else ("pass" if ok else "FAIL")


def ci_contains(st, name, value):
    """Whether the 95 % interval of the fitted scalar `name` contains `value` (None: no fit)."""
    lo, hi = st.scalars.get(name + "_ci_low", math.nan), st.scalars.get(name + "_ci_high", math.nan)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return None
    return lo <= value <= hi


def ci_score(st, name, value):
    """How far `value` lies from the fit `name` in units of the 95 % interval's half on its side (>= 1: outside
    the interval; None: no fit): the score of a row whose verdict is ci_contains."""
    p = st.scalars.get(name, math.nan)
    lo, hi = st.scalars.get(name + "_ci_low", math.nan), st.scalars.get(name + "_ci_high", math.nan)
    half = (hi - p) if value > p else (p - lo)
    if not all(math.isfinite(x) for x in (p, lo, hi)) or half <= 0:
        return None
    return abs(value - p) / half


def fmt_w(w):
    return f"{w:g}"


def cell(s):
    return str(s).replace("|", "\\|").replace("\n", " ")


LIMIT_COLUMNS = ("limit", "observable", "reference", "ref", "disc", "statistic", "threshold", "verdict", "w")
LIMIT_HEADS = ("limit", "observable", "reference", "reference value", "discrete value", "statistic", "threshold",
               "verdict", "w")
EFFECT_COLUMNS = ("parameter", "observable", "without", "with", "difference", "note")
EFFECT_HEADS = ("parameter", "observable", "without it (reference)", "with it", "difference", "note")
MEASURE_HEADS = ("observable", "continuum (or the value)", "discrete (largest N)", "difference", "note")


def summary_tables(rows):
    """The summary as markdown lines: the full answers to the paper's questions, then the three tables: limits that
    must hold, effects of a parameter, other measurements (also written as CSV by summary_csv)."""
    lim = [r for r in rows if r["kind"] == "limit"]
    eff = [r for r in rows if r["kind"] == "effect"]
    mea = [r for r in rows if r["kind"] == "measure"]
    ans = sorted((r for r in rows if r["kind"] == "answer"), key=lambda r: r["order"])
    out = ["## Summary", "",
           f"The full tables, also as CSV: `{CSV_NAMES['limit']}`, `{CSV_NAMES['effect']}`, `{CSV_NAMES['measure']}`.",
           ""]
    if ans:
        out += ["### The paper's questions", "",
                "The answers on the first screen, with their numbers (Bouchbinder et al. 2011; the 2D ones in a body "
                "of finite height H: docs/fronts.md §10.12, §10.16; on the paper's in-plane body §11.8, §11.9, §12).", ""]
        out += [f"- **{cell(r['question'])}** {cell(r['answer'])}" for r in ans]
        out += [""]
    out += [
           "Three tables (docs/studies.md, \"The report\"): **limits that must hold** are tested, each against the "
           "model or limit it is supposed to reach, with a statistic, its threshold and a verdict; **effects of a "
           "parameter** (threshold disorder w, N below the validity crossover, the strip height H) are differences "
           "a parameter causes, shown without a verdict: they are results, not failures; **measurements** are "
           "neither.", "",
           "### Limits that must hold", "",
           f"{len(lim)} rows, {sum(r['verdict'] == 'pass' for r in lim)} pass, "
           f"{sum(r['verdict'] == 'FAIL' for r in lim)} fail, {sum(r['verdict'] == 'n/a' for r in lim)} without a "
           "statistic.", "",
           "| " + " | ".join(LIMIT_HEADS) + " | file |", "|" + " --- |" * (len(LIMIT_HEADS) + 1)]
    out += ["| " + " | ".join(cell(r[k]) for k in LIMIT_COLUMNS) + f" | `{cell(r['source'])}` |" for r in lim]
    out += ["", "### Effects of a parameter", "",
            "| " + " | ".join(EFFECT_HEADS) + " | file |", "|" + " --- |" * (len(EFFECT_HEADS) + 1)]
    out += ["| " + " | ".join(cell(r[k]) for k in EFFECT_COLUMNS) + f" | `{cell(r['source'])}` |" for r in eff]
    out += ["", "### Measurements", "", "| " + " | ".join(MEASURE_HEADS) + " |", "|" + " --- |" * len(MEASURE_HEADS)]
    out += [f"| {' | '.join(cell(c) for c in r['cells'])} |" for r in mea]
    return out + [""]


CSV_NAMES = {"limit": "summary_limits.csv", "effect": "summary_effects.csv", "measure": "summary_measurements.csv"}


def summary_csv(root, rows):
    """The three tables of the summary as CSV files in DIR (CSV_NAMES), one row per table row, the same columns."""
    tables = {"limit": (LIMIT_HEADS + ("file",), lambda r: [r[k] for k in LIMIT_COLUMNS] + [r["source"]]),
              "effect": (EFFECT_HEADS + ("file",), lambda r: [r[k] for k in EFFECT_COLUMNS] + [r["source"]]),
              "measure": (MEASURE_HEADS, lambda r: list(r["cells"]))}
    for kind, (heads, values) in tables.items():
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(heads)
        w.writerows(values(r) for r in rows if r["kind"] == kind)
        write_report(os.path.join(root, CSV_NAMES[kind]), buf.getvalue())


def reference_of(res):
    """The model the file's /compare compared the discrete model with (docs/output.md): its attribute
    `reference`, absent for the continuum; without /compare, mean_field when the file has it, else continuum."""
    if "compare" in res.f:
        return plot.as_str(res.f["compare"].attrs.get("reference", "continuum"))
    return "mean_field" if "mean_field" in res.models else "continuum"


def disorder_of(res):
    """(w, noise on) of the file's discrete model, from its resolved config."""
    w = plot.as_float(res.param("discrete", "width", 0.0))
    w = 0.0 if w is None or not math.isfinite(w) else float(w)
    if str(res.param("discrete", "threshold", "delta")) == "delta":
        w = 0.0
    return w, bool(res.param("discrete", "noise", True))


# --------------------------------------------------------------------------------------------
# one plot function per study kind; each returns (figures, summary rows)


def friction_law_study(st, outdir):
    figs, rows = [], []
    t = st.tables.get("friction_law_error", {})
    if t:
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        loglog_fit(ax, t["N"], t["random"], st, st.best_fit("friction_law_random_exponent"), "random part", "C3", "o")
        ax.loglog(t["N"], t["bias"], "s", color="C1", label="bias (seed mean)")
        ax.loglog(t["N"], t["batch_stderr"], "x", color="C2", label="batch-means stderr")
        ax.loglog(t["N"], t["random"][0] * (t["N"] / t["N"][0]) ** -0.5, ":", color="gray", label="N^-1/2")
        ax.set_xlabel("contacts per site N")
        ax.set_ylabel("relative error of steady friction (RMS over v)")
        ax.set_title(st.title("friction law, discrete vs continuum"), fontsize=8)
        ax.legend(fontsize=8)
        save(fig, outdir, f"{st.stem}_error_vs_N.png", figs)
    # Fig. 2 (left): the steady law of both models at each N (seed 1) and the closed form.
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    drawn_cont = False
    seen = set()
    for run_id, point in st.runs:
        N = point.get("discrete.contacts_per_site")
        if N in seen or not os.path.exists(st.run_file(run_id)):
            continue
        seen.add(N)
        with h5py.File(st.run_file(run_id), "r") as f:
            if "discrete/friction_law" in f:
                g = f["discrete/friction_law"]
                ax.errorbar(g["v"][()], g["sigma"][()], yerr=g["sigma_stderr"][()], marker=".", ls="-", lw=0.8,
                            capsize=2, label=f"discrete N={N}")
            if not drawn_cont and "continuum/friction_law" in f:
                g = f["continuum/friction_law"]
                ax.plot(g["v"][()], g["sigma"][()], "ko", mfc="none", label="continuum")
                ax.plot(g["v"][()], g["sigma_closed_form"][()], "k-", lw=0.8, label="closed form")
                drawn_cont = True
    ax.set_xscale("log")
    ax.set_xlabel("slip rate v")
    ax.set_ylabel("steady friction sigma")
    ax.set_title(st.title("Fig. 2 (left): steady friction law"), fontsize=8)
    ax.legend(fontsize=8)
    save(fig, outdir, f"{st.stem}_fig2_left.png", figs)
    if t:
        fit = st.best_fit("friction_law_random_exponent")
        rows.append(limit_row("N-rate of a study: discrete -> continuum as N^-1/2", f"{st.name}: steady friction, random "
                              f"error at N = {t['N'][-1]:.0f}", "continuum", "0", f"{t['random'][-1]:.3g}",
                              st.fit_labels("friction_law_random_exponent"), "95% CI of the slope contains -1/2",
                              verdict_of(ci_contains(st, fit, NRATE)), st.source, st.w_label(),
                              score=ci_score(st, fit, NRATE)))
        rows.append(limit_row("discrete -> continuum as N -> inf at w = 0", f"{st.name}: steady friction, bias at "
                              f"N = {t['N'][-1]:.0f}", "continuum", "0", f"{t['bias'][-1]:.3g}", "bias (seed mean)",
                              "<= 1%", verdict_of(t["bias"][-1] <= BIAS_TOL if math.isfinite(t["bias"][-1]) else None),
                              st.source, st.w_label()))
    return figs, rows


def threshold_width_study(st, outdir):
    figs, rows = [], []
    t = st.tables.get("threshold_width", {})
    if not t:
        return figs, rows
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    loglog_fit(ax, t["width"], t["distance"], st, "threshold_width_exponent", "distance to continuum", "C3")
    ax.set_xlabel("threshold width w")
    ax.set_ylabel("RMS relative distance of steady friction")
    ax.set_title(st.title("threshold disorder, noise off"), fontsize=8)
    ax.legend(fontsize=8)
    save(fig, outdir, f"{st.stem}_distance_vs_w.png", figs)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    cont = False
    steady = "sigma_at_vmin" in t
    for run_id, point in st.runs:
        if not os.path.exists(st.run_file(run_id)):
            continue
        with h5py.File(st.run_file(run_id), "r") as f:
            label = f"w = {point.get('discrete.width')}"
            if steady and "discrete/friction_law" in f:
                g = f["discrete/friction_law"]
                ax.plot(g["v"][()], g["sigma"][()], "-", lw=1, label=label)
            elif not steady and "discrete/series/drive_force" in f:
                ax.plot(f["discrete/series/t"][()], f["discrete/series/drive_force"][()], "-", lw=1, label=label)
            if not cont and steady and "continuum/friction_law" in f:
                g = f["continuum/friction_law"]
                ax.plot(g["v"][()], g["sigma"][()], "k--", lw=1.2, label="continuum")
                cont = True
            elif not cont and not steady and "continuum/series/drive_force" in f:
                ax.plot(f["continuum/series/t"][()], f["continuum/series/drive_force"][()], "k--", lw=1.2,
                        label="continuum")
                cont = True
    if steady:
        ax.set_xscale("log")
        ax.set_xlabel("slip rate v")
        ax.set_ylabel("steady friction sigma")
        ax.set_title(st.title("steady law vs threshold width w (noise off)"), fontsize=8)
    else:
        ax.set_xlabel("t")
        ax.set_ylabel("drive force F")
        ax.set_title(st.title("static peak and slip vs threshold width w (noise off)"), fontsize=8)
    ax.legend(fontsize=8)
    save(fig, outdir, f"{st.stem}_{'laws' if steady else 'histories'}_vs_w.png", figs)
    k = int(np.argmin(t["width"]))
    lim = "discrete (noise off) -> continuum as w -> 0"
    rows.append(limit_row(lim, f"{st.name}: distance to the continuum at w = {t['width'][k]:.3g}", "continuum", "0",
                          f"{t['distance'][k]:.3g}", "rate " + st.fit_label("threshold_width_exponent"),
                          "<= 1% at the smallest w", verdict_of(abs(t["distance"][k]) <= BIAS_TOL
                                                                 if math.isfinite(t["distance"][k]) else None),
                          st.source, f"{t['width'][k]:g}"))
    if "threshold_width_peak_exponent" in st.scalars:
        rows.append(limit_row(lim, f"{st.name}: static peak shift at w = {t['width'][k]:.3g}", "continuum", "0",
                              f"{t['F_peak_shift'][k]:.3g}", "rate " + st.fit_label("threshold_width_peak_exponent"),
                              "<= 1% at the smallest w", verdict_of(abs(t["F_peak_shift"][k]) <= BIAS_TOL
                                                                     if math.isfinite(t["F_peak_shift"][k]) else None),
                              st.source, f"{t['width'][k]:g}"))
    return figs, rows


def transient_friction_study(st, outdir):
    figs, rows = [], []
    t = st.tables.get("transient_friction", {})
    if not t:
        return figs, rows
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.5))
    loglog_fit(axs[0], t["N"], t["distance_mean"], st, st.best_fit("transient_distance_exponent"),
               "curve distance (mean over seeds)")
    axs[0].set_xlabel("contacts per site N")
    axs[0].set_ylabel("relative RMS distance of friction history")
    axs[0].legend(fontsize=8)
    seen, cont = set(), False
    for run_id, point in st.runs:
        N = point.get("discrete.contacts_per_site")
        if N in seen or not os.path.exists(st.run_file(run_id)):
            continue
        seen.add(N)
        with h5py.File(st.run_file(run_id), "r") as f:
            col = "sigma" if "discrete/series/sigma" in f and "continuum/cycles" not in f else "drive_force"
            if "discrete/series" in f:
                axs[1].plot(f["discrete/series/t"][()], f[f"discrete/series/{col}"][()], lw=0.7, label=f"discrete N={N}")
            if not cont and "continuum/series" in f:
                axs[1].plot(f["continuum/series/t"][()], f[f"continuum/series/{col}"][()], "k-", lw=1.2,
                            label="continuum")
                cont = True
    axs[1].set_xlabel("t")
    axs[1].set_ylabel("friction")
    axs[1].legend(fontsize=8)
    fig.suptitle(st.title("transient friction, discrete vs continuum"), fontsize=8)
    save(fig, outdir, f"{st.stem}_transient.png", figs)
    rows.append(limit_row("N-rate of a study: discrete -> continuum as N^-1/2", f"{st.name}: friction history distance "
                          f"at N = {t['N'][-1]:.0f}", "continuum", "0", f"{t['distance_mean'][-1]:.3g}",
                          st.fit_labels("transient_distance_exponent"), "95% CI of the slope contains -1/2",
                          verdict_of(ci_contains(st, st.best_fit("transient_distance_exponent"), NRATE)), st.source,
                          st.w_label(), score=ci_score(st, st.best_fit("transient_distance_exponent"), NRATE)))
    return figs, rows


def front_speeds_study(st, outdir):
    figs, rows = [], []
    t = st.tables.get("front_speeds", {})
    if not t:
        return figs, rows
    obs = ["t_star", "t_hat", "c_slow_alt", "c_transient", "x_arrest"]
    fig, axs = plt.subplots(2, len(obs), figsize=(4 * len(obs), 7.5))
    N = t["N"]
    for k, o in enumerate(obs):
        ax = axs[0, k]
        ax.errorbar(N, t[o + "_mean"], yerr=t[o + "_sd"], marker="o", color="C3", capsize=3, label="discrete mean ± sd")
        ax.axhline(t[o + "_continuum"][0], color="C0", label="continuum")
        # every seed's value
        for run_id, point in st.runs:
            p = st.run_file(run_id)
            if not os.path.exists(p):
                continue
            with h5py.File(p, "r") as f:
                if "discrete/events" in f:
                    key = "c_slow_alt" if o == "c_slow_alt" else o
                    ax.plot(float(point["discrete.contacts_per_site"]), plot.as_float(f["discrete/events"].attrs[key]),
                            ".", color="gray", alpha=0.5)
        ax.set_xscale("log")
        ax.set_title(o, fontsize=9)
        ax.set_xlabel("N")
        if k == 0:
            ax.legend(fontsize=8)
        ax2 = axs[1, k]
        loglog_fit(ax2, N, t[o + "_sd"], st, st.best_fit(f"front_{o}_sd_exponent"), "sd over seeds", "C3", "o")
        absd = np.abs(t[o + "_rel_diff"])
        ax2.loglog(N[absd > 0], absd[absd > 0], "s", color="C1", label="|mean - continuum|/continuum")
        ax2.set_xlabel("N")
        ax2.legend(fontsize=8)
    fig.suptitle(st.title("fig1 events and front speeds vs N (discrete over seeds)"), fontsize=9)
    fig.tight_layout()
    save(fig, outdir, f"{st.stem}_fronts_vs_N.png", figs)
    for o in obs:
        fit = st.best_fit(f"front_{o}_sd_exponent")
        rows.append(limit_row("N-rate of a study: spread over seeds as N^-1/2",
                              f"{st.name}: {o}, mean ± sd over seeds at N = {N[-1]:.0f}", "continuum",
                              f"{t[o + '_continuum'][-1]:.4g}", f"{t[o + '_mean'][-1]:.4g} ± {t[o + '_sd'][-1]:.2g} "
                              f"({t[o + '_rel_diff'][-1]:+.2%})", "spread: " + st.fit_label(fit),
                              "95% CI of the slope contains -1/2", verdict_of(ci_contains(st, fit, NRATE)), st.source,
                              st.w_label(), score=ci_score(st, fit, NRATE)))
    return figs, rows


def fig2_study(st, outdir):
    figs, rows = [], []
    groups = {k[len("fig2_"):]: v for k, v in st.tables.items()
              if k.startswith("fig2_") and k not in ("fig2_all", "fig2_heights")}
    if not groups:
        return figs, rows
    heights = st.tables.get("fig2_heights", {})
    if heights and len(heights.get("H", [])) > 1:
        return fig2_bodies_plots(st, outdir, *fig2_strip_plots(st, outdir))
    fig, axs = plt.subplots(1, 2, figsize=(12, 5))
    for i, (name, t) in enumerate(sorted(groups.items())):
        for ax, m in zip(axs, ("continuum", "discrete")):
            y = t["c_" + m]
            ok = np.isfinite(y)
            a = st.scalars.get(f"fig2_slope_{name}_{m}", math.nan)
            ax.plot(t["X"][ok], y[ok], "os^vD"[i % 5], color=f"C{i}", label=f"vary {name}: slope {a:.2f}")
    allt = st.tables.get("fig2_all", {})
    for ax, m in zip(axs, ("continuum", "discrete")):
        a = st.scalars.get(f"fig2_slope_all_{m}", math.nan)
        if allt and math.isfinite(a):
            xs = np.linspace(0, np.nanmax(allt["X"]) * 1.05, 10)
            ax.plot(xs, a * xs, "k--", lw=1, label=f"all: slope {a:.2f}")
        ax.set_xlabel("sqrt(mu alpha / (eta kappa))")
        ax.set_ylabel("transient front speed c")
        ax.set_title(m, fontsize=9)
        ax.legend(fontsize=8)
    fig.suptitle(st.title("Fig. 2 (right): transient front speed collapse"), fontsize=9)
    save(fig, outdir, f"{st.stem}_fig2_right.png", figs)
    for m in ("continuum", "discrete"):
        slope = f"{st.scalars.get('fig2_slope_all_' + m, math.nan):.3g}"
        rows.append(measure_row(f"Fig. 2 right slope ({m})", slope if m == "continuum" else "",
                                slope if m == "discrete" else "", "", "c_transient against sqrt(mu alpha/(eta kappa)), "
                                "through the origin, every run"))
    rows += fig2_answer(st, groups, figs[-1])
    if heights and len(heights.get("H", [])) == 1:
        for m in ("continuum", "discrete"):
            if np.isfinite(heights[f"slope_{m}"][0]):
                slope = f"{heights[f'slope_{m}'][0]:.3g}"
                rows.append(measure_row(f"Fig. 2 right against c_min, slope ({m})", slope if m == "continuum" else "",
                                        slope if m == "discrete" else "", "",
                                        f"c_transient/c_min {heights[f'ratio_mean_{m}'][0]:.3g} "
                                        f"± {100 * heights[f'ratio_rsd_{m}'][0]:.0f} % over "
                                        f"{int(heights[f'measured_{m}'][0])} runs (docs/fronts.md §10.16)"))
    return figs, rows


FIG2_SPREAD = 1.25  # Fig. 2 right "collapses": the largest of the per-parameter slopes within 25 % of the smallest


def fig2_answer(st, groups, figure):
    """Fig. 2 right's answer: the continuum's transient speeds collapse on one line when the slopes of the runs
    varying each of mu, alpha, eta, kappa agree within FIG2_SPREAD."""
    slopes = {n: st.scalars.get(f"fig2_slope_{n}_continuum", math.nan) for n in sorted(groups)}
    finite = [v for v in slopes.values() if math.isfinite(v) and v > 0]
    a = st.scalars.get("fig2_slope_all_continuum", math.nan)
    if not finite or not math.isfinite(a):
        return []
    yes = len(finite) == len(slopes) and max(finite) <= FIG2_SPREAD * min(finite)
    short = (f"c_transient = {a:.2f} sqrt(mu alpha/(eta kappa)); the slopes varying "
             f"{', '.join(slopes)} alone lie within {min(finite):.2f} .. {max(finite):.2f}"
             + ("" if yes else f", more than {FIG2_SPREAD - 1:.0%} apart"))
    return [answer_row("Fig. 2 right: does the transient front speed scale as sqrt(mu alpha/(eta kappa))?",
                       short + " (continuum).", yes, short, figure, 3)]


def fig2_bodies_plots(st, outdir, figs, rows):
    """Fig. 2 (right) in-plane beside the antiplane strip and the 1D chain (issue 39 item 3, docs/fronts.md §11.9): for a
    fig2 study whose runs are on the in-plane strip (fig2_all/inplane), c_transient against the run's own c_min per
    height, beside the antiplane study of the main job (../fig2_strip/study.h5: its strips and its chain); one summary
    row per in-plane height against the antiplane strip at the same H. `figs`, `rows` (fig2_strip_plots') are returned
    with these added; unchanged for any other fig2 study or when ../fig2_strip is missing."""
    a = st.tables.get("fig2_all", {})
    if "inplane" not in a or not np.any(a["inplane"] == 1):
        return figs, rows
    other = None
    path = os.path.join(os.path.dirname(st.dir), "fig2_strip", "study.h5")
    if os.path.exists(path):
        try:
            other = Study(path).tables.get("fig2_all")
        except (OSError, KeyError) as e:
            print(f"report.py: warning: {path}: {e}", file=sys.stderr)
    Hs = sorted(set(a["H"][a["inplane"] == 1]))
    fig, axs = plt.subplots(1, len(Hs) + 1, figsize=(5 * (len(Hs) + 1), 5), squeeze=False)
    axs = axs[0]

    def draw(ax, t, sel, mk, col, lab):
        x, y = t["c_min"][sel], t["c_continuum"][sel]
        ok = np.isfinite(x) & np.isfinite(y)
        ax.plot(x[ok], y[ok], mk, color=col, mfc="none" if col != "C0" else col, label=lab)
        return x[ok], y[ok]
    for k, H in enumerate(Hs):
        ax = axs[k]
        xi, yi = draw(ax, a, (a["H"] == H) & (a["inplane"] == 1), "o", "C0", f"in-plane H = {H:g}")
        if other is not None:
            draw(ax, other, other["H"] == H, "s", "C1", f"antiplane H = {H:g}")
        top = max(np.nanmax(xi) if xi.size else 1.0, np.nanmax(yi) if yi.size else 1.0) * 1.1
        ax.plot([0, top], [0, top], "k:", lw=1, label="c_transient = c_min")
        ax.set_xlabel("c_min of the run's own strip")
        ax.set_ylabel("c_transient (continuum)")
        ax.set_title(f"H = {H:g}", fontsize=9)
        ax.legend(fontsize=8)
        r = yi / xi
        if r.size:
            mine = fig2_below_text(fig2_below(a, (a["H"] == H) & (a["inplane"] == 1)), "in-plane runs")
            line = (f"in-plane H = {H:g}: c_transient/c_min {np.mean(r):.3g} (scatter {100 * np.std(r, ddof=1) / np.mean(r):.0f} %"
                    f" over {r.size} runs), {mine}")
            base = ""
            if other is not None:
                sel = (other["H"] == H) & np.isfinite(other["ratio_continuum"])
                if sel.any():
                    ro = other["ratio_continuum"][sel]
                    base = f"antiplane {np.mean(ro):.3g} ({fig2_below_text(fig2_below(other, sel), 'runs')})"
            rows.append(effect_row(f"body at H = {H:g}: in-plane vs antiplane strip", "c_transient / c_min, mean over runs",
                                   base or "no antiplane study beside", f"{np.mean(r):.3g}", mine,
                                   line + " (docs/fronts.md §11.9)", st.source))
    ax = axs[-1]
    for k, H in enumerate(Hs):
        sel = (a["H"] == H) & (a["inplane"] == 1)
        x, y = a["X"][sel], a["c_continuum"][sel]
        ok = np.isfinite(y)
        ax.plot(x[ok], y[ok], "o^s"[k % 3], color=f"C{k + 2}", label=f"in-plane H = {H:g}")
    if other is not None:
        ch = other["H"] == 0
        ax.plot(other["X"][ch], other["c_continuum"][ch], "D", color="k", mfc="none", label="1D chain (fig2_strip)")
    ax.set_xlabel("sqrt(mu alpha/(eta kappa)), mu = E'H (in-plane), integrated")
    ax.set_ylabel("c_transient")
    ax.set_title("the paper's axis: in-plane and the 1D chain", fontsize=9)
    ax.legend(fontsize=8)
    fig.suptitle(st.title("Fig. 2 (right) in-plane beside the antiplane strip and the 1D chain"), fontsize=9)
    save(fig, outdir, f"{st.stem}_fig2_right_bodies.png", figs)
    for r in rows:  # the in-plane answer links the figure that puts it beside the antiplane strip and the chain
        if r["kind"] == "answer" and "in-plane" in r["question"]:
            r["figure"] = figs[-1]
    return figs, rows


def fig2_below(a, sel, m="continuum"):
    """How many runs of `sel` (fig2_all) run below their own c_min: (beyond, raw, without, n) — below c_min by more than
    c_min's estimate (fig2_all/c_min_error, docs/fronts.md §10.20), below it at all, below it with no estimate (NaN: not
    counted as beyond), and the runs with both speeds. The transient's own error is not in the study (none is counted);
    a file written before c_min carried its estimate counts every run below as without one."""
    c, cm = a["c_" + m][sel], a["c_min"][sel]
    err = a["c_min_error"][sel] if "c_min_error" in a else np.full(cm.shape, np.nan)
    ok = np.isfinite(c) & np.isfinite(cm)
    below = ok & (c < cm)
    beyond = below & np.isfinite(err) & (c < cm - err)
    return int(np.sum(beyond)), int(np.sum(below)), int(np.sum(below & ~np.isfinite(err))), int(np.sum(ok))


def fig2_below_text(counts, what="runs"):
    """'8 of 13 runs below c_min by more than its estimate (10 below it at all)': fig2_below's counts in words."""
    beyond, raw, without, n = counts
    text = f"{beyond} of {n} {what} below c_min by more than its estimate"
    more = [f"{raw} below it at all"] if raw != beyond else []
    if without:
        more.append(f"{without} of them without an estimate")
    return text + (f" ({'; '.join(more)})" if more else "")


def fig2_is_inplane(a):
    """Whether every run of a fig2 study's table fig2_all is on the in-plane strip (its column inplane, issue 39)."""
    return "inplane" in a and a["inplane"].size > 0 and bool(np.all(a["inplane"] == 1))


def fig2_height_label(H, h, k):
    if H == 0:
        return "1D chain"
    return f"H = {H:g} (H/l {h['H_over_l_min'][k]:.2g}-{h['H_over_l_max'][k]:.2g})"


def fig2_strip_plots(st, outdir):
    """Fig. 2 (right) in the strip (docs/fronts.md §10.16): c_transient against sqrt(mu alpha/(eta kappa)) and
    against the run's own c_min, one colour per height; the ratio c_transient/c_min against H/l; one effect row
    per height against the chain (the effect of H on the collapse)."""
    figs, rows = [], []
    a, h = st.tables["fig2_all"], st.tables["fig2_heights"]
    Hs = list(h["H"])
    fig, axs = plt.subplots(1, 3, figsize=(16, 5))
    for k, H in enumerate(Hs):
        sel = a["H"] == H
        y = a["c_continuum"][sel]
        ok = np.isfinite(y)
        lab = fig2_height_label(H, h, k)
        axs[0].plot(a["X"][sel][ok], y[ok], "os^vD"[k % 5], color=f"C{k}", label=lab)
        cm = a["c_min"][sel]
        ok2 = ok & np.isfinite(cm)
        sl = h["slope_continuum"][k]
        axs[1].plot(cm[ok2], y[ok2], "os^vD"[k % 5], color=f"C{k}",
                    label=f"{lab}: slope {sl:.2f}, scatter {100 * h['ratio_rsd_continuum'][k]:.0f} %")
        if np.isfinite(sl) and ok2.any():
            xs = np.linspace(0, np.nanmax(cm[ok2]) * 1.05, 10)
            axs[1].plot(xs, sl * xs, "--", color=f"C{k}", lw=1)
        r = a["ratio_continuum"][sel]
        xpos = np.full(r.shape, H if H > 0 else 0.5)
        axs[2].plot(xpos[np.isfinite(r)], r[np.isfinite(r)], "os^vD"[k % 5], color=f"C{k}", label=lab)
    cmax = np.nanmax(a["c_min"]) * 1.05 if np.isfinite(a["c_min"]).any() else 1.0
    axs[1].plot([0, cmax], [0, cmax], "k:", lw=1, label="c_transient = c_min")
    axs[0].set_xlabel("sqrt(mu alpha / (eta kappa)), mu integrated")
    axs[0].set_ylabel("transient front speed c_transient (continuum)")
    axs[0].set_title("the paper's axis", fontsize=9)
    axs[1].set_xlabel("c_min of the run's own scene")
    axs[1].set_ylabel("c_transient")
    axs[1].set_title("against the minimal steady front speed", fontsize=9)
    axs[2].set_xscale("log")
    axs[2].axhline(1.0, color="k", ls=":", lw=1)
    axs[2].set_xlabel("H (the chain drawn at 0.5)")
    axs[2].set_ylabel("c_transient / c_min")
    axs[2].set_title("the ratio per run", fontsize=9)
    for ax in axs:
        ax.legend(fontsize=8)
    fig.suptitle(st.title("Fig. 2 (right) in the strip: transient fronts against c_min(H)"), fontsize=9)
    save(fig, outdir, f"{st.stem}_fig2_right_strip.png", figs)
    chain = Hs.index(0.0) if 0.0 in Hs else None
    parts = []
    for k, H in enumerate(Hs):
        where = "chain" if H == 0 else f"H = {H:g} (H/l ~ {h['H_over_l_max'][k]:.2g})"
        parts.append(f"{where}: slope "
                     f"{h['slope_continuum'][k]:.2f}, c_transient/c_min {h['ratio_mean_continuum'][k]:.2f} "
                     f"(scatter {100 * h['ratio_rsd_continuum'][k]:.0f} %), {fig2_below_text(fig2_below(a, a['H'] == H))}")
    if parts:
        # the answer counts only the transients below c_min by more than c_min's estimate (issue 39 item 6)
        below = [fig2_below(a, a["H"] == H) + (H,) for H in Hs]
        worst = max(below, key=lambda b: (b[0], b[1], b[4]))
        where = "the chain" if worst[4] == 0 else f"H = {worst[4]:g}"
        short = ("every transient runs above its own c_min, or below it by less than c_min's estimate, at every height"
                 if worst[0] == 0 else
                 f"at {where} {worst[0]} of {worst[3]} transients run below the slowest steady front of their own strip "
                 "by more than its estimate" + (f" ({worst[1]} below it at all)" if worst[1] != worst[0] else ""))
        inplane = fig2_is_inplane(a)
        body = ("on the paper's in-plane body of height H (Fig. 2 right in-plane)" if inplane else
                "in a body of height H (Fig. 2 right in the strip)")
        rows.append(answer_row(f"Are transient fronts excitations of the steady front at c_min {body}?",
                               "; ".join(parts) + ". A slope of order one with the transients above c_min is the "
                               "paper's picture; runs below c_min are transients slower than the slowest steady "
                               "front of their own strip. Counted below c_min: by more than c_min's estimate (the "
                               "transients' own error is not in the study).", worst[0] == 0, short, figs[-1], 5))
    for k, H in enumerate(Hs):
        mean, rsd, sl = h["ratio_mean_continuum"][k], h["ratio_rsd_continuum"][k], h["slope_continuum"][k]
        note = (f"slope through the origin {sl:.3g}, scatter {100 * rsd:.0f} % over {int(h['measured_continuum'][k])} runs "
                f"(docs/fronts.md §10.16)")
        if H == 0 or chain is None:
            rows.append(measure_row("Fig. 2 right against c_min, 1D chain (continuum)", f"{mean:.3g}", "", "", note))
            continue
        base = h["ratio_mean_continuum"][chain]
        rows.append(effect_row(f"strip height {fig2_height_label(H, h, k)}", "c_transient / c_min, mean over runs",
                               f"chain {base:.3g}", f"{mean:.3g}", f"{100 * (mean / base - 1):+.1f} %", note,
                               st.source))
    return figs, rows


def front_spectrum_study(st, outdir):
    figs, rows = [], []
    t = st.tables.get("front_spectrum", {})
    if not t:
        return figs, rows
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.5))
    b = st.tables.get("front_branch", {})
    if b:
        axs[0].plot(b["sigma_d"], b["c"], "k-", lw=1.2, label="solved steady fronts (branch)")
        axs[1].plot(b["sigma_d"], b["v_behind"], "k-", lw=1.2, label="sigma_ss(v) = sigma_d")
    lim = st.scalars.get("nucleation_limit_sigma_d", math.nan)
    if math.isfinite(lim):
        axs[0].axvline(lim, color="C2", ls="--", lw=1, label=f"nucleation limit {lim:.3g}")
    for m, c in (("continuum", "C0"), ("discrete", "C3")):
        axs[0].plot(t["sigma_d"], t["c_front_" + m], "o" if m == "continuum" else "x", color=c, label=f"nucleated ({m})")
        axs[1].plot(t["sigma_d"], t["v_behind_" + m], "o" if m == "continuum" else "x", color=c, label=m)
    for ax in axs:
        ax.axvline(t["sigma_c_d"][0], color="gray", ls=":", label="sigma_c^d")
        ax.set_xlabel("applied stress sigma_d")
        ax.legend(fontsize=8)
    axs[0].set_ylabel("steady front speed")
    axs[1].set_ylabel("slip rate behind the front")
    fig.suptitle(st.title("front spectrum, homogeneous loading"), fontsize=9)
    save(fig, outdir, f"{st.stem}_spectrum.png", figs)
    rows.append(measure_row("slowest nucleated front (continuum)", f"{st.scalars.get('spectrum_slowest_front', math.nan):.3g}",
                 "", "", f"at sigma_d = {st.scalars.get('spectrum_slowest_front_sigma_d', math.nan):.3g}; "
                         f"nucleation limit sigma_d = {lim:.3g} (a property of the start)"))
    if math.isfinite(st.scalars.get("branch_c_min", math.nan)):
        rows.append(measure_row("minimal steady front speed c_min (solved branch)", f"{st.scalars['branch_c_min']:.4g}", "", "",
                     f"at sigma_d = {st.scalars.get('branch_sigma_d_at_c_min', math.nan):.5g} (end of the branch)"))
    speeds = front_spectrum_speeds(st, outdir)  # the spectrum against c_s, c_R, c_p (docs/fronts.md §12)
    return figs + speeds[0], rows + speeds[1]


SPECTRUM_TWIN = "front_spectrum_strip"  # the antiplane twin of an in-plane front_spectrum study (docs/fronts.md §12)


def spectrum_twin(st):
    """The antiplane twin's Study beside an in-plane front_spectrum study (its directory's sibling), or None."""
    path = os.path.join(os.path.dirname(st.dir), SPECTRUM_TWIN, "study.h5")
    if os.path.abspath(path) == os.path.abspath(st.path) or not os.path.exists(path):
        return None
    try:
        twin = Study(path)
    except STUDY_UNREADABLE:
        return None
    return twin if "front_spectrum_speeds" in twin.tables else None


def spectrum_speeds_panels(axs, t, label, style):
    """One body's runs of front_spectrum_speeds on the two panels: homogeneous against sigma_d, edge against the
    loading rate K v_d of its drive."""
    h = t["homogeneous"] == 1
    e = ~h
    axs[0].plot(t["sigma_d"][h], t["c_peak_over_cs"][h], "^", label=f"{label}: peak", **style)
    axs[0].plot(t["sigma_d"][h], t["c_settled_over_cs"][h], "o-", label=f"{label}: settled (c_front)", **style)
    if e.any():
        rate = t["K"][e] * t["v_d"][e]
        order = np.argsort(rate)
        axs[1].plot(rate[order], t["c_peak_over_cs"][e][order], "^", label=f"{label}: peak", **style)
        axs[1].plot(rate[order], t["c_settled_over_cs"][e][order], "o", label=f"{label}: c_transient", **style)


def front_spectrum_speeds(st, outdir):
    """front_spectrum_inplane.png (issue 39 item 4): every run's peak and settled tip speed over c_s, the in-plane
    strip's and its antiplane twin's, with c_R, c_s, c_p marked; the summary rows of the supershear question."""
    figs, rows = [], []
    t = st.tables.get("front_spectrum_speeds", {})
    c_p = st.scalars.get("spectrum_c_p", math.nan)
    if not t or not math.isfinite(c_p):  # only an in-plane study draws it (with its twin when there)
        return figs, rows
    c_s, c_R = st.scalars["spectrum_c_s"], st.scalars.get("spectrum_c_R", math.nan)
    twin = spectrum_twin(st)
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
    spectrum_speeds_panels(axs, t, "in-plane", dict(color="C0"))
    if twin is not None:
        spectrum_speeds_panels(axs, twin.tables["front_spectrum_speeds"], "antiplane", dict(color="C3", mfc="none"))
    for ax in axs:
        ax.axhspan(c_R / c_s, 1.0, color="0.85", zorder=0)
        ax.axhline(c_R / c_s, color="k", ls="--", lw=0.9, label=f"c_R = {c_R / c_s:.4g} c_s")
        ax.axhline(1.0, color="k", ls="-", lw=0.9, label="c_s")
        ax.axhline(c_p / c_s, color="k", ls=":", lw=0.9, label=f"c_p = {c_p / c_s:.3g} c_s")
        ax.set_ylim(0, 1.08 * c_p / c_s)
    axs[0].set_xlabel("applied stress sigma_d (homogeneous loading, nucleation patch)")
    axs[1].set_xlabel("loading rate K v_d of the drive (edge loading; fig1: 0.75)")
    axs[0].set_ylabel("tip speed / c_s")
    axs[0].legend(fontsize=7)
    axs[1].legend(fontsize=7)
    fig.suptitle(st.title(f"the spectrum of fronts: in-plane strip (c_s = {c_s:.4g}) and its antiplane twin"), fontsize=9)
    save(fig, outdir, "front_spectrum_inplane.png", figs)
    sub, sup = st.scalars.get("spectrum_fastest_subshear", math.nan), st.scalars.get("spectrum_slowest_supershear", math.nan)
    rows.append(measure_row("in-plane fronts above c_s (peak or settled), fastest peak / c_s",
                            f"{int(st.scalars.get('spectrum_supershear_runs', 0))} runs",
                            f"{st.scalars.get('spectrum_max_peak_over_cs', math.nan):.3g}", "",
                            f"settled speeds nearest c_s: {sub:.3g} c_s below, {sup:.3g} c_s above; c_R = "
                            f"{c_R / c_s:.4g} c_s (docs/fronts.md §12)"))
    if twin is not None:
        rows.append(measure_row("antiplane twin: fastest peak / c_s (bounded by 1)",
                                f"{twin.scalars.get('spectrum_max_peak_over_cs', math.nan):.3g}", "", "",
                                f"{int(twin.scalars.get('spectrum_supershear_runs', 0))} runs above c_s"))
    rows += spectrum_answer(st, t, twin, figs[-1])
    return figs, rows


def spectrum_answer(st, t, twin, figure):
    """The answer to the paper's "what about the sub-Rayleigh/supershear fronts?" on its in-plane body (issue 39 item
    4): Yes when some in-plane run's peak or settled speed exceeds c_s and no run of the antiplane twin's does (or the
    twin is not beside it: then on the in-plane runs alone). Every number from the study's scalars and table."""
    sc = st.scalars
    c_s, c_R, c_p = sc["spectrum_c_s"], sc.get("spectrum_c_R", math.nan), sc["spectrum_c_p"]
    n_sup, n = int(sc.get("spectrum_supershear_runs", 0)), len(t["c_s"])
    hom = t["c_settled_over_cs"][(t["homogeneous"] == 1) & np.isfinite(t["c_settled_over_cs"])]
    text = (f"{n_sup} of {n} in-plane runs faster than c_s (settled up to {sc.get('spectrum_max_settled_over_cs', math.nan):.3g} "
            f"c_s, peak {sc.get('spectrum_max_peak_over_cs', math.nan):.3g} c_s; c_R = {c_R / c_s:.4g} c_s, c_p = "
            f"{c_p / c_s:.3g} c_s)")
    if hom.size:
        text += f"; the settled fronts of homogeneous loading {np.min(hom):.3g} .. {np.max(hom):.3g} c_s"
    sub, sup = sc.get("spectrum_fastest_subshear", math.nan), sc.get("spectrum_slowest_supershear", math.nan)
    if math.isfinite(sub) and math.isfinite(sup):
        text += f", the nearest c_s {sub:.3g} below and {sup:.3g} above"
    yes = n_sup > 0
    if twin is not None:
        tw = twin.scalars
        n_tw = int(tw.get("spectrum_supershear_runs", 0))
        text += (f"; the antiplane twin (the same c_s): {n_tw} of {len(twin.tables['front_spectrum_speeds']['c_s'])} runs "
                 f"above c_s, fastest peak {tw.get('spectrum_max_peak_over_cs', math.nan):.3g} c_s")
        yes = yes and n_tw == 0
    return [answer_row("Sub-Rayleigh or supershear (the paper's open question): does this law give supershear fronts "
                       "on the paper's in-plane body, and none on the antiplane strip?",
                       text + " (continuum; docs/fronts.md §12).", yes, text, figure, 6)]


def steady_fronts_study(st, outdir):
    """Runs started from the solved front: speeds against the solved one (kicked or not), and N convergence."""
    figs, rows = [], []
    t = st.tables.get("steady_fronts", {})
    n = st.tables.get("steady_front_N", {})
    if n:
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        loglog_fit(ax, n["N"], n["rms_discrete_vs_continuum"], st, st.best_fit("steady_front_speed_exponent"),
                   "RMS over seeds of c_discrete / c_continuum - 1", "C3")
        ax.loglog(n["N"], np.abs(n["mean_discrete_vs_solved"]), "s", color="C0", label="|seed mean c_discrete / c_solved - 1|")
        ax.set_xlabel("contacts per site N")
        ax.set_ylabel("relative front speed error")
        ax.set_title(st.title("steady front: discrete speed vs N"), fontsize=8)
        ax.legend(fontsize=8)
        save(fig, outdir, f"{st.stem}_speed_vs_N.png", figs)
        rows.append(limit_row("N-rate of a study: discrete -> continuum as N^-1/2", f"{st.name}: discrete front speed vs "
                              f"continuum at N = {n['N'][-1]:.0f}", "continuum", "0",
                              f"{n['rms_discrete_vs_continuum'][-1]:.3g}", st.fit_labels("steady_front_speed_exponent"),
                              "95% CI of the slope contains -1/2",
                              verdict_of(ci_contains(st, st.best_fit("steady_front_speed_exponent"), NRATE)), st.source,
                              st.w_label(), score=ci_score(st, st.best_fit("steady_front_speed_exponent"), NRATE)))
    elif t:
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        for kick, mk in ((0.0, "o"), (-0.5, "v"), (2.0, "^")):
            sel = t["kick_dv"] == kick
            if sel.any():
                ax.plot(t["sigma_d"][sel], 100 * t["rel_continuum"][sel], mk, color="C0", label=f"continuum, kick {kick:g}")
                ax.plot(t["sigma_d"][sel], 100 * t["rel_discrete"][sel], mk, color="C3", mfc="none",
                        label=f"discrete, kick {kick:g}")
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xlabel("applied stress sigma_d")
        ax.set_ylabel("c_front / c_solved - 1  [%]")
        ax.set_title(st.title("fronts started from the solved branch (kicked or not)"), fontsize=8)
        ax.legend(fontsize=8)
        save(fig, outdir, f"{st.stem}_speed_vs_solved.png", figs)
        k = st.scalars.get("kick_max_speed_change", math.nan)
        worst = np.nanmax(np.abs(t["rel_continuum"])) if len(t["rel_continuum"]) else math.nan
        rows.append(measure_row(f"{st.name}: front started from the solved one, max abs(c/c_solved - 1)", f"{worst:.2g}",
                     f"{np.nanmax(np.abs(t['rel_discrete'])):.2g}", "",
                     f"kicked fronts return to the branch: max speed change {k:.2g}" if math.isfinite(k) else ""))
    return figs, rows


def fronts_file(path, root, figdir, studies):
    """fronts.h5 (slipfront fronts): the branch with the time-dependent points of the studies, profiles, and
    the c_min collapse. A failed or interrupted file (no branch point, c_min NaN) is reported with its reason."""
    figs, rows, lines = [], [], []
    outdir, stem = figdir, figure_key(root, path)
    with h5py.File(path, "r") as f:
        b = f["branch"]
        ba = attrs(b)
        meta = f["meta"].attrs
        scene = plot.as_str(meta.get("scene", "fronts"))
        status, message = plot.as_str(meta.get("status", "unknown")), plot.as_str(meta.get("message", ""))
        c_min, sd_min = ba.get("c_min", math.nan), ba.get("sigma_d_at_c_min", math.nan)
        fig, axs = plt.subplots(1, 2, figsize=(12, 4.5))
        ax = axs[0]
        if "sigma_d" in b and "c" in b:
            ax.plot(b["sigma_d"][()], b["c"][()], "k-", lw=1.3, label="solved steady fronts")
        else:
            plot.no_data(ax, f"no steady front ({status})")
        if math.isfinite(c_min):
            err = ba.get("c_min_error", math.nan)
            ax.plot([sd_min], [c_min], "k*", ms=12,
                    label=f"c_min = {c_min:.4g}" + (f" ± {err:.2g}" if math.isfinite(err) else " (no error estimate)"))
        if math.isfinite(ba.get("sigma_c_d", math.nan)):
            ax.axvline(ba["sigma_c_d"], color="gray", ls=":", label="sigma_c^d")
        for st in studies:
            if st.kind == "front_spectrum" and "front_spectrum" in st.tables:
                t = st.tables["front_spectrum"]
                ax.plot(t["sigma_d"], t["c_front_continuum"], "o", color="C0", mfc="none", label="nucleated, continuum")
                ax.plot(t["sigma_d"], t["c_front_discrete"], "x", color="C3", label="nucleated, discrete")
                lim = st.scalars.get("nucleation_limit_sigma_d", math.nan)
                if math.isfinite(lim):
                    ax.axvline(lim, color="C2", ls="--", lw=1, label=f"nucleation limit {lim:.3g}")
            if st.kind == "steady_fronts" and "steady_fronts" in st.tables and "steady_front_N" not in st.tables:
                t = st.tables["steady_fronts"]
                sel = t["kick_dv"] == 0
                ax.plot(t["sigma_d"][sel], t["c_continuum"][sel], "s", color="C0", label="started from solved, continuum")
                ax.plot(t["sigma_d"][sel], t["c_discrete"][sel], "+", color="C3", ms=10, label="started from solved, discrete")
        ax.set_xlabel("applied stress sigma_d")
        ax.set_ylabel("steady front speed c")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
        ax = axs[1]
        for k in sorted(f["profiles"] if "profiles" in f else [], key=int):
            g = f["profiles"][k]
            a = attrs(g)
            ax.plot(g["xi"][()], g["v"][()] / a["v_behind"], lw=1,
                    label=f"sigma_d {a['sigma_d']:.3g}, c {a['c']:.3g}" + (" (limit)" if a.get("limiting") else ""))
        ax.set_xlim(-200, 20)
        ax.set_xlabel("xi = x - c t (tip at 0)")
        ax.set_ylabel("v / v_behind")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
        fig.suptitle(f"{scene}: steady fronts, the branch and its profiles (docs/fronts.md)   [{status}]", fontsize=9)
        save(fig, outdir, f"{stem}_{scene}_fronts_branch.png", figs)
        c_err = ba.get("c_min_error", math.nan)  # the estimate beside the number (docs/fronts.md §10.20)
        c_txt = f"{c_min:.5g} ± {c_err:.2g}" if math.isfinite(c_err) else f"{c_min:.5g} (no error estimate)"
        acc = plot.as_str(ba.get("accuracy", ""))
        rows.append(measure_row(f"{scene}: minimal steady front speed c_min (solved)", c_txt, "", "",
                     f"at sigma_d = {sd_min:.5g}; branch end: {ba.get('end', '')}; status {status}"
                     + (f"; accuracy {acc}" if acc else "")))
        if "scaling" in f and "points" in f["scaling"] and "c_min" in f["scaling"]["points"]:
            sc = f["scaling"]
            names = plot.as_str(sc.attrs["parameters"]).split(",")
            pts = {k: sc["points"][k][()] for k in sc["points"]}
            fits = {k: sc["fits"][k][()] for k in sc["fits"]}
            fig, ax = plt.subplots(figsize=(6.5, 4.5))
            for i, name in enumerate(names):
                sel = pts["parameter_index"] == i
                ax.plot(pts["scale"][sel], pts["c_min"][sel], "osD^v"[i % 5], color=f"C{i}", label=f"vary {name}")
            allfit = fits["parameter_index"] == -1
            a, spread = float(fits["prefactor"][allfit][0]), float(fits["spread"][allfit][0])
            fitted = int(fits["points"][allfit][0])
            tried = int(fits["tried"][allfit][0]) if "tried" in fits else len(pts["c_min"])
            if math.isfinite(a) and len(pts["scale"]):
                xs = np.linspace(0, np.nanmax(pts["scale"]) * 1.05, 10)
                ax.plot(xs, a * xs, "k--", lw=1, label=f"c_min = {a:.3f} sqrt(mu alpha/(eta kappa)), "
                                                       f"max dev {100 * spread:.1f}% over {fitted} of {tried} points")
            ax.set_xlabel("sqrt(mu alpha / (eta kappa))")
            ax.set_ylabel("minimal steady front speed c_min")
            ax.set_title(f"{scene}: c_min collapse (the paper's Fig. 2 right, for the minimal speed)", fontsize=8)
            ax.legend(fontsize=8)
            save(fig, outdir, f"{stem}_{scene}_cmin_collapse.png", figs)
            refused = [ln for ln in plot.as_str(sc["fits"].attrs.get("refused", "")).split("\n") if ln.startswith("all: ")]
            why = refused[0][len("all: "):] if refused and refused[0] != "all: fitted" else ""
            rows.append(measure_row(f"{scene}: c_min / sqrt(mu alpha/(eta kappa)) ({fitted} of {tried} branches with a c_min)",
                         f"{a:.3g}", "", "", f"no fit: {why}" if why else
                         f"largest deviation {100 * spread:.1f}% over the {fitted} fitted points"))
        end = f"the branch ends at sigma_d = {sd_min:.6g} ({plot.as_str(ba.get('reason', ''))})" if math.isfinite(c_min) \
            else f"no c_min: {message or plot.as_str(ba.get('reason', ''))}"
        lines += [f"## Steady fronts `{scene}`", "", f"File: `{os.path.relpath(path, root)}`, status {status}: {end}.", ""]
    for w in figs:
        lines += [f"![{os.path.basename(w)}]({os.path.relpath(w, root)})", ""]
    return lines, rows


def validity_friction_study(st, outdir):
    """The validity map on the steady law: bias vs N per alpha, the map with its 1% / 5% contours, the collapse."""
    figs, rows = [], []
    t = st.tables.get("validity_friction", {})
    x = st.tables.get("validity_crossover", {})
    if not t:
        return figs, rows
    # the reference kappa, eta (the analysis picks the pair most points ran at); other pairs: the kappa/eta figure
    kref = st.scalars.get("validity_friction_kappa_ref", t["kappa"][0] if "kappa" in t else math.nan)
    eref = st.scalars.get("validity_friction_eta_ref", t["eta"][0] if "eta" in t else math.nan)
    tref = (t["kappa"] == kref) & (t["eta"] == eref) if "kappa" in t else np.ones(len(t["N"]), bool)
    widths = sorted(set(t["width"]))
    fig, axs = plt.subplots(1, len(widths), figsize=(5.2 * len(widths), 4.3), squeeze=False)
    for ax, w in zip(axs[0], widths):
        for i, a in enumerate(sorted(set(t["alpha"]))):
            m = (t["alpha"] == a) & (t["width"] == w) & tref
            ax.loglog(t["N"][m], np.maximum(t["bias"][m], 1e-5), "o-", color=f"C{i}", ms=4, label=f"alpha - 1 = {a - 1:.3g}")
        for lev in (0.01, 0.05):
            ax.axhline(lev, color="gray", ls=":", lw=0.8)
        ax.set_xlabel("contacts per site N")
        ax.set_ylabel("bias of the steady friction (RMS over v)")
        ax.set_title(f"w = {w:g}", fontsize=9)
        ax.legend(fontsize=8)
    fig.suptitle(st.title(f"validity map, steady law: systematic error vs N (kappa = {kref:g}, eta = {eref:g})"), fontsize=9)
    save(fig, outdir, f"{st.stem}_bias_vs_N.png", figs)
    # the map (w = 0): where the continuum holds to 1% and 5%
    m0 = (t["width"] == 0) & tref
    if m0.any():
        Ns, As = sorted(set(t["N"][m0])), sorted(set(t["alpha_minus_1"][m0]))
        grid = np.full((len(As), len(Ns)), np.nan)
        for k in np.where(m0)[0]:
            grid[As.index(t["alpha_minus_1"][k]), Ns.index(t["N"][k])] = max(t["bias"][k], 1e-5)
        fig, ax = plt.subplots(figsize=(6.8, 5.2), constrained_layout=True)
        X, Y = np.meshgrid(np.log10(Ns), np.log10(As))
        pc = ax.pcolormesh(X, Y, np.log10(grid), shading="nearest", cmap="viridis")
        fig.colorbar(pc, ax=ax, label="log10 bias")
        cs = ax.contour(X, Y, np.log10(grid), levels=[-2, np.log10(0.05)], colors=["w", "r"], linewidths=1.5)
        ax.clabel(cs, fmt={-2: "1%", np.log10(0.05): "5%"}, fontsize=8)
        if x:
            mx = (x["width"] == 0) & np.isfinite(x["N_star_1"])
            if "kappa" in x:
                mx &= (x["kappa"] == kref) & (x["eta"] == eref)
            ax.plot(np.log10(x["N_star_1"][mx]), np.log10(x["alpha_minus_1"][mx]), "w*", ms=11, mec="k", mew=0.8,
                    label="N* (1%)")
            p = st.scalars.get("validity_friction_Nstar1_exponent", math.nan)
            c = st.scalars.get("validity_friction_Nstar1_exponent_prefactor", math.nan)
            if math.isfinite(p):
                am = np.array(As)
                ax.plot(np.log10(c * am ** p), np.log10(am), "w--", lw=1, label=f"N* = {c:.3g} (alpha-1)^{p:.2f}")
            ax.legend(fontsize=8, loc="lower left", facecolor="0.6", framealpha=0.9)
        ax.set_xlabel("log10 N")
        ax.set_ylabel("log10 (alpha - 1)")
        ax.set_title(textwrap.fill(st.title("where the continuum law holds (w = 0): bias of the steady friction"), 70),
                     fontsize=9)
        save(fig, outdir, f"{st.stem}_map.png", figs)
        # the collapse: bias against N (alpha - 1)^{-p}, fitted p and the naive p = -2
        p = st.scalars.get("validity_friction_Nstar1_exponent", -1.5)
        fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
        for ax, q, lab in ((axs[0], -p, f"N (alpha - 1)^{-p:.2f} (fitted)"), (axs[1], 2.0, "N (alpha - 1)^2 (naive)")):
            for i, a in enumerate(sorted(set(t["alpha"][m0]))):
                m = m0 & (t["alpha"] == a)
                ax.loglog(t["N"][m] * (a - 1) ** q, np.maximum(t["bias"][m], 1e-5), "o-", color=f"C{i}", ms=4,
                          label=f"alpha - 1 = {a - 1:.3g}")
            ax.set_xlabel(lab)
            ax.set_ylabel("bias")
            ax.legend(fontsize=8)
        fig.suptitle(st.title("collapse of the steady-law bias"), fontsize=9)
        save(fig, outdir, f"{st.stem}_collapse.png", figs)
    # kappa and eta: N* of every w = 0 point against alpha - 1, raw and scaled by the free fit's kappa^q eta^r
    pa, pk, pe = (st.scalars.get(f"validity_friction_free_fit_{n}_exponent", math.nan) for n in ("alpha_minus_1", "kappa", "eta"))
    if x and "kappa" in x and math.isfinite(pk):
        w0 = (x["width"] == 0) & np.isfinite(x["N_star_1"])
        pairs = sorted(set(zip(x["kappa"][w0], x["eta"][w0])))
        fig, axs = plt.subplots(1, 3, figsize=(15, 4.3))
        for j, (kk, ee) in enumerate(pairs):
            m = w0 & (x["kappa"] == kk) & (x["eta"] == ee)
            lab = f"kappa = {kk:g}, eta = {ee:g}"
            axs[0].loglog(x["alpha_minus_1"][m], x["N_star_1"][m], "o", color=f"C{j}", label=lab)
            axs[1].loglog(x["alpha_minus_1"][m], x["N_star_1"][m] * ((ee / eref) / (kk / kref)) ** 0.5, "o", color=f"C{j}", label=lab)
            axs[2].loglog(x["alpha_minus_1"][m], x["N_star_1"][m] / ((kk / kref) ** pk * (ee / eref) ** pe), "o", color=f"C{j}",
                          label=lab)
        am = np.geomspace(min(x["alpha_minus_1"][w0]), max(x["alpha_minus_1"][w0]), 50)
        pc = st.scalars.get("validity_friction_collapse_exponent", math.nan)
        cc = st.scalars.get("validity_friction_collapse_exponent_prefactor", math.nan)
        if math.isfinite(pc):
            axs[1].loglog(am, cc * am ** pc, "k--", lw=1, label=f"fit: (alpha - 1)^{pc:.2f}")
        # the free fit's line at the reference kappa, eta
        sel = w0
        pref = np.exp(np.mean(np.log(x["N_star_1"][sel]) - pa * np.log(x["alpha_minus_1"][sel])
                              - pk * np.log(x["kappa"][sel] / kref) - pe * np.log(x["eta"][sel] / eref)))
        axs[2].loglog(am, pref * am ** pa, "k--", lw=1, label=f"free fit: (alpha - 1)^{pa:.2f}")
        axs[0].set_ylabel("N* (bias < 1%)")
        axs[0].set_title("measured", fontsize=8)
        axs[1].set_ylabel("scaled N*")
        axs[1].set_title(f"N* ((eta/{eref:g}) / (kappa/{kref:g}))^(1/2): the argument's scaling", fontsize=8)
        axs[2].set_ylabel("scaled N*")
        axs[2].set_title(f"N* / ((kappa/{kref:g})^{pk:.2f} (eta/{eref:g})^{pe:.2f}): the free fit", fontsize=8)
        for ax in axs:
            ax.set_xlabel("alpha - 1")
            ax.legend(fontsize=8)
        fig.suptitle(st.title("N* against kappa and eta: the (kappa/eta)^(1/2) of the argument and the free fit"), fontsize=9)
        save(fig, outdir, f"{st.stem}_kappa_eta.png", figs)
        rows.append(measure_row(f"{st.name}: N* ~ (alpha - 1)^p kappa^q eta^r, free fit (w = 0)", "", f"{pa:.2f}, {pk:.2f}, {pe:.2f}", "",
                     "argument: -3/2, +1/2, -1/2; " + ", ".join(st.fit_label(f"validity_friction_free_fit_{n}_exponent")
                                                              for n in ("alpha_minus_1", "kappa", "eta"))))
    rows.append(measure_row(f"{st.name}: N* (steady-law bias < 1%, w = 0) ~ (alpha - 1)^p", "", "", "",
                 st.fit_label("validity_friction_Nstar1_exponent") + "; theory -3/2, naive -2"))
    if x:
        for k in range(len(x["alpha"])):
            if x["width"][k] == 0 and math.isfinite(x["N_star_1"][k]) and ("kappa" not in x or (x["kappa"][k] == kref and x["eta"][k] == eref)):
                rows.append(measure_row(f"{st.name}: N* (1%) at alpha - 1 = {x['alpha_minus_1'][k]:.3g}", "", f"{x['N_star_1'][k]:.3g}", "",
                             f"between N = {x['N_star_1_low'][k]:.3g} and {x['N_star_1_high'][k]:.3g}"))
    return figs, rows


def validity_fig1_study(st, outdir):
    """The validity map on fig1: the fraction of continuum-like runs vs N per alpha, and its collapse."""
    figs, rows = [], []
    t = st.tables.get("validity_fig1", {})
    if not t:
        return figs, rows
    dt_ref = max(t["dt"])
    ref = t["dt"] == dt_ref
    fig, axs = plt.subplots(1, 2, figsize=(11, 4.2))
    for i, a in enumerate(sorted(set(t["alpha"][ref]))):
        m = ref & (t["alpha"] == a)
        yerr = [t["fraction"][m] - t["fraction_low"][m], t["fraction_high"][m] - t["fraction"][m]]
        axs[0].errorbar(t["N"][m], t["fraction"][m], yerr=yerr, marker="o", capsize=3, color=f"C{i}", label=f"alpha - 1 = {a - 1:.3g}")
        axs[1].plot(t["N"][m] * (a - 1) ** 2, t["fraction"][m], "o-", color=f"C{i}", label=f"alpha - 1 = {a - 1:.3g}")
    fine = ~ref
    if fine.any():
        axs[0].errorbar(t["N"][fine], t["fraction"][fine], yerr=[t["fraction"][fine] - t["fraction_low"][fine],
                        t["fraction_high"][fine] - t["fraction"][fine]], marker="s", ls="none", color="k", capsize=3,
                        label=f"dt = {t['dt'][fine][0]:g} (step check)")
    for ax in axs:
        ax.set_xscale("log")
        ax.set_ylabel("fraction of continuum-like fig1 runs")
        ax.legend(fontsize=8)
    axs[0].set_xlabel("contacts per site N")
    axs[1].set_xlabel("N (alpha - 1)^2")
    fig.suptitle(st.title(f"validity map, fig1 (implicit dt = {dt_ref:g}, Wilson 95% intervals)"), fontsize=9)
    save(fig, outdir, f"{st.stem}_fraction.png", figs)
    # the modes, run by run: c_ratio against the t^ shift, the classification box, per alpha, coloured by N
    r = st.tables.get("validity_fig1_runs", {})
    if r:
        rr = r["dt"] == dt_ref
        alphas = sorted(set(r["alpha"][rr]))
        fig, axs = plt.subplots(1, len(alphas), figsize=(4.2 * len(alphas), 4.0), squeeze=False, sharey=True)
        for ax, a in zip(axs[0], alphas):
            for i, n in enumerate(sorted(set(r["N"][rr]))):
                m = rr & (r["alpha"] == a) & (r["N"] == n)
                ax.plot(r["t_hat_shift"][m], r["c_ratio"][m], ".", color=f"C{i}", ms=4, alpha=0.7, label=f"N = {n:g}")
            ax.add_patch(plt.Rectangle((-0.1, 0), 0.2, 1.2, fill=False, ls="--", color="k", lw=1))
            ax.set_xlabel("t^ shift: t^(discrete)/t^(continuum) - 1")
            ax.set_title(f"alpha - 1 = {a - 1:.3g}", fontsize=8)
        axs[0][0].set_ylabel("c_transient(discrete) / c_transient(continuum)")
        axs[0][0].legend(fontsize=8)
        fig.suptitle(st.title("fig1 runs by mode (dashed box: continuum-like)"), fontsize=9)
        save(fig, outdir, f"{st.stem}_modes.png", figs)
    if math.isfinite(st.scalars.get("validity_fig1_Nstar50_exponent", math.nan)):
        rows.append(measure_row(f"{st.name}: N* (half of fig1 runs continuum-like) ~ (alpha - 1)^p", "", "", "",
                     st.fit_label("validity_fig1_Nstar50_exponent") + "; theory -2"))
    stp = st.tables.get("validity_fig1_step", {})
    for k in range(len(stp.get("alpha", []))):
        fine = "explicit" if stp["dt_fine"][k] == 0 else f"dt {stp['dt_fine'][k]:g}"
        pv = float(stp["pvalue"][k])
        rows.append(limit_row("the continuum-like fraction does not depend on the time step",
                              f"{st.name}: continuum-like fraction at alpha = {stp['alpha'][k]:g}, N = {stp['N'][k]:g}",
                              f"discrete at {fine}", f"{stp['fraction_fine'][k]:.3f}",
                              f"{stp['fraction'][k]:.3f} (dt {stp['dt'][k]:g})",
                              f"difference {stp['difference'][k]:+.3f}, p = {pv:.2f} (two-proportion z test, "
                              f"{stp['runs'][k]:g} seeds)", "p >= 0.05",
                              verdict_of(pv >= 0.05 if math.isfinite(pv) else None), st.source, st.w_label()))
    return figs, rows


STRIP_EVENTS = (("t_star", "first yield t*"), ("t_hat", "instability t^"), ("c_slow", "slow-front speed c_slow"),
                ("c_transient", "transient speed c_transient"), ("x_arrest", "arrest position x_arrest"))


def strip_height_study(st, outdir):
    """fig1 on the strip against H/l_e: the five events of both models, the 1D chain as the H -> 0 line (dashed),
    and their relative differences to it (log-log, with the 0.5 % tolerance and an H^2 guide). A study with runs on
    the in-plane strip (inplane_height) has its own table: its figure shows the three bodies, its rows its own check."""
    figs, rows = [], []
    inplane = st.tables.get("inplane_height", {})
    anti = st.tables.get("strip_height", {})
    anti = anti if anti and len(anti.get("H", [])) else {}
    if inplane and len(inplane.get("H", [])):  # the in-plane strip's runs (the study inplane_height): three bodies
        events_vs_height(st, outdir, figs, [("in-plane", inplane, "-")] + ([("antiplane", anti, "--")] if anti else []),
                         "§10.2", "fig1 on three bodies vs the height: the in-plane strip (solid), the antiplane strip "
                         "(dashed), the 1D chain (dotted: the H -> 0 line)", "_events_vs_H_bodies.png")
        rows += height_rows(st, inplane, "inplane_height", "in-plane strip")
    if not anti:
        return figs, rows
    le = float(np.median(anti["H"][anti["H"] > 0] / anti["H_over_le"][anti["H"] > 0])) if (anti["H"] > 0).any() else math.nan
    events_vs_height(st, outdir, figs, [("strip", anti, "-")], "§9.2",
                     f"fig1 on the strip vs its height (l_e = sqrt(mu/alpha) = {le:.4g}; dashed: the 1D chain, the H -> 0 "
                     "line)", "_events_vs_H.png")
    rows += height_rows(st, anti, "strip_height", "strip")
    return figs, rows


def events_vs_height(st, outdir, figs, bodies, section, title, suffix):
    """The five events of both models (open markers: discrete) against H/l_e for each (name, table, line style) of
    `bodies`, the 1D chain's values as horizontal lines (dashed; dotted beside several bodies), and the first body's
    relative differences to the chain in log-log with the 0.5 % line and an (H/l_e)^2/3 guide (docs/model.md
    `section`)."""
    t0 = bodies[0][1]
    chain = np.where(t0["H"] == 0)[0]
    several = len(bodies) > 1
    models = (("continuum", "C0", "o"), ("discrete", "C3", "s"))
    fig, axs = plt.subplots(2, 3, figsize=(15, 8.5), constrained_layout=True)
    for ax, (o, what) in zip(axs.flat, STRIP_EVENTS):
        for m, color, marker in models:
            for name, t, ls in bodies:
                y = t.get(f"{o}_{m}")
                if y is None:
                    continue
                ok = (t["H"] > 0) & np.isfinite(y)
                ax.plot(t["H_over_le"][ok], y[ok], marker=marker, color=color, ls=ls, lw=0.8,
                        mfc="none" if m == "discrete" else color, label=f"{name} ({m})" if several else m)
            y = t0.get(f"{o}_{m}")
            if y is not None and len(chain) and math.isfinite(y[chain[0]]):
                ax.axhline(y[chain[0]], color=color, ls=":" if several else "--", lw=1,
                           label=f"1D chain ({m}): {y[chain[0]]:.4g}")
        ax.axvline(1.0, color="0.6", ls=":", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlabel("H / l_e")
        ax.set_title(what, fontsize=9)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7 if several else 8)
    ax = axs.flat[5]
    x, strip = t0["H_over_le"], t0["H"] > 0
    drawn = False
    for i, (o, what) in enumerate(STRIP_EVENTS):
        for m, _, marker in models:
            r = t0.get(f"{o}_{m}_rel_1d")
            if r is None:
                continue
            ok = strip & np.isfinite(r) & (np.abs(r) > 0)
            if ok.any():
                ax.loglog(x[ok], np.abs(r[ok]), marker=marker, color=f"C{i}", ls="-" if m == "continuum" else ":",
                          lw=0.8, ms=4, mfc="none" if m == "discrete" else f"C{i}",
                          label=f"{o} ({m})" if m == "continuum" else None)
                drawn = True
    if drawn:
        xs = np.geomspace(max(np.nanmin(x[strip]), 1e-3), 1.0, 20)
        ax.loglog(xs, xs ** 2 / 3, "k-", lw=0.8, alpha=0.5, label=f"(H/l_e)^2 / 3 (model.md {section})")
        ax.axhline(0.005, color="k", ls="--", lw=0.8, label="0.5 %")
        ax.set_xlabel("H / l_e")
        ax.set_ylabel("|event / 1D event - 1|  (open, dotted: discrete)")
        ax.set_title(f"{bodies[0][0]}: relative difference to the 1D chain" if several else
                     "relative difference to the 1D chain", fontsize=9)
        ax.legend(fontsize=8, ncol=2)
    else:
        plot.no_data(ax, "no 1D chain run: no relative differences")
    fig.suptitle(st.title(title), fontsize=9)
    save(fig, outdir, f"{st.stem}{suffix}", figs)


def height_rows(st, t, prefix, body):
    """The summary rows of one strip body's table of a strip_height study (`prefix`: strip_height for the antiplane
    strip, inplane_height for the in-plane strip): the H -> 0 limit at the smallest height, the effect of the largest,
    the dy checks."""
    rows = []
    H, x = t["H"], t["H_over_le"]
    strip = H > 0
    chain = np.where(H == 0)[0]
    thin = st.scalars.get(f"{prefix}_thin_H", math.nan)
    if len(chain) and math.isfinite(thin):
        k = int(np.where(H == thin)[0][0])
        big = int(np.argmax(np.where(strip, H, -1)))
        for o, what in STRIP_EVENTS:
            c, d = t.get(f"{o}_continuum"), t.get(f"{o}_discrete")
            if c is None or d is None:
                continue
            rc, rd = t[f"{o}_continuum_rel_1d"], t[f"{o}_discrete_rel_1d"]
            order = st.fit_label(f"{prefix}_order_{o}_continuum").replace("slope", "order in H")
            worst = max(abs(rc[k]), abs(rd[k]))
            rows.append(limit_row(f"{body} -> 1D chain as H -> 0 (both models)",
                                  f"{st.name}: {o}, 1D chain -> H = {thin:g} (H/l_e = {x[k]:.3g})", "1D chain",
                                  f"{c[chain[0]]:.4g} / {d[chain[0]]:.4g}", f"{c[k]:.4g} / {d[k]:.4g}",
                                  f"H = {thin:g} vs 1D (continuum / discrete): {rc[k]:+.3%} / {rd[k]:+.3%}; {order}",
                                  "abs <= 0.5%", verdict_of(worst <= STRIP_THIN_TOL if math.isfinite(worst) else None),
                                  st.source, st.w_label()))
            rows.append(effect_row(f"{body} height H", f"{st.name}: {o}, 1D chain -> H = {H[big]:g} (H/l_e = {x[big]:.3g}) "
                                   "(continuum / discrete)", f"1D chain {c[chain[0]]:.4g} / {d[chain[0]]:.4g}",
                                   f"H = {H[big]:g}: {c[big]:.4g} / {d[big]:.4g}",
                                   f"{rc[big]:+.2%} / {rd[big]:+.2%}", order, st.source))
    dy = st.tables.get(f"{prefix}_dy", {})
    for k in range(len(dy.get("H", []))):
        rows.append(measure_row(f"{st.name}: events at H = {dy['H'][k]:g}, dy = {dy['dy'][k]:g} against dy = {dy['dy_reference'][k]:g}",
                     "", "", f"largest change {dy['max_rel_ref'][k]:.3%}", "both models, t*, t^, c_slow, c_transient, x_arrest"))
    return rows


DISORDER_LAWS = ("delta", "uniform", "gaussian", "weibull")  # the codes of studies/disorder_limit.cpp's tables
DISORDER_RENEWALS = ("fresh", "quenched")
DISORDER_LEVEL = 0.01  # where mean_field departs from the continuum: the validity map's 1 % (docs/model.md §8)
DISORDER_W0_MAX = 0.05  # a w -> 0 limit row needs a w-rate or a width at most this (fig1's and the law's alpha - 1)


def disorder_label(t, k):
    law, ren = int(t["threshold"][k]), int(t["renewal"][k])
    return (f"{DISORDER_LAWS[law] if 0 <= law < len(DISORDER_LAWS) else 'other'}_"
            f"{DISORDER_RENEWALS[ren] if 0 <= ren < len(DISORDER_RENEWALS) else 'other'}")


def disorder_observables(t, suffix):
    return [c[:-len(suffix)] for c in sorted(t) if c.endswith(suffix)]


def disorder_limit_study(st, outdir):
    """Threshold disorder (kind disorder_limit): the discrete model's relative difference to mean_field against N per
    (law, renewal, w): its spread over seeds (the random part) with its N-fit, the RMS (with the bias) and an N^-1/2
    guide; |mean_field - continuum|/continuum against w per (law, renewal), with the 1 % line and its crossing.
    Rows: the N-rates of the random part are limits (95 % CI contains -1/2); the w -> 0 rate a limit (the difference
    at the smallest w within 1 %) for each (law, renewal) with a w-rate or a width <= 0.05; the differences at each w
    effects of w."""
    figs, rows = [], []
    tn, tw = st.tables.get("disorder_limit_N", {}), st.tables.get("disorder_limit_w", {})
    fig1 = "t_hat_rel_diff" in tw or "t_hat_rms_rel" in tn
    what = "fig1 events" if fig1 else "steady friction law"
    if tn and len(tn.get("N", [])):
        obs = disorder_observables(tn, "_rms_rel")
        groups = {}
        for k in range(len(tn["N"])):
            groups.setdefault((disorder_label(tn, k), float(tn["w"][k])), []).append(k)
        # an observable equal to mean_field at every N (t* at w = 0.2: the first yield is deterministic) has no panel;
        # the title says so
        drawn = [o for o in obs if any(np.any(np.isfinite(a) & (a > 0)) for a in (tn[f"{o}_sd_rel"], tn[f"{o}_rms_rel"]))]
        same = [o for o in obs if o not in drawn]
        # at most two panels a row: four in a row made a figure 18 inches wide, its 8-pt legends unreadable at the
        # width a report is read at
        cols = min(2, max(1, len(drawn)))
        nrows = -(-max(1, len(drawn)) // cols)
        fig, axs = plt.subplots(nrows, cols, figsize=(5.4 * cols, 4.3 * nrows), constrained_layout=True, squeeze=False)
        if not drawn:
            plot.no_data(axs[0, 0], "identical to mean_field at every N")
        for ax in axs.flat[max(1, len(drawn)):]:
            ax.axis("off")
        for ax, o in zip(axs.flat, drawn):
            for i, ((lab, w), ks) in enumerate(sorted(groups.items())):
                fit = st.best_fit(f"disorder_N_{o}_{lab}_w{w:g}_sd_exponent")
                N, y = tn["N"][ks], tn[f"{o}_sd_rel"][ks]
                loglog_fit(ax, N, y, st, fit, f"{lab}, w = {w:g}: spread over seeds", f"C{i}")
                rms = tn[f"{o}_rms_rel"][ks]
                okr = np.isfinite(rms) & (rms > 0)
                ax.loglog(N[okr], rms[okr], "x", color=f"C{i}", label=f"{lab}, w = {w:g}: RMS (with the bias)")
                ok = np.isfinite(y) & (y > 0)
                if ok.any():
                    j = int(np.argmin(np.where(ok, N, np.inf)))
                    ax.loglog(N, y[j] * (N / N[j]) ** -0.5, ":", color=f"C{i}", lw=0.8)
            ax.set_xlabel("contacts per site N")
            ax.set_ylabel("discrete / mean_field - 1 over seeds")
            ax.set_title(f"{o} (dotted: N^-1/2)", fontsize=9)
            ax.legend(fontsize=8, loc="best")
        note = f"\n{', '.join(same)}: identical to mean_field at every N (no panel)" if same else ""
        fig.suptitle(st.title(f"{what}: discrete -> mean_field as N grows, at each w") + note, fontsize=9)
        save(fig, outdir, f"{st.stem}_distance_vs_N.png", figs)
        for (lab, w), ks in sorted(groups.items()):
            big = ks[int(np.argmax(tn["N"][ks]))]
            for o in obs:
                name = f"disorder_N_{o}_{lab}_w{w:g}_sd_exponent"
                if name not in st.scalars:
                    continue
                fit = st.best_fit(name)
                total = st.fit_label(st.best_fit(f"disorder_N_{o}_{lab}_w{w:g}_exponent"))
                rows.append(limit_row("N-rate of a study: discrete -> mean_field as N^-1/2 at w > 0",
                                      f"{st.name}: {o} ({lab}), spread over seeds of the relative difference at "
                                      f"N = {tn['N'][big]:.0f}", "mean_field",
                                      f"{tn[f'{o}_mean_field'][big]:.4g}" if f"{o}_mean_field" in tn else "",
                                      f"{tn[f'{o}_sd_rel'][big]:.3g}",
                                      f"random part {st.fit_labels(name)}; RMS with the bias {total}",
                                      "95% CI of the slope contains -1/2", verdict_of(ci_contains(st, fit, NRATE)),
                                      st.source, f"{w:g}", score=ci_score(st, fit, NRATE)))
    if tw and len(tw.get("w", [])):
        obs = disorder_observables(tw, "_rel_diff")
        groups = {}
        for k in range(len(tw["w"])):
            groups.setdefault(disorder_label(tw, k), []).append(k)
        fig, axs = plt.subplots(1, len(obs), figsize=(4.2 * len(obs), 4), constrained_layout=True, squeeze=False)
        for ax, o in zip(axs[0], obs):
            for i, (lab, ks) in enumerate(sorted(groups.items())):
                ks = sorted(ks, key=lambda k: tw["w"][k])
                w, y = tw["w"][ks], tw[f"{o}_rel_diff"][ks]
                ok = np.isfinite(y) & (y > 0)
                ax.loglog(w[ok], y[ok], "o-", color=f"C{i}", lw=0.8, ms=4,
                          label=f"{lab}: {st.fit_label(f'disorder_w_{o}_{lab}_exponent').replace('slope', 'rate')}")
                x = st.scalars.get(f"disorder_w1pct_{o}_{lab}", math.nan)
                if math.isfinite(x):
                    ax.axvline(x, color=f"C{i}", ls=":", lw=0.8)
            ax.axhline(DISORDER_LEVEL, color="k", ls="--", lw=0.8, label="1 %")
            ax.set_xlabel("threshold width w")
            ax.set_ylabel("|mean_field / continuum - 1|")
            ax.set_title(f"{o} (dotted: the 1 % crossing)", fontsize=9)
            ax.legend(fontsize=8)
        fig.suptitle(st.title(f"{what}: mean_field (N -> inf) against the continuum as w -> 0"), fontsize=9)
        save(fig, outdir, f"{st.stem}_distance_vs_w.png", figs)
        for lab, ks in sorted(groups.items()):
            ks = sorted(ks, key=lambda k: tw["w"][k])
            lo, hi = ks[0], ks[-1]
            for o in obs:
                rel = tw[f"{o}_rel_diff"]
                cont = tw.get(f"{o}_continuum", np.full(len(rel), math.nan))
                mf = tw.get(f"{o}_mean_field", np.full(len(rel), math.nan))
                x = st.scalars.get(f"disorder_w1pct_{o}_{lab}", math.nan)
                status = st.scalars.get(f"disorder_w1pct_{o}_{lab}_status", math.nan)
                cross = (f"1 % at w = {x:.3g}" if math.isfinite(x) else
                         f"above 1 % already at w = {tw['w'][lo]:g}" if status == -1 else
                         f"within 1 % up to w = {tw['w'][hi]:g}")
                rate = st.fit_label(f"disorder_w_{o}_{lab}_exponent").replace("slope", "rate")
                rows.append(effect_row("threshold disorder w (at N -> inf: mean_field)",
                                       f"{st.name}: {o} ({lab}), continuum -> mean_field at w = {tw['w'][lo]:g} .. "
                                       f"{tw['w'][hi]:g}", f"{cont[lo]:.4g}" if math.isfinite(cont[lo]) else "continuum",
                                       f"{mf[hi]:.4g}" if math.isfinite(mf[hi]) else f"w = {tw['w'][hi]:g}",
                                       ", ".join(f"{tw['w'][k]:g}: {rel[k]:.2%}" for k in ks), f"{cross}; {rate}",
                                       st.source))
                if f"disorder_w_{o}_{lab}_exponent" not in st.scalars and tw["w"][lo] > DISORDER_W0_MAX:
                    continue  # no width near 0 (e.g. a renewal run at large w only): no w -> 0 limit to test
                rows.append(limit_row("mean_field -> continuum as w -> 0", f"{st.name}: {o} ({lab}), |mean_field/"
                                      f"continuum - 1| at w = {tw['w'][lo]:g}", "continuum",
                                      f"{cont[lo]:.4g}" if math.isfinite(cont[lo]) else "0",
                                      f"{mf[lo]:.4g}" if math.isfinite(mf[lo]) else f"{rel[lo]:.3g}",
                                      f"{rel[lo]:.3%}; {rate}", "<= 1% at the smallest w",
                                      verdict_of(rel[lo] <= DISORDER_LEVEL if math.isfinite(rel[lo]) else None),
                                      st.source, f"{tw['w'][lo]:g}"))
    return figs, rows


# ---- c_min(H) of the strip at fixed material (docs/fronts.md §10.12; CSV of the study kind strip_cmin_height, or of
# build/bench/strip_cmin_height) ----

CMIN_CSV = "strip_cmin_height.csv"
CMIN_1D_TOL = 0.01  # "the 1D regime holds": c_min within 1 % of the 1D c_min at mu = mu' H
CMIN_LEAVE = 0.01  # "the crossover": the local exponent first below 1/2 - 0.01


def cmin_is_inplane(path):
    """Whether a strip_cmin_height CSV comes from the in-plane strip: the scalar `inplane` of the study.h5 beside it
    (docs/fronts.md §11.8); False without one (the antiplane strip's CSVs before issue 39)."""
    h5 = os.path.join(os.path.dirname(path), "study.h5")
    try:
        with h5py.File(h5, "r") as f:
            return bool(plot.as_float(f["study/scalars"].attrs.get("inplane", 0.0)) == 1.0)
    except (OSError, KeyError):
        return False


def read_cmin_csv(path):
    """The columns of a strip_cmin_height CSV as float arrays (rows with a finite positive H and c_min), sorted by H;
    None when it has no such row or lacks a column the figure needs."""
    import csv
    with open(path, newline="", encoding="utf-8", errors="replace") as f:
        rows = list(csv.DictReader(f))
    need = ("H", "H_over_l", "H_over_l_kappa", "c_min", "c_min_over_s", "c_min_1d")
    if not rows or any(k not in rows[0] for k in need):
        return None

    def num(v):
        try:
            return float(v)
        except (TypeError, ValueError):
            return math.nan
    t = {k: np.array([num(r.get(k)) for r in rows]) for k in need}
    # the estimate beside each c_min (docs/fronts.md §10.20; NaN in a CSV written before it existed)
    t["c_min_error"] = np.array([num(r.get("c_min_error")) for r in rows])
    # the mesh of each height and its verdict on paths.rtol (1 met, 0 NOT met, NaN not judged or an older CSV)
    for k in ("rows", "intervals", "rtol_met"):
        t[k] = np.array([num(r.get(k)) for r in rows])
    ok = np.isfinite(t["H"]) & (t["H"] > 0) & np.isfinite(t["c_min"]) & (t["c_min"] > 0)
    order = np.argsort(t["H"][ok])
    t = {k: v[ok][order] for k, v in t.items()}
    return t if len(t["H"]) else None


def cmin_analysis(t):
    """The paper's lengths from the data (l = H/(H/l), l_kappa, s = c/(c/s)), the local exponent between neighbours,
    the paper's intermediate-regime exponent 1/2 - eps/2 (tan(pi eps/2) = c/s at the interval's midpoint), the
    Brener-Marchenko eps_BM = ln(H/l_k)/ln(H/l), and the one-line answer's numbers."""
    H, c, c1 = t["H"], t["c_min"], t["c_min_1d"]
    a = {"H": H, "c": c, "c1": c1}
    a["l"] = float(np.median(H / t["H_over_l"]))
    a["lk"] = float(np.median(H / t["H_over_l_kappa"]))
    a["s"] = float(np.median(c / t["c_min_over_s"]))
    a["ratio"] = c / c1
    a["eps"] = 2 / math.pi * np.arctan(c / a["s"])
    with np.errstate(divide="ignore", invalid="ignore"):
        a["eps_bm"] = np.where(H > a["lk"], np.log(H / a["lk"]) / np.log(H / a["l"]), math.nan)
    if len(H) >= 2:
        a["Hmid"] = np.sqrt(H[1:] * H[:-1])
        a["expo"] = np.log(c[1:] / c[:-1]) / np.log(H[1:] / H[:-1])
        a["pred"] = 0.5 - (2 / math.pi * np.arctan(np.sqrt(c[1:] * c[:-1]) / a["s"])) / 2
    else:
        a["Hmid"] = a["expo"] = a["pred"] = np.array([])
    # prefactor of the 1D line c_min,1D/s = A sqrt(H/l_k), from the 1D c_min at the smallest H
    a["A"] = float(c1[0] / (a["s"] * math.sqrt(H[0] / a["lk"]))) if math.isfinite(c1[0]) else math.nan
    # where the 1D regime holds: the largest H up to which every c_min is within CMIN_1D_TOL of the 1D c_min
    good = np.abs(a["ratio"] - 1) <= CMIN_1D_TOL
    a["n1d"] = int(np.argmin(good)) if not good.all() else len(H)
    # the crossover: the first interval whose local exponent is below 1/2 - CMIN_LEAVE
    low = np.where(a["expo"] < 0.5 - CMIN_LEAVE)[0]
    a["cross"] = int(low[0]) if len(low) else -1
    return a


def intermediate_form(H, a):
    """The paper's intermediate regime, c/s = A sqrt(H/l_k) (l/H)^(eps/2) with tan(pi eps/2) = c/s (A the 1D
    prefactor): solved for c by bisection at each H > l (the right side falls with c there)."""
    out = np.full(len(H), math.nan)
    for i, h in enumerate(H):
        if h <= a["l"] or not math.isfinite(a["A"]):
            continue
        top = a["A"] * math.sqrt(h / a["lk"])
        lo, hi = 0.0, top
        for _ in range(80):
            x = 0.5 * (lo + hi)
            eps = 2 / math.pi * math.atan(x)
            if x < top * (a["l"] / h) ** (eps / 2):
                lo = x
            else:
                hi = x
        out[i] = a["s"] * 0.5 * (lo + hi)
    return out


def strip_cmin_section(path, root, figdir):
    """The report's c_min(H) section: the figure (c_min against H, log-log, with the 1D line, the paper's
    intermediate form, the Brener-Marchenko large-H form and the lengths l, l_kappa; below, the local exponent
    against 1/2 and the paper's exponents) and one summary row answering the paper's question from the numbers.
    ([], []) when the file has no usable row."""
    try:
        t = read_cmin_csv(path)
    except OSError as e:
        print(f"report.py: warning: {path}: {e}", file=sys.stderr)
        return [], []
    if t is None:
        return [], []
    a = cmin_analysis(t)
    H, c = a["H"], a["c"]
    l, lk, s = a["l"], a["lk"], a["s"]
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(9, 9), sharex=True, constrained_layout=True,
                                 gridspec_kw={"height_ratios": [3, 2]})
    ax.loglog(H, c, "o-", color="C0", lw=1, label="c_min of the strip (computed)")
    if np.isfinite(a["c1"]).any():
        ax.loglog(H, a["c1"], "--", color="k", lw=1,
                  label=f"1D c_min at mu = mu' H (measured; = {a['A']:.4f} s sqrt(H/l_kappa))")
    ax.loglog(H, 0.576 * s * np.sqrt(H / lk), ":", color="0.5", lw=1,
              label="paper's 1D line 0.576 sqrt(mu' H alpha/(eta kappa)) = 0.576 s sqrt(H/l_kappa)")
    Hs = np.geomspace(H[0], H[-1], 200)
    inter = intermediate_form(Hs, a)
    if np.isfinite(inter).any():
        ax.loglog(Hs, inter, "-", color="C2", lw=1,
                  label="paper, l << H << l_kappa: c/s = A sqrt(H/l_kappa) (l/H)^(eps/2), tan(pi eps/2) = c/s")
    bm = Hs > lk * 1.05
    if bm.any():
        eb = np.log(Hs[bm] / lk) / np.log(Hs[bm] / l)
        ax.loglog(Hs[bm], s * np.tan(np.pi * eb / 2), "-", color="C3", lw=1,
                  label="Brener-Marchenko, H >> l_kappa: c/s = tan(pi eps_BM/2), eps_BM = ln(H/l_kappa)/ln(H/l)")
    ax.axhline(s, color="0.6", ls=":", lw=0.8)
    for b in (ax, bx):
        for x, name in ((l, "l"), (lk, "l_kappa")):
            if H[0] <= x <= H[-1]:
                b.axvline(x, color="0.4", ls="-.", lw=0.8)
    for x, name in ((l, f"l = {l:.4g}"), (lk, f"l_kappa = {lk:.4g}")):
        if H[0] <= x <= H[-1]:
            ax.text(x, ax.get_ylim()[0], " " + name, rotation=90, va="bottom", ha="right", fontsize=8, color="0.3")
    ax.text(H[0], s, f" s = mu'/eta = {s:.4g}", va="bottom", fontsize=8, color="0.4")
    ax.set_ylabel("c_min")
    ax.legend(fontsize=8, loc="upper left")
    if len(a["expo"]):
        bx.semilogx(a["Hmid"], a["expo"], "o-", color="C0", lw=1, label="d ln c_min / d ln H (between neighbours)")
        bx.semilogx(a["Hmid"], a["pred"], "s--", color="C2", lw=1, mfc="none",
                    label="paper, intermediate: 1/2 - eps/2 (eps from the measured c/s)")
        if bm.sum() >= 3:
            cb = np.log(s * np.tan(np.pi * (np.log(Hs[bm] / lk) / np.log(Hs[bm] / l)) / 2))
            bx.semilogx(Hs[bm][1:-1], (cb[2:] - cb[:-2]) / (np.log(Hs[bm][2:]) - np.log(Hs[bm][:-2])), "-", color="C3",
                        lw=1, label="Brener-Marchenko form's d ln c / d ln H")
        bx.axhline(0.5, color="k", ls="--", lw=0.8, label="1/2 (1D)")
        bx.set_ylim(0, 0.7)
        bx.legend(fontsize=8, loc="lower left")
    else:
        plot.no_data(bx, "one H only: no local exponent")
    bx.set_xlabel("H (strip height)")
    bx.set_ylabel("local exponent")
    fig.suptitle(f"c_min(H) of the strip at fixed material (l = {l:.4g}, l_kappa = {lk:.4g}, s = {s:.4g}); "
                 f"{os.path.relpath(path, root)}", fontsize=9)
    figs = []
    save(fig, figdir, f"{figure_key(root, path)}_cmin_vs_H.png", figs)

    # the one-line answer, from the numbers
    n1d, k = a["n1d"], a["cross"]
    if n1d == 0:
        holds = f"1D c_min (within {CMIN_1D_TOL:.0%}) fails already at H = {H[0]:.4g}"
    else:
        holds = (f"1D c_min holds (within {CMIN_1D_TOL:.0%}) up to H = {H[n1d - 1]:.4g} (H/l = {H[n1d - 1] / l:.3g})"
                 + ("" if n1d < len(H) else ", the largest H"))
    if k >= 0:
        cross = (f"exponent leaves 1/2 (< {0.5 - CMIN_LEAVE:.2f}: {a['expo'][k]:.3f}) on H/l = {H[k] / l:.3g} .. "
                 f"{H[k + 1] / l:.3g}")
    else:
        cross = f"exponent stays >= {0.5 - CMIN_LEAVE:.2f} to H = {H[-1]:.4g}"
    big = len(H) - 1
    if H[big] > lk and math.isfinite(a["eps_bm"][big]):
        gap = (f"at H = {H[big]:.4g} (H/l_kappa = {H[big] / lk:.3g}): eps = {a['eps'][big]:.3f} vs eps_BM = "
               f"{a['eps_bm'][big]:.3f} (gap {a['eps'][big] - a['eps_bm'][big]:+.3f}; c_min = "
               f"{c[big] / (s * math.tan(math.pi * a['eps_bm'][big] / 2)):.3g} x BM), c_min/c_min,1D = {a['ratio'][big]:.3g}")
    else:
        gap = f"no H > l_kappa = {lk:.4g}: large-H regime not reached (c_min/c_min,1D = {a['ratio'][big]:.3g} at H = {H[big]:.4g})"
    expo = (f"local exponent {a['expo'][0]:.3f} -> {a['expo'][-1]:.3f}" if len(a["expo"]) else "")
    rel = t["c_min_error"] / t["c_min"]
    if np.isfinite(rel).any():
        w = int(np.nanargmax(rel))
        errs = (f"; c_min carries its estimated error: largest {100 * rel[w]:.2g} % "
                f"(c_min = {t['c_min'][w]:.6g} ± {t['c_min_error'][w]:.2g} at H = {H[w]:.4g})")
    else:
        errs = "; no error estimates in this CSV (written before docs/fronts.md §10.20)"
    unmet = [f"{h:.4g}" for h, v in zip(H, t["rtol_met"]) if v == 0]
    if unmet:
        errs += f"; rtol NOT met at {len(unmet)} of {len(H)} heights (H = {', '.join(unmet)})"
    body = "the in-plane strip" if cmin_is_inplane(path) else "the strip"
    rows = [measure_row(f"c_min(H) of {body}, H = {H[0]:.4g} .. {H[-1]:.4g}: does the 1D c_min hold?",
                        f"{holds}; {cross}", "", gap, expo + errs),
            answer_row("Does the minimal steady front speed vary smoothly from 1D to 2D as H grows?"
                       + (" (the in-plane strip)" if body != "the strip" else ""),
                       f"c_min(H) at fixed strip material, H = {H[0]:.4g} .. {H[-1]:.4g}: {holds}; {cross}; {gap}.",
                       bool(np.all(np.isfinite(c)) and np.all(np.isfinite(a["expo"]))),
                       f"c_min is found at every H = {H[0]:.4g} .. {H[-1]:.4g}; {holds}; {cross}",
                       figs[0] if figs else "", 4)]
    return figs, rows


CMIN_BODIES_AGREE = 0.01  # the two bodies "agree": in-plane c_min within 1 % of the antiplane one at the same 1D material


def cmin_bodies_plots(st, outdir):
    """c_min(H) of both strips on one plot (issue 39 item 2, docs/fronts.md §11.8): a strip_cmin_height study on the
    in-plane strip (scalar inplane = 1) beside the antiplane study of the main job (../strip_cmin_height/, the same 1D
    material: l, l_kappa, s equal), with the 1D line, the paper's regimes and the lengths; below, c_min/c_min,1D and the
    local exponents of both. One summary row: where the bodies agree, where not. ([], []) for the antiplane study or
    when either CSV is missing."""
    if st.scalars.get("inplane", 0.0) != 1.0:
        return [], []
    anti_path = os.path.join(os.path.dirname(st.dir), "strip_cmin_height", CMIN_CSV)
    try:
        tin = read_cmin_csv(os.path.join(st.dir, CMIN_CSV))
        tan = read_cmin_csv(anti_path) if os.path.exists(anti_path) else None
    except OSError as e:
        print(f"report.py: warning: {e}", file=sys.stderr)
        return [], []
    if tin is None:
        return [], []
    ain = cmin_analysis(tin)
    l, lk, s = ain["l"], ain["lk"], ain["s"]
    fig, (ax, bx, cx) = plt.subplots(3, 1, figsize=(9, 11), sharex=True, constrained_layout=True,
                                     gridspec_kw={"height_ratios": [3, 2, 2]})
    bodies = [("in-plane strip", tin, ain, "C0", "o")]
    if tan is not None:
        bodies.append(("antiplane strip", tan, cmin_analysis(tan), "C1", "s"))
    for name, t, a, col, mk in bodies:
        e = t["c_min_error"]
        ax.errorbar(a["H"], a["c"], yerr=np.where(np.isfinite(e), e, 0), fmt=mk + "-", color=col, lw=1, ms=4,
                    label=f"c_min, {name}")
        bx.semilogx(a["H"], a["ratio"], mk + "-", color=col, lw=1, label=name)
        if len(a["expo"]):
            cx.semilogx(a["Hmid"], a["expo"], mk + "-", color=col, lw=1, label=f"d ln c_min/d ln H, {name}")
            cx.semilogx(a["Hmid"], a["pred"], mk + ":", color=col, lw=1, mfc="none", label=f"1/2 - eps/2 from its c/s ({name})")
    ax.loglog(ain["H"], ain["c1"], "--", color="k", lw=1, label="1D c_min of the same column mu = E'H = mu'H")
    Hs = np.geomspace(ain["H"][0], ain["H"][-1], 200)
    inter = intermediate_form(Hs, ain)
    if np.isfinite(inter).any():
        ax.loglog(Hs, inter, "-", color="C2", lw=0.8, label="paper, l << H << l_kappa (A sqrt(H/l_kappa)(l/H)^(eps/2))")
    bm = Hs > lk * 1.05
    if bm.any():
        eb = np.log(Hs[bm] / lk) / np.log(Hs[bm] / l)
        ax.loglog(Hs[bm], s * np.tan(np.pi * eb / 2), "-", color="C3", lw=0.8, label="Brener-Marchenko, H >> l_kappa")
    ax.axhline(s, color="0.6", ls=":", lw=0.8)
    for b in (ax, bx, cx):
        for x in (l, lk):
            if ain["H"][0] <= x <= ain["H"][-1]:
                b.axvline(x, color="0.4", ls="-.", lw=0.8)
    ax.set_ylabel("c_min")
    ax.legend(fontsize=7, loc="upper left")
    bx.axhline(1.0, color="k", ls="--", lw=0.8)
    bx.set_ylabel("c_min / c_min,1D")
    bx.legend(fontsize=7)
    cx.axhline(0.5, color="k", ls="--", lw=0.8)
    cx.set_ylim(0, 0.7)
    cx.set_ylabel("local exponent")
    cx.set_xlabel(f"H (l = {l:.4g}, l_kappa = {lk:.4g}: dash-dotted)")
    cx.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"c_min(H) of the in-plane and antiplane strips at the same 1D material (s = {s:.4g}); "
                 f"{st.name}", fontsize=9)
    figs = []
    save(fig, outdir, f"{st.stem}_cmin_bodies.png", figs)
    rows = [measure_row("c_min(H) in-plane: c_min/c_min,1D at the smallest and largest H",
                        f"{ain['ratio'][0]:.6g} (H = {ain['H'][0]:.4g}), {ain['ratio'][-1]:.4g} (H = {ain['H'][-1]:.4g})",
                        "", "", "docs/fronts.md §11.8")]
    if tan is not None:
        common = np.intersect1d(tin["H"], tan["H"])
        rin = np.array([tin["c_min"][tin["H"] == h][0] for h in common])
        ran = np.array([tan["c_min"][tan["H"] == h][0] for h in common])
        q = rin / ran
        agree = np.abs(q - 1) <= CMIN_BODIES_AGREE
        n = int(np.argmin(agree)) if not agree.all() else len(common)
        upto = f"up to H = {common[n - 1]:.4g} (H/l = {common[n - 1] / l:.3g})" if n else "at no height"
        short = (f"in-plane c_min within {CMIN_BODIES_AGREE:.0%} of the antiplane one {upto}; "
                 f"in-plane/antiplane = {q[-1]:.3g} at H = {common[-1]:.4g} (H/l_kappa = {common[-1] / lk:.3g})")
        rows.append(answer_row("Does c_min(H) of the paper's in-plane body follow the antiplane strip's "
                               "(the same 1D material)?", short + ".", bool(agree.all()), short, figs[0], 4))
    return figs, rows


def study_plots(kind):
    """The plots of a study of `kind`: the function `<kind>_study(st, outdir) -> (figures, summary rows)` of this file.
    The kinds are the program's one table (studies::study_kinds() in studies/study.cpp; `slipfront study --list-kinds
    --json`, docs/cli.md), listed nowhere here: tests/test_study_kinds.cpp checks that every kind of the table has its
    function here and every such function names a kind of the table. A kind without plots has one returning none."""
    def resolution_study(st, outdir):  # the errors and orders: the section's scalars and notes (tables in study.h5)
        return [], []

    def strip_cmin_height_study(st, outdir):  # its CSV has its own section (cmin_section); in-plane: both bodies
        return cmin_bodies_plots(st, outdir)

    def runs_study(st, outdir):  # no analysis: nothing to draw
        return [], []

    return {**globals(), **locals()}.get(f"{kind}_study", runs_study)


def scene_rows(res, source=""):
    """Summary rows of a scene file with the discrete model and its reference (/compare's `reference`: mean_field
    when the scene lists it, else the continuum). The discrete model against its reference is a limit that must
    hold when the reference is the ensemble's own N -> infinity limit at its w: mean_field, or the continuum at
    w = 0 (docs/model.md §2.1, §2.2); with w > 0 against the continuum it is an effect of the disorder (no verdict).
    With both mean_field and continuum, mean_field against the continuum is the effect of w at N -> infinity."""
    rows = []
    if "discrete" not in res.models or not ({"continuum", "mean_field"} & set(res.models)):
        return rows
    ref = reference_of(res)
    if ref not in res.models:
        ref = "mean_field" if "mean_field" in res.models else "continuum"
    w, noise = disorder_of(res)
    n = res.param("discrete", "contacts_per_site", "?")
    if res.kind() == "sweep":  # Fig. 2 (left): the minimum of the steady law, both models and the closed form
        p = plot.interface_params(res)
        values = {}
        for m in res.models:
            a = res.group(m).attrs
            values[m] = {what: plot.as_float(a.get(k, a.get(k2, math.nan)))
                         for what, k, k2 in (("v_m", "v_m_numeric", "v_m_fit"), ("sigma_c^d", "sigma_c_numeric",
                                                                                   "sigma_c_fit"))}
            if m == "discrete":
                values[m] = {"v_m": plot.as_float(a.get("v_m_fit", math.nan)),
                             "sigma_c^d": plot.as_float(a.get("sigma_c_fit", math.nan))}
        keys = (("v_m", 0), ("sigma_c^d", 1))
        ag = plot.aging_params(res)
        closed = (plot.aged_minimum_of_friction(p, ag) if ag else plot.minimum_of_friction(*p)) if p else None
        label = {k: f"{k} (closed form{' with aging' if ag else ''} {closed[i]:.5g}; discrete: parabola fit)" if p else k
                 for k, i in keys}
    else:
        values = {m: plot.events(res.group(m)) for m in res.models}
        keys = [(k, 0) for k in {"edge": ("t_star", "t_hat", "c_slow_alt", "c_transient", "x_arrest"),
                                 "homogeneous": ("c_front", "v_behind"),
                                 "spring_block": ("t_star", "t_hat")}.get(res.loading(), ("t_star",))]
        label = {k: f"{k} (discrete N={n})" for k, _ in keys}
    tested = ref == "mean_field" or w == 0
    for k, _ in keys:
        c, d = values[ref].get(k, math.nan), values["discrete"].get(k, math.nan)
        if not (math.isfinite(c) or math.isfinite(d)):
            continue
        relv = (d - c) / abs(c) if math.isfinite(c) and math.isfinite(d) and c != 0 else math.nan
        rel = f"{relv:+.2%}" if math.isfinite(relv) else ""
        if tested:
            if noise:
                lim, tol, thr = f"discrete -> {ref} as N -> inf at w = {fmt_w(w)}", SCENE_EVENT_TOL, "abs <= 5%"
            else:
                lim, tol, thr = f"discrete = {ref} at w = {fmt_w(w)}, noise off", IDENTITY_TOL, "abs <= 1e-12"
            ok = None if not math.isfinite(relv) else abs(relv) <= tol
            rows.append(limit_row(lim, f"{res.scene}: {label[k]}", ref, f"{c:.5g}", f"{d:.5g}",
                                  f"relative difference {rel or 'n/a'}", thr, verdict_of(ok), source, fmt_w(w),
                                  score=abs(relv) / tol if math.isfinite(relv) else None))
        else:
            rows.append(effect_row(f"threshold disorder w = {fmt_w(w)} (discrete N = {n}; the continuum is w = 0)",
                                   f"{res.scene}: {label[k]}", f"continuum {c:.5g}", f"discrete {d:.5g}", rel,
                                   "no mean_field in the file: the disorder's effect, not a test", source))
    if ref == "mean_field" and "continuum" in res.models and w > 0:
        for k, _ in keys:
            c, m = values["continuum"].get(k, math.nan), values["mean_field"].get(k, math.nan)
            if not (math.isfinite(c) or math.isfinite(m)):
                continue
            rel = f"{(m - c) / abs(c):+.2%}" if math.isfinite(c) and math.isfinite(m) and c != 0 else ""
            rows.append(effect_row(f"threshold disorder w = {fmt_w(w)} (mean_field: N -> inf at w; continuum: w = 0)",
                                   f"{res.scene}: {label[k].replace(f' (discrete N={n})', '')}", f"continuum {c:.5g}",
                                   f"mean_field {m:.5g}", rel, "deterministic, both N -> inf", source))
    if res.loading() == "homogeneous":
        rows += settle_rows(res, values)
    rows += normal_stress_rows(res, ref)
    return rows


CLOSURE_TOL = 0.10  # the closure's measured steady offset within 10 % of the derived Jensen offset (§11.4)


def aging_rows(res, source):
    """Contact aging (docs/model.md §11): the limits ensemble -> mean field -> closure, each with its statistic. On a
    sweep, the closure's steady offset from the balance at the lowest rate against the derived
    alpha phi b (ln(1 + 1/x) - e^x E1(x)), x = kappa v tau_a (§11.4: a limit of the derivation, tested); on a
    slide-hold-slide history, the ensemble's peak slope d peak / d ln t_h against mean_field's (5 %) and the
    closure's peaks against mean_field's (measured: the closure gives new contacts the old ones' mean age)."""
    ag, p = plot.aging_params(res), plot.interface_params(res)
    if not ag or not p or "mean_field" not in res.models:
        return []
    rows, w = [], fmt_w(disorder_of(res)[0])
    if res.kind() == "sweep" and "continuum" in res.models:
        v, c = (plot.dataset(res.group("continuum"), f"friction_law/{k}") for k in ("v", "sigma"))
        m = plot.dataset(res.group("mean_field"), "friction_law/sigma")
        if v is not None and c is not None and m is not None and len(v) == len(c) == len(m) and len(v):
            k = int(lowest_rate_index(v))
            (alpha, kappa, _), (b, tau) = p, ag
            x = kappa * abs(v[k]) * tau
            derived = alpha * b * (math.log1p(1.0 / x) - float(plot.exp_e1(x)[0])) / (1.0 + kappa * abs(v[k]))
            rel = (c[k] - m[k]) / derived - 1.0
            rows.append(limit_row("closure -> age-structured balance: the steady offset (docs/model.md §11.4)",
                                  f"{res.scene}: sigma_closure - sigma_mean_field at v = {v[k]:.3g} (reference value: "
                                  "the derived offset)", "mean_field", f"{derived:.4g}", f"{c[k] - m[k]:.4g}",
                                  f"relative to the derived {rel:+.2%}", f"abs <= {CLOSURE_TOL:.0%}",
                                  verdict_of(abs(rel) <= CLOSURE_TOL), source, w, score=abs(rel) / CLOSURE_TOL))
    pk = plot.model_hold_peaks(res) if res.kind() == "history" else {}
    if "mean_field" in pk:
        ref = plot.peak_slope(pk["mean_field"])
        if "discrete" in pk:
            d = plot.peak_slope(pk["discrete"])
            rel = (d - ref) / abs(ref)
            rows.append(limit_row("discrete -> mean_field as N -> inf (contact aging)",
                                  f"{res.scene}: static peak slope d peak / d ln t_h (t_h >= 10; discrete N="
                                  f"{res.param('discrete', 'contacts_per_site', '?')})", "mean_field", f"{ref:.4g}",
                                  f"{d:.4g}", f"relative difference {rel:+.2%}", "abs <= 5%",
                                  verdict_of(abs(rel) <= SCENE_EVENT_TOL), source, w, score=abs(rel) / SCENE_EVENT_TOL))
        if "continuum" in pk and len(pk["continuum"]) == len(pk["mean_field"]):
            c, m = pk["continuum"], pk["mean_field"]
            rows.append(measure_row(f"{res.scene}: the one-variable closure's static peaks against mean_field's",
                                    f"t_h = {c[0, 0]:g}: {c[0, 1]:.4g}", f"{m[0, 1]:.4g}",
                                    f"{c[0, 1] - m[0, 1]:+.4g} (t_h = {c[-1, 0]:g}: {c[-1, 1] - m[-1, 1]:+.2g})",
                                    f"slopes {plot.peak_slope(c):.4f} / {ref:.4f}: the closure gets the ln t_h slope, "
                                    "not the short holds (docs/model.md §11.4); figure <scene>_peaks.png"))
    return rows


def lowest_rate_index(v):
    """Index of the smallest |v| (the sweep's lowest rate)."""
    return min(range(len(v)), key=lambda i: abs(v[i]))


BASE_EVENTS = ("t_star", "t_hat", "c_transient", "x_arrest")


def base_effect_rows(res, root, source):
    """The effects of aging and of a normal-load profile on fig1 (docs/model.md §11, §12): a fig1_* scene with
    interface.aging_b > 0 or interface.load_x against fig1 of the same output tree (DIR/fig1/results.h5), the
    continuum's events (and mean_field's, against fig1's continuum). None without fig1 in the tree."""
    effects = []
    if plot.aging_params(res):
        effects.append(f"contact aging b = {plot.aging_params(res)[0]:g}, tau_a = {plot.aging_params(res)[1]:g}")
    if res.param("interface", "load_x"):
        effects.append(f"normal-load profile p/p0 = {res.param('interface', 'load_p')} at x = "
                       f"{res.param('interface', 'load_x')} ({res.param('interface', 'load_channel', 'reattachment')})")
    base = os.path.join(root, "fig1", "results.h5")
    if not effects or not res.scene.startswith("fig1_") or res.loading() != "edge" or not os.path.exists(base):
        return []
    try:
        b = plot.Results(base)
        with b.f:
            without = plot.events(b.group("continuum")) if "continuum" in b.models else {}
    except OSError:
        return []
    rows = []
    for m in ("continuum", "mean_field"):
        if m not in res.models:
            continue
        e = plot.events(res.group(m))
        for k in BASE_EVENTS:
            a, w = without.get(k, math.nan), e.get(k, math.nan)
            if math.isfinite(a) and math.isfinite(w):
                rows.append(effect_row("; ".join(effects), f"{res.scene}: {k} ({m})", f"fig1 continuum {a:.5g}",
                                       f"{m} {w:.5g}", f"{(w - a) / abs(a):+.2%}" if a else "",
                                       "the effect against fig1 (DIR/fig1/results.h5)", source))
    return rows


def normal_stress_rows(res, ref):
    """The in-plane strip's interface normal stress compared (/compare/sigma_yy_snapshot_distance and the histories of
    its extremes, docs/output.md): one measurement row, no verdict (the discrete model's sampling sets it)."""
    c = res.f["compare"] if "compare" in res.f else None
    if c is None or "sigma_yy_snapshot_distance" not in c:
        return []
    val = {k: plot.as_float(c[k][()]) if k in c else math.nan
           for k in ("sigma_yy_snapshot_distance", "min_sigma_yy_history_distance", "max_sigma_yy_history_distance")}
    return [measure_row(f"{res.scene}: interface normal stress sigma_yy(x, 0, t), discrete against {ref}", "", "",
                        f"snapshots {val['sigma_yy_snapshot_distance']:.3g}; min/max histories "
                        f"{val['min_sigma_yy_history_distance']:.3g} / {val['max_sigma_yy_history_distance']:.3g}",
                        "relative L2 distances (/compare, docs/output.md); figure <scene>_sigma_yy.png")]


def scene_answers(res, written):
    """The answers of the paper's Fig. 1 (the scene fig1, edge loading) and Fig. 2 left (the scene friction_law, a
    sweep) from the continuum's events or steady law, each with the scene's figure."""
    if "continuum" not in res.models:
        return []
    fig = lambda suffix: next((w for w in written if w.endswith(suffix)), "")  # noqa: E731
    if res.scene == "fig1" and res.loading() == "edge":
        e, L = plot.events(res.group("continuum")), plot.as_float(res.param("bulk", "length", math.nan))
        ts, th, xa = (e.get(k, math.nan) for k in ("t_star", "t_hat", "x_arrest"))
        yes = all(math.isfinite(v) for v in (ts, th, xa)) and (not math.isfinite(L) or xa < L)
        short = (f"slow front from t* = {ts:.4g}, fast transient at t^ = {th:.4g}, arrest at x = {xa:.4g} of "
                 f"L = {L:g} (continuum)" if yes else
                 "the sequence is incomplete (continuum): " + ", ".join(
                     f"{k} = {v:.4g}" if math.isfinite(v) else f"no {k}" for k, v in
                     (("t*", ts), ("t^", th), ("x_arrest", xa))))
        return [answer_row("Fig. 1: does edge loading give a slow front, then a fast transient front that arrests "
                           "inside the system?", short, yes, short, fig(f"{res.scene}_fronts.png"), 1)]
    if res.scene == "friction_law" and res.kind() == "sweep":
        a = res.group("continuum").attrs
        vm, sc = (plot.as_float(a.get(k, math.nan)) for k in ("v_m_numeric", "sigma_c_numeric"))
        yes = math.isfinite(vm) and math.isfinite(sc)
        p = plot.interface_params(res)
        closed = f" (closed form {plot.minimum_of_friction(*p)[1]:.5g})" if p else ""
        short = (f"sigma_ss(v) falls, then rises: its minimum sigma_c^d = {sc:.5g}{closed} at v_m = {vm:.4g}"
                 if yes else "no minimum of the measured steady friction law")
        return [answer_row("Fig. 2 left: is the steady friction law velocity-weakening, then strengthening, with a "
                           "minimum sigma_c^d?", short, yes, short, fig(f"{res.scene}_steady_friction.png"), 2)]
    return []


def settle_rows(res, values):
    """A nucleated front's c_front is measured where its speed has settled (docs/model.md §3.1): per model, where it
    settled and the drift it saw, or that it did not settle (c_front is then the middle-half fit)."""
    rows = []
    for m in res.models:
        e = values.get(m, {})
        c, settled = e.get("c_front", math.nan), e.get("front_settled", math.nan)
        if not math.isfinite(c) or not math.isfinite(settled):
            continue
        x, drift = e.get("x_settled", math.nan), e.get("c_front_drift", math.nan)
        where = f"settled from x = {x:.0f}" if settled > 0 else "did not settle: middle-half fit"
        rows.append(measure_row(f"{res.scene}: c_front ({m})", f"{c:.5g}", "", f"drift {drift:+.2%}",
                                f"{where} (docs/model.md §3.1)"))
    return rows


# --------------------------------------------------------------------------------------------
# contact statistics (docs/contacts.md): the agent's measured ones against the continuum's prediction

PHASES = ("before yield", "slow front", "transient", "after arrest")
REGIONS = ("behind", "tip", "ahead")


def _contacts(res):
    """(the reference's contacts group, discrete contacts group) when both have the class tables, else None. The
    reference is the model /compare tested the agent against (mean_field when listed, else the continuum:
    docs/contacts.md §3); its tables are the prediction."""
    f = res.f
    ref = reference_of(res)
    if f"{ref}/contacts/class_lifetime_counts" in f and "discrete/contacts/class_lifetime_counts" in f:
        return f[f"{ref}/contacts"], f["discrete/contacts"]
    return None


def _matched(c, d, table="region_age_counts"):
    """A per-snapshot region table (region_age_counts or region_threshold_counts) by class, summed over the contact
    snapshots at which both models were in the same phase (as compare::matched_tables); (measured, predicted)
    [12, nb] or None."""
    need = (table, "contact_snapshot_phase", "snapshot_t")
    if not all(k in c and k in d for k in need):
        return None
    rm, rp = d[table][()], c[table][()]
    pm, pp = d["contact_snapshot_phase"][()], c["contact_snapshot_phase"][()]
    if rm.shape != rp.shape or len(pm) != len(pp):
        return None
    nb = rm.shape[1] // 3
    m, p = np.zeros((12, nb)), np.zeros((12, nb))
    for k in range(len(pm)):
        if pm[k] != pp[k] or pm[k] >= 4:  # phase 4 (next event): not classed (docs/model.md §7.2)
            continue
        ph = int(pm[k])
        m[3 * ph:3 * ph + 3] += rm[k].reshape(3, nb)
        p[3 * ph:3 * ph + 3] += rp[k].reshape(3, nb)
    return m, p


def _fit_rows(res):
    """/compare/contacts as a list of dicts."""
    if "compare/contacts" not in res.f:
        return []
    g = res.f["compare/contacts"]
    cols = {k: g[k][()] for k in g}
    return [{k: float(v[i]) for k, v in cols.items()} for i in range(len(cols.get("phase", [])))]


def _class_grid(res, outdir, figs, name, what, measured, predicted, edges, fits, stat, ref="continuum"):
    """Histograms per phase (rows) and region (columns): the agent's (bars) and the prediction (line),
    as fractions per decade of the class's total."""
    rows = [ph for ph in range(4) if measured[3 * ph:3 * ph + 3].sum() + predicted[3 * ph:3 * ph + 3].sum() > 0]
    if not rows:
        return
    # fixed margins, not constrained_layout: on these log axes its iterated tick layout took 3 of the 3.5 s a
    # grid costs (cProfile), and the grid is regular
    height = 3.1 * len(rows) + 1
    fig, axes = plt.subplots(len(rows), 3, figsize=(13, height), squeeze=False)
    title = res.title(f"{what}: agent (red bars) vs {ref} prediction (blue line), by phase and region; "
                      "per panel the contacts counted, measured / predicted", fig)
    top = 0.45 + 0.18 * (title.count("\n") + 1)  # inches above the first row's (two-line) titles: the suptitle's lines
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.75 / height, top=1 - top / height, wspace=0.22, hspace=0.75)
    lo = np.where(edges[:-1] > 0, edges[:-1], edges[1] / 10 ** 0.2)  # [0, 1e-3) drawn one bin wide
    hi = np.where(np.isfinite(edges[1:]), edges[1:], edges[-2] * 10 ** 0.2)
    dec = np.log10(hi / lo)
    for i, ph in enumerate(rows):
        for r in range(3):
            ax = axes[i, r]
            cls = 3 * ph + r
            mt, pt = measured[cls].sum(), predicted[cls].sum()
            if mt <= 0 and pt <= 0:  # a class no contact ended in: a note, not an empty panel
                ax.axis("off")
                ax.text(0.5, 0.5, f"{PHASES[ph]}, {REGIONS[r]}:\nno contacts, measured or predicted",
                        ha="center", va="center", transform=ax.transAxes, fontsize=9, color="0.35")
                continue
            else:
                if mt > 0:
                    ax.stairs(measured[cls] / mt / dec, np.append(lo[0], hi), fill=True, color="C3", alpha=0.45)
                if pt > 0:
                    ax.stairs(predicted[cls] / pt / dec, np.append(lo[0], hi), color="C0", lw=1.4)
                ax.set_xscale("log")
                fit = [f for f in fits if f["statistic"] == stat and int(f["phase"]) == ph and int(f["region"]) == r]
                # counts and the fit in the panel's title: a legend inside the axes covered the histograms' peaks
                tag = f": n {mt:.3g} / {pt:.3g}"
                if fit:
                    f = fit[0]
                    tag += f"\nKS {f['ks_distance']:.4f}, p {f['p_value']:.2g}" + ("" if f["tested"] else " (not tested)")
            ax.set_title(f"{PHASES[ph]}, {REGIONS[r]}{tag}", fontsize=9)
            ax.set_xlabel(what)
            if r == 0:
                ax.set_ylabel("fraction per decade")
    fig.suptitle(title, fontsize=9, y=1 - 0.1 / height, va="top")
    save(fig, outdir, f"{res.scene}_{name}.png", figs)


def contacts_section(res, outdir, source=""):
    """The contact-statistics figures and summary rows of a scene with the agent's statistics and the
    continuum's prediction (docs/contacts.md): age maps, lifetime and age histograms by phase and region,
    surviving thresholds; one summary row per tested statistic and class (distance to the prediction)."""
    both = _contacts(res)
    if both is None:
        return [], []
    c, d = both
    ref = reference_of(res)
    w, _ = disorder_of(res)
    figs, rows = [], []
    # 1. age maps side by side: the continuum's mean age (its age field) and the agent's (exact)
    maps = [(m, plot.dataset(res.group(m), "snapshots/age")) for m in (ref, "discrete")]
    maps = [(m, a) for m, a in maps if a is not None and a.size]
    if maps:
        pos = np.concatenate([a[np.isfinite(a) & (a > 0)] for _, a in maps])
        vmax = float(pos.max()) if pos.size else 1.0
        vmin = max(float(pos.min()) if pos.size else 1e-3, vmax * 1e-4)
        fig, axes = plt.subplots(1, len(maps) + 1, figsize=(6 * (len(maps) + 1), 5.5), squeeze=False,
                                 constrained_layout=True)
        for j, (m, a) in enumerate(maps):
            g = res.group(m)
            x, ts = plot.dataset(g, "x"), plot.dataset(g, "snapshots/t")
            pc = axes[0, j].pcolormesh(x, ts, np.clip(a, vmin, vmax), shading="nearest", cmap="cividis",
                                       norm=plot.LogNorm(vmin=vmin, vmax=vmax), rasterized=True)
            t, tip = plot.dataset(g, "series/t"), plot.dataset(g, "series/tip_x_alt")
            if t is not None and tip is not None:
                axes[0, j].plot(tip, t, "w--", lw=0.9, label="front (A < A_tip_alt)")
                axes[0, j].legend(fontsize=8, loc="upper right")
            axes[0, j].set_title((f"{m} prediction" if m != "discrete" else "agent (measured)") + ": mean age")
            axes[0, j].set_xlabel("x")
            axes[0, j].set_ylabel("t")
            fig.colorbar(pc, ax=axes[0, j], label="mean contact age")
        if len(maps) == 2 and maps[0][1].shape == maps[1][1].shape:
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.log2(maps[1][1] / maps[0][1])
            g = res.group(ref)
            pc = axes[0, -1].pcolormesh(plot.dataset(g, "x"), plot.dataset(g, "snapshots/t"), np.clip(ratio, -1, 1),
                                        shading="nearest", cmap="RdBu_r", vmin=-1, vmax=1, rasterized=True)
            fig.colorbar(pc, ax=axes[0, -1], label=f"log2(agent / {ref})")
            axes[0, -1].set_title(f"agent / {ref} (log2, clipped at ±1)")
            axes[0, -1].set_xlabel("x")
        else:
            plot.no_data(axes[0, -1], "no pair of age maps")
        fig.suptitle(res.title("mean contact age a(x, t)", fig), fontsize=9)
        save(fig, outdir, f"{res.scene}_ages.png", figs)
    fits = _fit_rows(res)
    edges = c["class_time_edges"][()]
    # 2. lifetimes, 3. ages (at the snapshots where both models share a phase)
    _class_grid(res, outdir, figs, "lifetimes", "lifetime of completed attachments", d["class_lifetime_counts"][()],
                c["class_lifetime_counts"][()], edges, fits, 0, ref)
    matched = _matched(c, d)
    if matched is not None:
        _class_grid(res, outdir, figs, "age_histograms", "age of attached contacts", matched[0], matched[1], edges,
                    fits, 1, ref)
    # 4. surviving thresholds: attached contacts by class against the drawn ones and, when the reference predicts
    # them (mean_field at the scene's w, or the continuum at w = 0: threshold_hist_edges on the agent's edges), against
    # the prediction at the snapshots both models share a phase (statistic 2 of /compare/contacts)
    if "class_threshold_counts" in d and "threshold_hist_edges" in d:
        te = d["threshold_hist_edges"][()]
        predicted = None
        if "threshold_hist_edges" in c and np.array_equal(c["threshold_hist_edges"][()], te):
            predicted = _matched(c, d, "region_threshold_counts")
        th = predicted[0] if predicted is not None else d["class_threshold_counts"][()]
        drawn = d["threshold_drawn_counts"][()] if "threshold_drawn_counts" in d else np.zeros(th.shape[1])
        mid = 0.5 * (te[:-1] + np.where(np.isfinite(te[1:]), te[1:], te[:-1]))
        width = float(plot.as_float(res.param("discrete", "width", 0.0)) or 0.0)
        prow = [ph for ph in range(4) if th[3 * ph:3 * ph + 3].sum() > 0]
        fig, axes = plt.subplots(max(1, len(prow)), 3, figsize=(13, 3 * max(1, len(prow)) + 1), squeeze=False,
                                 constrained_layout=True)
        dm = float((drawn * mid).sum() / drawn.sum()) if drawn.sum() > 0 else 1.0
        stair_edges = te[:-1].tolist() + [te[-2] + (te[-2] - te[-3])]
        for i, ph in enumerate(prow):
            for r in range(3):
                ax = axes[i, r]
                row = th[3 * ph + r]
                if row.sum() <= 0:
                    plot.no_data(ax, "no contacts")
                else:
                    am = float((row * mid).sum() / row.sum())
                    ax.stairs(row / row.sum(), stair_edges, fill=True, color="C3", alpha=0.45,
                              label=f"attached (mean {am:.3f})")
                    if drawn.sum() > 0:
                        ax.stairs(drawn / drawn.sum(), stair_edges, color="k", lw=1.0, ls=":",
                                  label=f"drawn from g (mean {dm:.3f})")
                    pm_mean = None
                    if predicted is not None and predicted[1][3 * ph + r].sum() > 0:
                        prow_p = predicted[1][3 * ph + r]
                        pm_mean = float((prow_p * mid).sum() / prow_p.sum())
                        ax.stairs(prow_p / prow_p.sum(), stair_edges, color="C0", lw=1.4,
                                  label=f"{ref} prediction (mean {pm_mean:.3f})")
                        fit = [f for f in fits if f["statistic"] == 2 and int(f["phase"]) == ph and int(f["region"]) == r]
                        if fit:
                            f = fit[0]
                            tag = f"KS {f['ks_distance']:.4f}, p {f['p_value']:.2g}" + ("" if f["tested"] else " (not tested)")
                            ax.text(0.02, 0.95, tag, transform=ax.transAxes, fontsize=8, va="top")
                    ax.set_xlim(0, max(2.0, 1 + 4 * width))
                    ax.legend(fontsize=8, loc="upper right")
                    if ph > 0 and width > 0:
                        rows.append(effect_row(f"threshold disorder w = {width:g} (the front keeps the strong contacts)",
                                               f"{res.scene}: surviving thresholds, {PHASES[ph]}, {REGIONS[r]}",
                                               f"drawn mean {dm:.4f}", f"attached mean {am:.4f}", f"{am / dm - 1:+.2%}",
                                               "thresholds of the attached contacts against those drawn from g"
                                               + ("" if pm_mean is None else f" ({ref} predicts {pm_mean / dm - 1:+.2%})"),
                                               source))
                ax.set_title(f"{PHASES[ph]}, {REGIONS[r]}", fontsize=9)
                ax.set_xlabel("threshold s")
        if not prow:
            plot.no_data(axes[0, 0], "no threshold statistics")
        note = "" if width > 0 else "   (w = 0: every threshold is 1)"
        what = "at the snapshots both models share a phase" if predicted is not None else "all contact snapshots"
        fig.suptitle(res.title(f"thresholds of the attached contacts vs drawn and predicted ({what}){note}", fig),
                     fontsize=9)
        save(fig, outdir, f"{res.scene}_thresholds.png", figs)
    # the goodness of fit: a limit that must hold when the prediction is from the ensemble's own N -> infinity
    # limit at its w (mean_field, or the continuum at w = 0), each row at the family false-alarm rate
    # CONTACTS_FAMILY_ALPHA (Bonferroni over the scene's tested rows, docs/contacts.md §3); else an effect of w
    n = res.param("discrete", "contacts_per_site", "?")
    tested = [f for f in fits if f.get("tested")]
    alpha_row = CONTACTS_FAMILY_ALPHA / max(1, len(tested))
    for f in tested:
        stat = ("lifetimes", "ages", "thresholds")[int(f["statistic"])]
        ph, r = PHASES[int(f["phase"])], REGIONS[int(f["region"])]
        rel = f["measured_total"] / f["predicted_total"] - 1 if f["predicted_total"] > 0 else math.nan
        fit = (f"KS distance {f['ks_distance']:.4f}; X2 {f['chi2']:.1f}/{f['dof']:.0f}, p = {f['p_value']:.2g} "
               f"(m = {f['thinned_size']:.0f}); totals {rel:+.2%}")
        what = f"{res.scene}: contact {stat}, {ph}, {r} (agent N={n})"
        if ref == "mean_field" or w == 0:
            rows.append(limit_row(f"agent contact statistics = renewal prediction from {ref} at w = {fmt_w(w)}", what,
                                  ref, f"{f['predicted_total']:.4g} predicted", f"{f['measured_total']:.4g} measured",
                                  fit, f"p >= {alpha_row:.2g} (family {CONTACTS_FAMILY_ALPHA:g}, {len(tested)} rows)",
                                  verdict_of(f["p_value"] >= alpha_row), source, fmt_w(w),
                                  score=alpha_row / f["p_value"] if f["p_value"] > 0 else math.inf))
        else:
            rows.append(effect_row(f"threshold disorder w = {fmt_w(w)} (agent vs the continuum's prediction, w = 0)",
                                   what, f"continuum {f['predicted_total']:.4g}", f"agent {f['measured_total']:.4g}",
                                   f"{rel:+.2%}", fit + "; no mean_field in the file: not a test", source))
    return figs, rows


# --------------------------------------------------------------------------------------------
# the strip's body (docs/output.md /<model>/bulk/): u, tau_xz, tau_yz over (x, y) around t^

BULK_FIELDS = (("u", "displacement u", "viridis"), ("tau_xz", "shear stress tau_xz", "RdBu_r"),
               ("tau_yz", "shear stress tau_yz", "RdBu_r"))


def _bulk_group(res, model):
    """/<model>/bulk when it holds snapshots of every field (a strip run with output.bulk_dt > 0), else None."""
    g = res.group(model)
    if "bulk" not in g or not isinstance(g["bulk"], h5py.Group):
        return None
    b = g["bulk"]
    names = ("t", "x", "y") + tuple(f for f, _, _ in BULK_FIELDS)
    if not all(k in b and isinstance(b[k], h5py.Dataset) for k in names) or b["t"].shape[:1] in ((), (0,)):
        return None
    shape = (b["t"].shape[0], b["y"].shape[0], b["x"].shape[0])
    if any(b[f].shape != shape for f, _, _ in BULK_FIELDS):  # not the layout of docs/output.md: not pictured
        print(f"report.py: warning: {res.path}: /{model}/bulk fields are not [t, y, x] = {shape}; no pictures",
              file=sys.stderr)
        return None
    return b


def bulk_times(t, t_hat, t_arrest):
    """Indices of ~3 bulk snapshots bracketing t^: the last before it, one in the transient (nearest the middle
    of [t^, t_arrest], else the first at or after t^) and the first after the arrest (else the next one); without
    a t^ in the snapshots' span, the first, middle and last snapshot."""
    t = np.asarray(t, dtype=float)
    n = len(t)
    if not (math.isfinite(t_hat) and t[0] < t_hat <= t[-1]):
        return sorted({0, n // 2, n - 1})
    before = int(np.where(t < t_hat)[0][-1])
    after = np.where(t >= t_hat)[0]
    if math.isfinite(t_arrest) and t_arrest > t_hat:
        during = int(after[np.argmin(np.abs(t[after] - 0.5 * (t_hat + t_arrest)))])
        later = np.where(t >= t_arrest)[0]
    else:
        during = int(after[0])
        later = after[1:]
    later = [int(k) for k in later if k > during]
    return sorted({before, during} | ({later[0]} if later else set()))


def strip_fields_section(res, outdir):
    """Pictures of the strip's body around t^: per model, u, tau_xz and tau_yz over (x, y) at ~3 bulk snapshots
    bracketing t^ (colour scales shared by every model and time of a field). Nothing for runs without bulk
    snapshots (the 1D scenes, a strip without output.bulk_dt)."""
    bulks = [(m, b) for m, b in ((m, _bulk_group(res, m)) for m in res.models) if b is not None]
    if not bulks:
        return []
    figs = []
    picks, limits = {}, {}
    for m, b in bulks:
        ev = plot.events(res.group(m))
        picks[m] = bulk_times(b["t"][()], ev.get("t_hat", math.nan), ev.get("t_arrest", math.nan))
    for f, _, cmap in BULK_FIELDS:
        vals = np.concatenate([np.asarray(b[f][picks[m]], dtype=float).ravel() for m, b in bulks])
        vals = vals[np.isfinite(vals)]
        if cmap == "viridis":
            limits[f] = (float(vals.min()), float(vals.max())) if vals.size else (0.0, 1.0)
        else:  # symmetric about 0; the 99.5th percentile, so the loaded edge's corner does not set the scale
            a = float(np.percentile(np.abs(vals), 99.5)) if vals.size else 1.0
            limits[f] = (-a, a) if a > 0 else (-1.0, 1.0)
        if limits[f][0] == limits[f][1]:
            limits[f] = (limits[f][0] - 1.0, limits[f][1] + 1.0)
    for m, b in bulks:
        ev = plot.events(res.group(m))
        t_hat = ev.get("t_hat", math.nan)
        x, y, ts = b["x"][()], b["y"][()], b["t"][()]
        # the fronts live near the loaded edge: show x up to 1.5 x_arrest (all of it when there is no arrest)
        xa = ev.get("x_arrest", math.nan)
        xmax = float(min(x[-1], 1.5 * xa)) if math.isfinite(xa) and xa > 0 else float(x[-1])
        rows = picks[m]
        fig, axes = plt.subplots(len(rows), len(BULK_FIELDS), figsize=(16, 2.3 * len(rows) + 1.2), squeeze=False,
                                 constrained_layout=True)
        for j, (f, what, cmap) in enumerate(BULK_FIELDS):
            data = np.asarray(b[f][rows], dtype=float)
            for i, k in enumerate(rows):
                ax = axes[i, j]
                pc = ax.pcolormesh(x, y, data[i], shading="nearest", cmap=cmap, vmin=limits[f][0], vmax=limits[f][1],
                                   rasterized=True)
                ax.set_xlim(0, xmax)
                ax.set_ylim(y[0], y[-1])
                rel = f", t - t^ = {ts[k] - t_hat:+.3g}" if math.isfinite(t_hat) else ""
                ax.set_title(f"{what}, t = {ts[k]:.4g}{rel}", fontsize=8)
                ax.set_ylabel("y (interface at 0)")
                if i == len(rows) - 1:
                    ax.set_xlabel("x (loaded edge at 0)" if res.loading() == "edge" else "x")
            fig.colorbar(pc, ax=axes[:, j], label=f, shrink=0.9)
        when = f"around t^ = {t_hat:.4g}" if math.isfinite(t_hat) else "at the first, middle and last bulk snapshot (no t^)"
        fig.suptitle(res.title(f"the strip's body, {m} model: u, tau_xz, tau_yz over (x, y) {when}; x <= {xmax:.4g} of "
                               f"{x[-1]:.4g} shown, decimated grid of {len(x)} x {len(y)} nodes", fig), fontsize=9)
        save(fig, outdir, f"{res.scene}_strip_fields_{m}.png", figs)
    return figs


class Context:
    """What every report task needs: the results directory, the figure directory and the study files (the fronts
    sections draw the time-dependent points of the front studies)."""

    def __init__(self, root, figdir, studies):
        self.root, self.figdir = root, figdir
        self.front_studies = [p for p in studies if study_kind(p) in FRONT_STUDY_KINDS]


# What a damaged file raises when it is opened or read: h5py's OSError (empty, truncated, not HDF5), a KeyError for a
# group or attribute it lacks. Such a file is listed under "could not read" with its path and the reason; the rest of
# the report is written (issue 36). Reading a study.h5's header (Study) may also raise a ValueError or TypeError for
# an attribute of the wrong shape or type (STUDY_UNREADABLE); the plots are not guarded by either (a plotting error
# is a bug, not a bad file).
UNREADABLE = (OSError, KeyError)
STUDY_UNREADABLE = UNREADABLE + (ValueError, TypeError)


def unreadable(path, e):
    """The "could not read" line of a file that raised `e`: the path and the reason (h5py's KeyError says what is
    missing, e.g. "Unable to open object (object 'study' doesn't exist)", quoted: unquoted here)."""
    why = str(e).strip('"') if isinstance(e, KeyError) else str(e)
    return f"{path}: {why or type(e).__name__}"


FRONT_STUDY_KINDS = ("front_spectrum", "steady_fronts")


def study_kind(path):
    """The kind of a study.h5, read without its tables ("" if the file cannot be read: its own section lists it)."""
    try:
        with h5py.File(path, "r") as f:
            return plot.as_str(f["study"].attrs["kind"])
    except STUDY_UNREADABLE:
        return ""


def report_jobs(tasks):
    """Worker processes for the report: SLIPFRONT_REPORT_JOBS if set, else the cores this process may use (at most
    the number of tasks, at least 1)."""
    env = os.environ.get("SLIPFRONT_REPORT_JOBS", "")
    try:
        jobs = int(env) if env else len(os.sched_getaffinity(0))
    except (ValueError, AttributeError):
        jobs = os.cpu_count() or 1
    return max(1, min(jobs, tasks))


def run_task(task):
    """(context, section function, path) -> (markdown lines, summary rows, unreadable files)."""
    context, section, path = task
    out = section(context, path)
    plt.close("all")
    return out


def figure_lines(figs, root):
    out = []
    for w in figs:
        out += [f"![{os.path.basename(w)}]({os.path.relpath(w, root)})", ""]
    return out


# --------------------------------------------------------------------------------------------
# the first screen (docs/studies.md "The report"): provenance, the answers to the paper's questions, one digest row
# per limit, the links to the main figures; the full tables and the sections follow

# The sections in the paper's order (Fig. 1, Fig. 2 left and right, the steady fronts, then the discrete model's
# limits, the contact level and the strip), by the name of a file's directory; a directory not listed comes after,
# in path order.
PAPER_ORDER = ("fig1", "friction_law", "velocity_step", "spring_block", "fig2_sweep", "homogeneous_front",
               "steady_front", "front_spectrum", "front_branch", "friction_law_N", "threshold_width",
               "threshold_width_law", "velocity_step_N", "spring_block_N", "front_speeds_N", "steady_front_N",
               "validity_friction", "validity_fig1", "disorder_limit_law", "disorder_limit_fig1", "contacts",
               "contacts_disorder", "fig1_strip", "homogeneous_strip", "strip_height", "fig2_strip",
               "strip_cmin_height", "strip_collapse_H16", "strip_collapse_H1000", "strip_collapse_H100000",
               "contacts_strip")

# Failing limit rows that are known findings, each documented (limit contains, observable contains, where): the
# first screen marks a failure "known (where)" when it matches, else "NEW".
KNOWN_FINDINGS = (
    ("agent contact statistics", "after arrest", "docs/contacts.md §5"),
    ("agent contact statistics", "contacts_strip: contact lifetimes, slow front, tip", "docs/contacts.md §5.1"),
)

# The main figures linked from the first screen: (label, the end of the figure's file name).
MAIN_FIGURES = (("Fig. 1", "/fig1_fronts.png"), ("Fig. 2 left", "/friction_law_steady_friction.png"),
                ("Fig. 2 right", "_fig2_sweep_fig2_right.png"), ("c_min(H)", "_cmin_vs_H.png"),
                ("growth rates under the normal-load coupling", "/inplane_growth_rates.png"))


def paper_order(root, path):
    """The sort key of a file's section: its directory's place in PAPER_ORDER, then its path."""
    rel = os.path.relpath(path, root)
    name = os.path.basename(os.path.dirname(rel))
    return (PAPER_ORDER.index(name) if name in PAPER_ORDER else len(PAPER_ORDER), rel)


def provenance(paths):
    """(commits, dates, {status: [file, ...]}) of the HDF5 files the report reads: their /meta git_commit, created_utc
    and status (a file without them: "unreadable"). From the files, not the clock: the report of one directory is
    the same whenever it is written."""
    commits, dates, status = set(), set(), {}
    for path in paths:
        try:
            with h5py.File(path, "r") as f:
                meta = f["meta"].attrs
                commits.add(plot.as_str(meta.get("git_commit", "unknown")))
                if "created_utc" in meta:
                    dates.add(plot.as_str(meta["created_utc"]))
                st = plot.as_str(meta.get("status", "unknown"))
        except UNREADABLE:
            st = "unreadable"
        status.setdefault(st, []).append(path)
    return commits, dates, status


def known_finding(row):
    for limit, observable, where in KNOWN_FINDINGS:
        if limit in row["limit"] and observable in row["observable"]:
            return where
    return ""


def limits_digest(rows):
    """One markdown row per limit: pass/fail counts, the worst row's statistic, the failures named and marked."""
    groups = {}
    for r in rows:
        if r["kind"] == "limit":
            groups.setdefault(r["limit"], []).append(r)
    out = ["| limit | pass | fail | worst (statistic against its threshold) | failures |", "| --- | --- | --- | --- | --- |"]
    for limit, rs in groups.items():
        fails = [r for r in rs if r["verdict"] == "FAIL"]
        scored = [r for r in rs if r.get("score") is not None and math.isfinite(r["score"])]
        worst = max(scored, key=lambda r: r["score"]) if scored else (fails[0] if fails else None)
        worst_text = (f"{worst['statistic']} ({worst['threshold']}; {worst['observable']})" if worst else
                      "every row within its threshold" if len(fails) == 0 and any(r["verdict"] == "pass" for r in rs)
                      else "no statistic")
        named = "; ".join(f"{r['observable']} — " + (f"known ({known_finding(r)})" if known_finding(r) else "**NEW**")
                          for r in fails) or "none"
        out.append(f"| {cell(limit)} | {sum(r['verdict'] == 'pass' for r in rs)} | {len(fails)} | {cell(worst_text)} "
                   f"| {cell(named)} |")
    return out


def first_screen(summary, files, figures, root):
    """The report's first lines: provenance, the answers, the limits' digest, the main figures."""
    commits, dates, status = provenance(files)
    done = len(status.get("complete", []))
    bad = "; ".join(f"{k}: " + ", ".join(f"`{os.path.relpath(p, root)}`" for p in v)
                    for k, v in sorted(status.items()) if k != "complete")
    commit = ", ".join(sorted(c.removesuffix("-dirty")[:12] + ("-dirty" if c.endswith("-dirty") else "")
                              for c in commits)) or "none"
    day = lambda d: d.replace("T", " ").replace("Z", " UTC")  # noqa: E731
    when = (f"computed {day(min(dates))}" + (f" .. {day(max(dates))}" if len(dates) > 1 else "")) if dates else \
        "no computation date in the files"
    out = ["# slipfront report", "",
           f"Commit {commit}; {when}; inputs: {done} of {len(files)} result files complete"
           + (f", the others {bad}" if bad else "") + ". Every path is relative to this file's directory; every "
           "quantity is dimensionless (docs/model.md §1).", ""]
    links = [f"[{label}]({os.path.relpath(w, root)})" for label, end in MAIN_FIGURES
             for w in [next((w for w in figures if w.endswith(end)), "")] if w]
    answers = sorted((r for r in summary if r["kind"] == "answer"), key=lambda r: r["order"])
    if answers:
        out += ["## Answers to the paper's questions", ""]
        for r in answers:
            word = "" if r["yes"] is None else ("Yes — " if r["yes"] else "No — ")
            fig = f" ([figure]({os.path.relpath(r['figure'], root)}))" if r["figure"] else ""
            out.append(f"- **{cell(r['question'])}** {word}{cell(r['short'])}.{fig}")
        out.append("")
    lim = [r for r in summary if r["kind"] == "limit"]
    out += ["## Limits that must hold: digest", "",
            f"{len(lim)} row{'' if len(lim) == 1 else 's'}: {sum(r['verdict'] == 'pass' for r in lim)} pass, "
            f"{sum(r['verdict'] == 'FAIL' for r in lim)} fail, {sum(r['verdict'] == 'n/a' for r in lim)} without a "
            "statistic (full table under Summary; a failure is a known finding, with its page, or new).", ""]
    out += limits_digest(summary) + [""]
    out += [("Figures: " + " · ".join(links) + ". " if links else "") + "Below: the summary's full tables, then "
            "one section per scene, steady-front file and study, in the paper's order.", ""]
    return out


def scene_section(ctx, path):
    """A results.h5: its plots, contact statistics and strip pictures, and its summary rows."""
    root, figdir = ctx.root, ctx.figdir
    lines, summary = [], []
    try:
        res = plot.Results(path)
    except OSError as e:
        return [], [], [f"{path}: {e}"]
    written = []
    with res.f:
        scene_dir = figure_dir(figdir, root, path) if res.models else None
        if res.models:
            plot.PLOTTERS[res.kind()](res, scene_dir, written, 110)
        source = os.path.relpath(path, root)
        summary += scene_rows(res, source) + scene_answers(res, written) + aging_rows(res, source)
        summary += base_effect_rows(res, root, source)
        lines += [f"## Scene `{res.scene}`", "", f"{res.description}", "",
                  f"File: `{os.path.relpath(path, root)}`, status {res.status}, models {', '.join(res.models)}.", ""]
        cfigs, sfigs = [], []
        if res.models:
            cfigs, crows = contacts_section(res, scene_dir, source)
            summary += crows
            sfigs = strip_fields_section(res, scene_dir)
    lines += figure_lines(written, root)
    if cfigs:
        lines += ["### Contact statistics", "",
                  "Mean contact age maps (the reference's age field, the agent's exact ages), lifetime and age "
                  "histograms by phase and region with the reference's prediction (the continuum's, or mean_field's "
                  "at the scene's w), and the thresholds of the attached contacts against the drawn ones and the "
                  "predicted ones (docs/contacts.md). Goodness of fit: "
                  "`/compare/contacts` (chi-square on a uniform subsample of m contacts; KS distance of the whole "
                  "population); one summary row per tested statistic and class.", ""]
        lines += figure_lines(cfigs, root)
    if sfigs:
        lines += ["### The strip's body", "",
                  "The displacement u and the shear stresses tau_xz, tau_yz of the strip over (x, y) (the interface at "
                  "y = 0) at bulk snapshots bracketing t^: before it, during the transient and after its arrest "
                  "(`/<model>/bulk/`, docs/output.md; colour scales shared by every model and time of a field, the "
                  "stresses' scales clipped at the 99.5th percentile of |tau|).", ""]
        lines += figure_lines(sfigs, root)
    return lines, summary, []


def fronts_section(ctx, path):
    """A fronts.h5 (slipfront fronts) with the time-dependent points of the front studies; a file that cannot be
    read is listed instead."""
    keep = []
    for p in ctx.front_studies:
        try:
            keep.append(Study(p))
        except STUDY_UNREADABLE:
            pass  # its own section lists it
    try:
        more, rows = fronts_file(path, ctx.root, ctx.figdir, keep)
    except UNREADABLE as e:
        return [], [], [unreadable(path, e)]
    finally:
        for st in keep:
            st.f.close()
    return more, rows, []


def cmin_table_lines(t):
    """Every height's c_min with its estimate, its mesh and its verdict on paths.rtol (docs/fronts.md §10.20), as a
    markdown table; a line counting the heights NOT met."""
    def verdict(v):
        return "met" if v == 1 else "**NOT met**" if v == 0 else "not judged"
    lines = ["| H | c_min ± estimate | relative | rows × intervals | rtol |", "| --- | --- | --- | --- | --- |"]
    for k in range(len(t["H"])):
        c, e = t["c_min"][k], t["c_min_error"][k]
        est = f"{c:.8g} ± {e:.2g}" if math.isfinite(e) else f"{c:.8g} (no estimate)"
        rel = f"{100 * e / c:.2g} %" if math.isfinite(e) else ""
        mesh = (f"{t['rows'][k]:.0f} × {t['intervals'][k]:.0f}" if math.isfinite(t["rows"][k]) else "")
        lines.append(f"| {t['H'][k]:.6g} | {est} | {rel} | {mesh} | {verdict(t['rtol_met'][k])} |")
    unmet = [f"{h:.4g}" for h, v in zip(t["H"], t["rtol_met"]) if v == 0]
    if unmet:
        lines += ["", f"**{len(unmet)} of {len(t['H'])} heights NOT met** their rtol (H = {', '.join(unmet)}): "
                  "the study's notes say why (budget, mesh limit, no convergence)."]
    return lines + [""]


def cmin_section(ctx, path):
    """A strip_cmin_height.csv: c_min(H) with its summary rows."""
    root = ctx.root
    figs, rows = strip_cmin_section(path, root, ctx.figdir)
    lines = ["## c_min(H) of the strip at fixed material", "",
             "The limiting front's speed c_min against the strip's height H (the study strip_cmin_height, "
             "docs/fronts.md §10.12): the 1D line, the paper's intermediate form and the Brener-Marchenko "
             "large-H form, the lengths l and l_kappa; below, the local exponent against 1/2 and the paper's "
             "exponents.", "", f"File: `{os.path.relpath(path, root)}`, {len(figs) and 'plotted' or 'no usable row'}.", ""]
    try:
        t = read_cmin_csv(path)
    except OSError:
        t = None  # strip_cmin_section has warned
    if t is not None:
        lines += cmin_table_lines(t)
    return lines + figure_lines(figs, root), rows, []


# --------------------------------------------------------------------------------------------
# the growth rates of homogeneous sliding on the in-plane strip under the normal-load coupling (`slipfront stability`:
# stability.h5 and growth_rates.csv beside it, docs/output.md; docs/model.md §12.6, §12.7)

GROWTH_CSV = "growth_rates.csv"
STABILITY_CHANNELS = ("uncoupled", "reattachment", "instantaneous", "regularised")


def stability_facts(path):
    """(the attributes of /stability, kH, {group: its attributes and datasets}) of a stability.h5."""
    with h5py.File(path, "r") as f:
        s = f["stability"]
        facts = attrs(s)
        kh = s["kH"][()]
        channels = {}
        for g in STABILITY_CHANNELS:
            if g in s:
                channels[g] = attrs(s[g])
                channels[g].update({k: s[g][k][()] for k in s[g]})
    return facts, kh, channels


def channel_verdict(c, kh, facts):
    """(grows, the verdict's text) of one channel, from its rates: stable when no fastest mode's Re s exceeds the
    eigensolver's round-off at its kH; else the largest rate, where, and whether it converged in the rows."""
    re, im, off = c["fastest_re"], c["fastest_im"], c["roundoff"]
    if len(re) == 0:
        return None, "no rates (the file is not complete)"
    k = int(np.argmax(re))
    w = lambda s_im: abs(s_im) * facts["height"] / facts["pressure_speed"]  # noqa: E731 (omega H/c_p)
    where = f"kH = {kh[k]:.3g}, omega H/c_p = {w(im[k]):.3g}"
    rows = ", ".join(f"{r:.0f}" for r in c["check_rows"])
    if not np.any(re > off):
        res = c["resolved_re"]
        j = int(np.argmax(res))
        return False, (f"homogeneous sliding stable (max Re s over kH = {kh[0]:.3g} .. {kh[-1]:.3g}: {re[k]:.2g} at "
                       f"{where}, within the eigensolver's round-off {off[k]:.2g}; least-damped resolved mode "
                       f"{res[j]:.3g} at kH = {kh[j]:.3g})")
    rates = ", ".join(f"{x:.3g}" for x in c["check_re"])
    freqs = ", ".join(f"{w(x):.3g}" for x in c["check_im"])
    rows_text = (f"on {rows} rows at kH = {c['check_kH']:.3g}: Re s {rates}, omega H/c_p {freqs}")
    tail = (f"converged in the rows ({rows_text})" if c["converged"] == 1 else
            f"ill-posed: the fastest mode moves with the rows ({rows_text})")
    return True, f"unstable, max rate {re[k]:.3g} at {where}; {tail}"


def stability_summary(facts, kh, channels, source, scene):
    """The verdict lines (one per channel) and one effect row per coupled channel against the uncoupled strip: the
    coupling's effect on the largest growth rate (a result, no limit: kept apart from the limits that must hold)."""
    lines, rows = [], []
    base = channels.get("uncoupled")
    b = float(np.max(base["fastest_re"])) if base is not None and len(base["fastest_re"]) else math.nan
    what = (f"p_0 = {facts['normal_load']:.3g}, m = {facts['exponent']:.3g}, coefficient m sigma_bar0/p_0 = "
            f"{facts['coupling_coefficient']:.3g}")
    for g in STABILITY_CHANNELS[1:]:
        if g not in channels:
            continue
        c = channels[g]
        grows, text = channel_verdict(c, kh, facts)
        name = {"reattachment": "re-attachment channel", "instantaneous": "instantaneous channel"}.get(
            g, f"regularised instantaneous channel, L = {c['relaxation_length']:.3g}")
        own = " (the scene's)" if c.get("scene") == 1 else ""
        lines.append(f"- **{name}{own}**: {text}.")
        if grows is None:
            continue
        top = float(np.max(c["fastest_re"]))
        rows.append(effect_row(f"normal-load coupling, {name} ({what})",
                               f"{scene}: largest growth rate Re s of homogeneous sliding at v0 = {facts['v0']:.3g} over "
                               f"kH = {kh[0]:.3g} .. {kh[-1]:.3g} ({facts['rows']:.0f} rows)",
                               f"uncoupled {b:.3g}", f"{top:.3g}", f"{top - b:+.3g}",
                               "stable (within round-off)" if not grows else
                               "unstable; converged in the rows" if c["converged"] == 1 else
                               "unstable; ill-posed: not converged in the rows", source))
    return lines, rows


def stability_section(ctx, path):
    """A stability.h5 (slipfront stability) and the growth_rates.csv beside it: the figure, one verdict per channel
    and the effect rows."""
    root = ctx.root
    try:
        with h5py.File(path, "r") as f:
            meta, scene = attrs(f["meta"]), plot.as_str(f["meta"].attrs.get("scene", ""))
        facts, kh, channels = stability_facts(path)
    except UNREADABLE as e:
        return [], [], [unreadable(path, e)]
    source = os.path.relpath(path, root)
    lines = [f"## Growth rates of homogeneous sliding under the normal-load coupling (`{scene}`)", "",
             "The linear stability of homogeneous sliding at v0 on the in-plane strip when the contacts feel p = "
             "-sigma_yy (docs/model.md §12.6, §12.7; `slipfront stability`, continuum::leading_growth_rate): Re s "
             "against kH for the uncoupled strip and each channel, the least-damped resolved mode (|omega| H/c_p <= 4) "
             "and the fastest mode of all; each channel's fastest mode again on 2 and 4 times the rows.", "",
             f"File: `{source}`, status {meta.get('status', '?')}; v0 = {facts['v0']:.4g} (v_m = {facts['v_m']:.4g}), "
             f"H = {facts['height']:.4g}, c_s = {facts['shear_speed']:.4g}, c_p = {facts['pressure_speed']:.4g}, "
             f"p_0 = {facts['normal_load']:.4g}, m = {facts['exponent']:.3g}, m sigma_bar0/p_0 = "
             f"{facts['coupling_coefficient']:.3g}, {facts['rows']:.0f} rows.", ""]
    verdicts, rows = stability_summary(facts, kh, channels, source, scene)
    lines += verdicts + [""]
    csv_path = os.path.join(os.path.dirname(path), GROWTH_CSV)
    figs = []
    if os.path.exists(csv_path):
        own = next((c["label"] for c in channels.values() if c.get("scene") == 1), None)
        title = (f"{scene}: in-plane strip H = {facts['height']:.3g}, homogeneous sliding v0 = {facts['v0']:.3g}, "
                 f"p_0 = {facts['normal_load']:.3g}: growth rates under the coupling")
        figs = plot.growth_rates_figure(csv_path, figure_dir(ctx.figdir, root, path), 110, title,
                                        f"{facts['rows']:.0f} rows", own)
    else:
        lines += [f"No `{GROWTH_CSV}` beside it (written only when the computation completes): no figure.", ""]
    return lines + figure_lines(figs, root), rows, []


def scalar_lines(st):
    """A study's scalars as bullets: value, 95 % interval and definition (a scalar without one: no colon); the
    scalars without a value in this run (NaN: e.g. a fit with too few points) named in one line."""
    lines, none = [], []
    for k, v in sorted(st.scalars.items()):
        if "_ci_" in k or k.endswith("_points"):
            continue
        if not math.isfinite(v):
            none.append(f"`{k}`")
            continue
        lo, hi = st.scalars.get(k + "_ci_low"), st.scalars.get(k + "_ci_high")
        ci = f" (95% CI {lo:.3g} .. {hi:.3g})" if lo is not None and math.isfinite(lo) else ""
        what = st.definitions.get(k, "").strip()
        lines.append(f"- `{k}` = {v:.4g}{ci}" + (f": {what}" if what else ""))
    if none:
        lines.append(f"- without a value in this run (too few points or no event): {', '.join(none)}")
    return lines


def study_section(ctx, path):
    """A study.h5: its plots per kind, scalars with their intervals, notes and summary rows."""
    root = ctx.root
    try:
        st = Study(path)
    except STUDY_UNREADABLE as e:
        return [], [], [unreadable(path, e)]
    try:
        st.stem = f"{figure_key(root, path)}_{st.name}"
        st.source = os.path.relpath(path, root)
        figs, rows = study_plots(st.kind)(st, ctx.figdir)
        lines = [f"## Study `{st.name}` ({st.kind})", "", st.description, "",
                 f"{len(st.runs)} runs, {st.wall:.1f} s wall, status {st.status}.", ""]
        lines += scalar_lines(st)
        for n in st.notes:
            lines.append(f"- note: {n}")
        lines.append("")
        lines += figure_lines(figs, root)
    finally:
        st.f.close()
    return lines, rows, []


def said_once(lines):
    """The sections with a long paragraph that an earlier section said already (the contact statistics' and the
    strip body's explanations, one per scene with them) replaced by a pointer to the first."""
    seen, out = set(), []
    for line in lines:
        if len(line) > 200 and not line.startswith(("|", "!", "- ")):
            if line in seen:
                out.append("As in the first section above with this heading.")
                continue
            seen.add(line)
        out.append(line)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description="Plots and report.md for the slipfront results under DIR.")
    ap.add_argument("dir")
    args = ap.parse_args(argv)
    root = os.path.abspath(args.dir)
    figdir = os.path.join(root, "figures")
    os.makedirs(figdir, exist_ok=True)
    scenes, studies, fronts, cmins, stabilities = [], [], [], [], []
    for d, subdirs, files in os.walk(root):
        subdirs[:] = sorted(s for s in subdirs if s not in ("runs", "figures"))  # study runs are summarised
        if "results.h5" in files:
            scenes.append(os.path.join(d, "results.h5"))
        if "study.h5" in files:
            studies.append(os.path.join(d, "study.h5"))
        if "fronts.h5" in files:
            fronts.append(os.path.join(d, "fronts.h5"))
        if CMIN_CSV in files:
            cmins.append(os.path.join(d, CMIN_CSV))
        if "stability.h5" in files:
            stabilities.append(os.path.join(d, "stability.h5"))
    # One task per file, run in parallel (fork: matplotlib's Agg backend and h5py are opened in the workers only);
    # their sections are joined in this fixed order, so the report does not depend on the number of workers.
    kinds = {scene_section: 0, fronts_section: 1, cmin_section: 2, study_section: 3, stability_section: 4}
    tasks = sorted([(scene_section, path) for path in scenes] + [(fronts_section, path) for path in fronts]
                   + [(cmin_section, path) for path in cmins] + [(study_section, path) for path in studies]
                   + [(stability_section, path) for path in stabilities],
                   key=lambda t: (paper_order(root, t[1]), kinds[t[0]]))
    context = Context(root, figdir, sorted(studies))
    jobs = report_jobs(len(tasks))
    if jobs > 1:
        with concurrent.futures.ProcessPoolExecutor(max_workers=jobs,
                                                    mp_context=multiprocessing.get_context("fork")) as pool:
            parts = list(pool.map(run_task, [(context, f, p) for f, p in tasks]))
    else:
        parts = [run_task((context, f, p)) for f, p in tasks]
    lines, summary, missing = [], [], []
    for more, rows, miss in parts:
        lines += more
        summary += rows
        missing += miss
    figures = [os.path.join(root, m) for m in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", "\n".join(lines))]
    lines = (first_screen(summary, sorted(scenes + studies + fronts + stabilities), figures, root) + summary_tables(summary)
             + said_once(lines))
    for m in missing:
        lines.append(f"- could not read {m}")
    summary_csv(root, summary)
    out = os.path.join(root, "report.md")
    write_report(out, "\n".join(lines) + "\n")
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
