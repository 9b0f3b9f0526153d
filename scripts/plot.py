#!/usr/bin/python3
"""Plot a slipfront results file (layout: docs/output.md, docs/model.md §5).

    /usr/bin/python3 scripts/plot.py out/fig1/results.h5 [--outdir DIR]

Writes PNGs (default: next to the results file) and prints the path of each one:
  1D scenes (edge, homogeneous loading)  <scene>_fronts.png   drive force F(t) (max v for homogeneous
                                                               loading) and space-time maps of A,
                                                               sigma_bar, |v| (and the mean contact age
                                                               when the file has snapshots/age) with the
                                                               front tip, t*, t^
                                         <scene>_tip.png      tip trajectories and measured events
                                         <scene>_sigma_yy.png the in-plane strip's interface normal
                                                               stress: sigma_yy(x, 0) at the snapshots
                                                               nearest the events, its space-time maps
                                         <scene>_sequence.png the slip events (output.sequence): arrest
                                                               position and speed of each against its start
  imposed-rate sweep                     <scene>_steady_friction.png   sigma(v), A(v) against closed forms
  imposed-rate history                   <scene>_history.png  sigma(t), A(t), v(t), zooms on the jumps
                                         <scene>_peaks.png    with holds (v = 0): static peak against hold time
  spring block                           <scene>_stick_slip.png     F(t) with peaks and residuals
Every model group present (continuum, discrete, ...) is drawn: maps side by side, curves overlaid.
Missing groups, datasets or events (NaN) are skipped, not fatal.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

try:
    import tomllib  # Python >= 3.11 (Debian 12)
except ImportError:  # pragma: no cover
    tomllib = None

NOT_MODELS = {"meta", "config", "compare"}
MODEL_ORDER = ["continuum", "discrete"]
# The deterministic continuum is drawn on top of the (noisy) discrete curves it is compared with.
MODEL_STYLE = {"continuum": dict(color="C0", marker="o", zorder=3), "discrete": dict(color="C3", marker="s", zorder=2)}
V_LOG_DECADES = 4  # |v| maps: log colour scale over this many decades below the maximum


# --------------------------------------------------------------------------------------------
# reading


def as_str(value) -> str:
    """A string read from a file as text that can be written anywhere: bytes that are not UTF-8 become U+FFFD.
    h5py hands them over as bytes, or (variable-length UTF-8 strings) as str with surrogate escapes, which no
    UTF-8 file or figure can take."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, str):
        return value.encode("utf-8", "surrogateescape").decode("utf-8", "replace")
    if isinstance(value, np.ndarray) and value.shape == ():
        return as_str(value[()])
    return str(value)


def as_float(value) -> float:
    try:
        return float(np.asarray(value).reshape(-1)[0])
    except (TypeError, ValueError, IndexError):
        return math.nan


def finite(value) -> bool:
    return value is not None and isinstance(value, (int, float, np.floating)) and math.isfinite(value)


def dataset(group, path):
    """The dataset at `path` as a float array, or None if absent or unreadable."""
    if group is None or path not in group or not isinstance(group[path], h5py.Dataset):
        return None
    try:
        return np.asarray(group[path][()], dtype=float)
    except (TypeError, ValueError):
        return None


def read_config(f) -> dict:
    if "config" not in f or "toml" not in f["config"].attrs or tomllib is None:
        return {}
    try:
        return tomllib.loads(as_str(f["config"].attrs["toml"]))
    except Exception as e:  # a plot should not die on a config it cannot parse
        print(f"plot.py: warning: cannot parse /config toml: {e}", file=sys.stderr)
        return {}


def model_names(f) -> list[str]:
    keys = [k for k in f.keys() if k not in NOT_MODELS and isinstance(f[k], h5py.Group)]
    keys = [k for k in keys if any(s in f[k] for s in ("x", "series", "snapshots", "friction_law", "events"))]
    return [m for m in MODEL_ORDER if m in keys] + sorted(k for k in keys if k not in MODEL_ORDER)


def events(group) -> dict:
    if group is None or "events" not in group:
        return {}
    return {k: as_float(v) for k, v in group["events"].attrs.items()}


def style(model: str, i: int) -> dict:
    return MODEL_STYLE.get(model, dict(color=f"C{(i + 2) % 10}", marker="^", zorder=2))


class Results:
    def __init__(self, path: str):
        self.path = path
        self.f = h5py.File(path, "r")
        self.cfg = read_config(self.f)
        meta = self.f["meta"].attrs if "meta" in self.f else {}
        self.commit = as_str(meta["git_commit"]) if "git_commit" in meta else "unknown"
        self.status = as_str(meta["status"]) if "status" in meta else "unknown"
        stem = os.path.splitext(os.path.basename(path))[0]
        if stem == "results":  # out/<scene>/results.h5
            stem = os.path.basename(os.path.dirname(os.path.abspath(path))) or stem
        self.scene = str(self.cfg.get("scene") or (as_str(meta["scene"]) if "scene" in meta else stem))
        self.description = self.cfg.get("description", "")
        self.models = model_names(self.f)

    def group(self, model):
        return self.f[model]

    def param(self, section, key, default=None):
        return self.cfg.get(section, {}).get(key, default)

    def loading(self) -> str | None:
        return self.param("drive", "loading")

    def kind(self) -> str:
        loading = self.loading()
        has = lambda path: any(path in self.f[m] for m in self.models)  # noqa: E731
        if loading in ("edge", "homogeneous"):
            return "1d"
        if loading == "imposed_rate":
            return "sweep" if has("friction_law") or self.param("drive", "points") else "history"
        if loading == "spring_block":
            return "spring_block"
        # no usable config: infer from what is there
        if has("friction_law"):
            return "sweep"
        if has("series/tip_x") or has("snapshots/A"):
            return "1d"
        if has("cycles") or has("series/slip"):
            return "spring_block"
        if has("series/sigma"):
            return "history"
        return "unknown"

    def title(self, what: str, fig=None) -> str:
        """Scene, what the figure shows, commit and status; wrapped to the width of `fig`."""
        commit = self.commit
        if len(commit) > 20:  # a full hash: abbreviate, keep the -dirty mark
            commit = commit[:12] + ("-dirty" if commit.endswith("-dirty") else "")
        line = f"{self.scene}: {what}   [commit {commit}, status {self.status}]"
        bad = []
        for m in self.models:
            st = self.group(m).attrs.get("status")
            if st is not None and as_str(st) != "complete":
                bad.append(f"{m}: {as_str(st)}")
        if bad:
            line += "   (" + "; ".join(bad) + ")"
        text = line + (f"\n{self.description}" if self.description else "")
        if fig is None:
            return text
        width = max(40, int(fig.get_figwidth() * 11))
        return "\n".join(textwrap.fill(part, width) for part in text.split("\n"))


# --------------------------------------------------------------------------------------------
# closed forms (docs/model.md §1)


def interface_params(res: Results):
    a, k, e = (res.param("interface", n) for n in ("alpha", "kappa", "eta"))
    return (float(a), float(k), float(e)) if None not in (a, k, e) else None


def sigma_ss(v, alpha, kappa, eta):
    v = np.abs(np.asarray(v, dtype=float))
    return alpha / (1.0 + kappa * v) + eta * v


def area_ss(v, kappa):
    return 1.0 / (1.0 + kappa * np.abs(np.asarray(v, dtype=float)))


def aging_params(res: Results):
    """(b, tau_a) of a scene with contact aging (interface.aging_b > 0, docs/model.md §11), else None."""
    b, tau = res.param("interface", "aging_b", 0.0), res.param("interface", "aging_tau", 1.0)
    return (float(b), float(tau)) if b and float(b) > 0 else None


def exp_e1(x):
    """e^x E_1(x) for x > 0 (docs/model.md §11.1): the power series of E_1 below 1, 64-point Gauss-Laguerre of
    the integral of e^-t/(x + t) above (both to ~1e-8 at x = 1)."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    out = np.empty_like(x)
    small = x < 1.0
    k = np.arange(1, 40)
    kk = k * np.array([math.factorial(int(i)) for i in k], dtype=float)
    xs = x[small]
    out[small] = np.exp(xs) * (-np.euler_gamma - np.log(xs) - np.sum((-xs[:, None]) ** k / kk, axis=1))
    t, w = np.polynomial.laguerre.laggauss(64)
    out[~small] = np.sum(w / (x[~small, None] + t), axis=1)
    return out


def aged_sigma_ss(v, alpha, kappa, eta, b, tau, closure=False):
    """The steady law with contact aging (docs/model.md §11.1, §11.4): the age-structured balance's
    alpha (1 + b e^x E_1(x))/(1 + kappa v) + eta v, x = kappa v tau_a (mean_field and the ensemble), or the
    one-variable closure's alpha (1 + b ln(1 + 1/x))/(1 + kappa v) + eta v (the continuum law with aging)."""
    v = np.abs(np.asarray(v, dtype=float))
    x = kappa * v * tau
    aged = np.log1p(1.0 / x) if closure else exp_e1(x)
    return alpha * (1.0 + b * aged) / (1.0 + kappa * v) + eta * v


def aged_minimum_of_friction(p, ag):
    """v_m and sigma_c^d of the age-structured balance's steady law (docs/model.md §11.1), on a fine grid (relative
    spacing 1e-4 in v around the minimum: sigma_c^d to ~1e-9)."""
    vv = np.geomspace(1e-4, 1e4, 20001)
    s = aged_sigma_ss(vv, *p, *ag)
    k = int(np.argmin(s))
    if not 0 < k < len(vv) - 1:
        return math.nan, math.nan
    vv = np.geomspace(vv[k - 1], vv[k + 1], 2001)
    s = aged_sigma_ss(vv, *p, *ag)
    k = int(np.argmin(s))
    return float(vv[k]), float(s[k])


def minimum_of_friction(alpha, kappa, eta):
    """v_m and sigma_c^d of docs/model.md §1 (NaN if the law has no interior minimum)."""
    if kappa <= 0 or eta <= 0 or alpha * kappa / eta <= 1:
        return math.nan, math.nan
    return (math.sqrt(alpha * kappa / eta) - 1) / kappa, 2 * math.sqrt(alpha * eta / kappa) - eta / kappa


def t_star_formula(res: Results):
    """First yield at the edge, docs/model.md §1: t* = (K + sqrt(alpha mu)) / (alpha K v_d)."""
    p = interface_params(res)
    K, vd, mu = res.param("drive", "K"), res.param("drive", "v_d"), res.param("bulk", "mu")
    if p is None or None in (K, vd, mu) or K <= 0 or vd <= 0:
        return math.nan
    alpha = p[0]
    return (K + math.sqrt(alpha * mu)) / (alpha * K * vd)


# --------------------------------------------------------------------------------------------
# helpers


def mark_times(ax, ev, vertical=True, label=True, color=None, model=""):
    """t* (dotted) and t^ (dashed) as lines: vertical on time-series axes, horizontal on space-time
    maps. `color`/`model`: one model's events on axes shared by several models."""
    for key, name, ls, col in (("t_star", "t*", ":", "tab:cyan"), ("t_hat", "t^", "--", "tab:red")):
        t = ev.get(key, math.nan)
        if finite(t):
            text = f"{model + ': ' if model else ''}{name} = {t:.4g}"
            kw = dict(ls=ls, color=color or col, lw=1.2, label=text if label else None)
            (ax.axvline if vertical else ax.axhline)(t, **kw)


def no_data(ax, text="no data"):
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, color="0.4")
    ax.set_xticks([])
    ax.set_yticks([])


UNITS_NOTE = "all quantities dimensionless (docs/model.md §1)"


def units_note(fig):
    """The one line that says the figure's quantities are dimensionless, below the figure's bottom right corner (the
    saved image is widened to hold it: savefig(bbox_inches="tight"), so it covers no label)."""
    fig.text(0.998, -0.002, UNITS_NOTE, ha="right", va="top", fontsize=8, color="0.35")


def save(fig, outdir, name, written, dpi):
    path = os.path.join(outdir, name)
    units_note(fig)
    fig.savefig(path, dpi=dpi, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)
    written.append(path)


def fmt_event(ev, key, unit=""):
    v = ev.get(key, math.nan)
    return f"{key} = {v:.4g}{unit}" if finite(v) else f"{key} = -"


# --------------------------------------------------------------------------------------------
# 1D scenes: the Fig. 1 panels


def plot_1d(res: Results, outdir, written, dpi):
    models = res.models
    loading = res.loading()
    use_force = loading == "edge"
    if loading is None:  # homogeneous loading has no drive spring: F(t) is 0
        F = [dataset(res.group(m), "series/drive_force") for m in models]
        use_force = any(a is not None and np.any(a != 0) for a in F)

    # shared colour ranges so side-by-side maps compare
    def snap(m, k):
        return dataset(res.group(m), f"snapshots/{k}")

    sb_all = [a for a in (snap(m, "sigma_bar") for m in models) if a is not None and a.size]
    sb_lim = (0.0, 1.0)
    if sb_all:
        sb_lim = (np.nanmin([np.nanmin(a) for a in sb_all]), np.nanmax([np.nanmax(a) for a in sb_all]))
    v_all = [np.abs(a) for a in (snap(m, "v") for m in models) if a is not None and a.size]
    v_max = np.nanmax([np.nanmax(a) for a in v_all]) if v_all else 1.0
    v_max = v_max if finite(v_max) and v_max > 0 else 1.0
    v_min = v_max * 10.0 ** (-V_LOG_DECADES)

    # the mean contact age (docs/model.md §7), when the file has it: one more row, log colour scale
    age_all = [a for a in (snap(m, "age") for m in models) if a is not None and a.size]
    age_pos = [a[np.isfinite(a) & (a > 0)] for a in age_all]
    age_pos = [a for a in age_pos if a.size]
    has_age = bool(age_pos)
    age_max = max(float(np.max(a)) for a in age_pos) if has_age else 1.0
    age_min = max(min(float(np.min(a)) for a in age_pos), age_max * 1e-4) if has_age else 1e-4

    ncol = len(models)
    nrow = 5 if has_age else 4
    fig, axes = plt.subplots(nrow, ncol, figsize=(6.4 * ncol, 15 + 3.5 * (nrow - 4)), squeeze=False,
                             gridspec_kw=dict(height_ratios=[0.8] + [1] * (nrow - 1)), constrained_layout=True)
    t_formula = t_star_formula(res) if loading == "edge" else math.nan
    for j, m in enumerate(models):
        g = res.group(m)
        ev = events(g)
        t = dataset(g, "series/t")
        # row 0: drive force (edge) or max slip rate (homogeneous)
        ax = axes[0, j]
        key = "drive_force" if use_force else "max_v"
        y = dataset(g, f"series/{key}")
        if t is not None and y is not None and len(t) == len(y) and len(t):
            ax.plot(t, y, color="k", lw=1)
            pos = y[np.isfinite(y) & (y > 0)]
            if key == "max_v" and pos.size and pos.max() > 30 * pos.min():
                ax.set_yscale("log")
            ax.set_xlabel("t")
            ax.set_ylabel("F(t) = K (v_d t - u(0,t))" if key == "drive_force" else "max_x v")
            mark_times(ax, ev)
            if finite(t_formula):
                ax.axvline(t_formula, color="0.5", lw=0.8, ls="-.", label=f"t* formula = {t_formula:.4g}")
            if ax.get_legend_handles_labels()[0]:  # homogeneous loading: no event marked, nothing to list
                ax.legend(fontsize=8, loc="best")
        else:
            no_data(ax, f"no series/{key}")
        ax.set_title(f"{m}: {'drive force' if key == 'drive_force' else 'max slip rate'}")

        # rows 1-3: space-time maps
        x = dataset(g, "x")
        ts = dataset(g, "snapshots/t")
        tip_t, tip, tip_alt = t, dataset(g, "series/tip_x"), dataset(g, "series/tip_x_alt")
        A_tip = res.param("measure", "A_tip", 0.5)
        A_alt = res.param("measure", "A_tip_alt", 0.9)
        panels = (("A", "A (contact area)", "viridis", dict(vmin=0.0, vmax=1.0)),
                  ("sigma_bar", "sigma_bar", "magma", dict(vmin=sb_lim[0], vmax=sb_lim[1])),
                  ("v", f"|v| (log, clipped below {v_min:.0e})", "inferno",
                   dict(norm=LogNorm(vmin=v_min, vmax=v_max))))
        if has_age:
            panels += (("age", "mean contact age (log)", "cividis", dict(norm=LogNorm(vmin=age_min, vmax=age_max))),)
        for i, (name, label, cmap, kw) in enumerate(panels, start=1):
            ax = axes[i, j]
            field = snap(m, name)
            if x is None or ts is None or field is None or field.shape != (len(ts), len(x)) or not len(ts):
                no_data(ax, f"no snapshots/{name}")
                ax.set_title(f"{m}: {name}")
                continue
            if name == "v":
                field = np.clip(np.abs(field), v_min, v_max)
            if name == "age":
                field = np.clip(field, age_min, age_max)
            pc = ax.pcolormesh(x, ts, field, shading="nearest", cmap=cmap, rasterized=True, **kw)
            fig.colorbar(pc, ax=ax, label=label, pad=0.01)
            if tip_t is not None:
                keep = tip_t <= ts[-1] + 1e-12
                if tip is not None and len(tip) == len(tip_t):
                    ax.plot(tip[keep], tip_t[keep], color="w", lw=1.2, label=f"tip (A < {A_tip:g})")
                if tip_alt is not None and len(tip_alt) == len(tip_t):
                    ax.plot(tip_alt[keep], tip_t[keep], color="w", lw=1.0, ls="--", label=f"tip (A < {A_alt:g})")
            mark_times(ax, ev, vertical=False)
            if finite(ev.get("x_arrest")) and finite(ev.get("t_arrest")):
                ax.plot([ev["x_arrest"]], [ev["t_arrest"]], marker="*", ms=12, color="tab:green",
                        mec="k", ls="none", label=f"arrest x = {ev['x_arrest']:.4g}")
            ax.set_xlim(x[0], x[-1])
            ax.set_ylim(ts[0], ts[-1])
            ax.set_xlabel("x")
            ax.set_ylabel("t")
            ax.set_title(f"{m}: {name}")
            if i == 1 and ax.get_legend_handles_labels()[0]:  # (no tip, no arrest: no legend)
                leg = ax.legend(fontsize=8, loc="upper right", framealpha=0.6)
                leg.get_frame().set_facecolor("0.8")
    fig.suptitle(res.title("fronts (x horizontal, t upward)", fig), fontsize=11)
    save(fig, outdir, f"{res.scene}_fronts.png", written, dpi)

    # tip trajectories, all models on one axis, with the measured events
    fig, ax = plt.subplots(figsize=(9, 6), constrained_layout=True)
    lines = []
    for j, m in enumerate(models):
        g = res.group(m)
        st = style(m, j)
        t, tip, tip_alt = dataset(g, "series/t"), dataset(g, "series/tip_x"), dataset(g, "series/tip_x_alt")
        if t is None:
            continue
        if tip is not None and len(tip) == len(t):
            ax.plot(t, tip, color=st["color"], lw=1.3, zorder=st["zorder"],
                    label=f"{m}: tip, A < {res.param('measure', 'A_tip', 0.5):g}")
        if tip_alt is not None and len(tip_alt) == len(t):
            ax.plot(t, tip_alt, color=st["color"], lw=1.0, ls="--", zorder=st["zorder"],
                    label=f"{m}: tip, A < {res.param('measure', 'A_tip_alt', 0.9):g}")
        ev = events(g)
        mark_times(ax, ev, color=st["color"], model=m if len(models) > 1 else "")
        keys = ("t_star", "t_hat", "c_slow", "c_transient", "c_transient_peak", "x_arrest", "t_arrest", "c_front")
        lines.append(f"{m}: " + ", ".join(fmt_event(ev, k) for k in keys if k in ev))
        if any(k + "_alt" in ev for k in keys):
            lines.append(f"{m} (alt front): " + ", ".join(fmt_event({k: ev.get(k + '_alt')}, k) for k in keys
                                                         if k + "_alt" in ev))
    if finite(t_formula):
        ax.axvline(t_formula, color="0.5", lw=0.8, ls="-.", label=f"t* formula = {t_formula:.4g}")
    L = res.param("bulk", "length")
    if L is not None:
        ax.axhline(L, color="0.3", lw=0.8, label=f"L = {L:g}")
    t_all = [dataset(res.group(m), "series/t") for m in models]
    t_all = [a for a in t_all if a is not None and len(a)]
    if t_all:
        ax.set_xlim(min(a[0] for a in t_all), max(a[-1] for a in t_all))
    ax.set_xlabel("t")
    ax.set_ylabel("x_tip")
    if ax.lines:
        ax.legend(fontsize=8, loc="upper left")
    else:
        no_data(ax, "no series/tip_x")
    ax.set_title(res.title("front tip trajectory", fig), fontsize=10)
    if lines:
        text = "\n".join(_wrap(s) for s in lines)
        fig.text(0.01, 0.005, text, fontsize=8, family="monospace", va="bottom")
        bottom = 0.022 * (text.count("\n") + 1) + 0.02  # keep the axes clear of the event table
        fig.get_layout_engine().set(rect=(0, bottom, 1, 1 - bottom))
    save(fig, outdir, f"{res.scene}_tip.png", written, dpi)
    plot_normal_stress(res, outdir, written, dpi)
    plot_sequence(res, outdir, written, dpi)


def normal_stress_times(ts, ev, count=5):
    """The snapshot indices the sigma_yy(x) panel draws: the snapshots nearest the events (t*, halfway to t^, t^,
    the arrest) and the last one; evenly spaced ones when the run has none of those events."""
    wanted = [ev.get("t_star"), None, ev.get("t_hat"), ev.get("t_arrest"), ts[-1]]
    if finite(wanted[0]) and finite(wanted[2]):
        wanted[1] = 0.5 * (wanted[0] + wanted[2])
    wanted = [w for w in wanted if finite(w) and ts[0] <= w <= ts[-1]]
    if len(wanted) < 2:
        wanted = list(np.linspace(ts[0], ts[-1], count))
    return sorted({int(np.argmin(np.abs(ts - w))) for w in wanted})


def plot_normal_stress(res: Results, outdir, written, dpi):
    """The in-plane strip's interface normal stress (docs/output.md snapshots/sigma_yy; the other bodies have none):
    sigma_yy(x, 0) at the snapshots nearest the events, every model on one axis (solid: the first, dashed: the
    others), and its space-time map per model on one symmetric colour scale."""
    models = [m for m in res.models if dataset(res.group(m), "snapshots/sigma_yy") is not None]
    if not models:
        return
    first = res.group(models[0])
    x, ts = dataset(first, "x"), dataset(first, "snapshots/t")
    fields = {m: dataset(res.group(m), "snapshots/sigma_yy") for m in models}
    if x is None or ts is None or not len(ts) or any(f.shape != (len(ts), len(x)) for f in fields.values()):
        return
    # the colour scale at the 95th percentile of |sigma_yy|: the loaded corner's peak (not grid-converged) would
    # otherwise leave the interface behind the fronts white
    lim = float(np.nanpercentile(np.abs(np.concatenate([f.ravel() for f in fields.values()])), 95))
    lim = lim if finite(lim) and lim > 0 else 1.0
    fig, axes = plt.subplots(1, 1 + len(models), figsize=(7.5 + 6.0 * len(models), 5.5), squeeze=False,
                             constrained_layout=True)
    ax = axes[0, 0]
    for c, k in enumerate(normal_stress_times(ts, events(first))):
        for j, m in enumerate(models):
            ax.plot(x, fields[m][k], color=f"C{c}", lw=1.2 if j == 0 else 0.9, ls="-" if j == 0 else "--",
                    label=f"t = {ts[k]:.4g}" if j == 0 else None)
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("x")
    ax.set_ylabel("sigma_yy(x, 0)  (> 0: tension)")
    ax.set_title("interface normal stress" + (f" ({models[0]} solid, {', '.join(models[1:])} dashed)"
                                              if len(models) > 1 else f" ({models[0]})"), fontsize=10)
    ax.legend(fontsize=8, loc="best")
    for j, m in enumerate(models, start=1):
        ax = axes[0, j]
        pc = ax.pcolormesh(x, ts, fields[m], shading="nearest", cmap="RdBu_r", vmin=-lim, vmax=lim, rasterized=True)
        fig.colorbar(pc, ax=ax, label=f"sigma_yy(x, 0) (clipped at +-{lim:.3g}: 95 % of |values|)", pad=0.01,
                     extend="both")
        mark_times(ax, events(res.group(m)), vertical=False)
        ax.set_xlabel("x")
        ax.set_ylabel("t")
        ax.set_title(f"{m}: sigma_yy", fontsize=10)
    fig.suptitle(res.title("interface normal stress sigma_yy(x, 0, t) (the in-plane strip)", fig), fontsize=11)
    save(fig, outdir, f"{res.scene}_sigma_yy.png", written, dpi)


def plot_sequence(res: Results, outdir, written, dpi):
    """The slip events of an edge-loaded run (output.sequence, docs/output.md sequence/): each event's arrest position
    and speed against its start time, every model (a filled marker: the event spanned the interface)."""
    models = [m for m in res.models if dataset(res.group(m), "sequence/t_start") is not None]
    if not models or all(len(dataset(res.group(m), "sequence/t_start")) == 0 for m in models):
        return
    fig, (ax_x, ax_c) = plt.subplots(2, 1, figsize=(8.0, 6.4), sharex=True)
    for i, m in enumerate(models):
        g = res.group(m)
        t0, xa = dataset(g, "sequence/t_start"), dataset(g, "sequence/x_arrest")
        ce, span = dataset(g, "sequence/c_event"), dataset(g, "sequence/spanning")
        st = style(m, i)
        for k in range(len(t0)):
            face = st["color"] if span[k] == 1 else "none"
            lab = m if k == 0 else None
            ax_x.plot(t0[k], xa[k], st.get("marker", "o"), color=st["color"], mfc=face, ms=8, label=lab)
            ax_c.plot(t0[k], ce[k], st.get("marker", "o"), color=st["color"], mfc=face, ms=8, label=lab)
        ax_x.plot(t0, xa, "-", color=st["color"], lw=0.8, alpha=0.5)
        ax_c.plot(t0, ce, "-", color=st["color"], lw=0.8, alpha=0.5)
    ax_x.set_ylabel("arrest position x_arrest")
    ax_c.set_ylabel("event speed c_event")
    ax_c.set_xlabel("event start t")
    ax_x.legend(fontsize=9, title="filled: spanned the interface", title_fontsize=9)
    fig.suptitle(res.title("the sequence of slip events (output.sequence, docs/model.md §3.2)", fig), fontsize=11)
    save(fig, outdir, f"{res.scene}_sequence.png", written, dpi)


def _wrap(s, width=150):
    out, line = [], ""
    for word in s.split(", "):
        if line and len(line) + len(word) + 2 > width:
            out.append(line + ",")
            line = "    " + word
        else:
            line = f"{line}, {word}" if line else word
    return "\n".join(out + [line])


# --------------------------------------------------------------------------------------------
# 0D: friction law sweep


def plot_sweep(res: Results, outdir, written, dpi):
    fig, (ax, axA, axr) = plt.subplots(3, 1, figsize=(8.5, 11), sharex=True, constrained_layout=True,
                                       gridspec_kw=dict(height_ratios=[1.6, 1, 0.8]))
    p, ag = interface_params(res), aging_params(res)
    law = None  # the closed form each model is held to: with aging the age-structured balance's (§11.1)
    if p:
        law = (lambda u: aged_sigma_ss(u, *p, *ag)) if ag else (lambda u: sigma_ss(u, *p))  # noqa: E731
    axz = ax.inset_axes([0.06, 0.5, 0.36, 0.45])  # zoom on the minimum
    vmins, vmaxs = [], []
    for j, m in enumerate(res.models):
        g = res.group(m)
        v, s, se, A = (dataset(g, f"friction_law/{k}") for k in ("v", "sigma", "sigma_stderr", "A"))
        if v is None or s is None or len(v) != len(s) or not len(v):
            continue
        st = style(m, j)
        vmins.append(np.nanmin(v))
        vmaxs.append(np.nanmax(v))
        yerr = se if se is not None and len(se) == len(v) else None
        for a in (ax, axz):
            a.errorbar(v, s, yerr=yerr, ls="none", marker=st["marker"], ms=4, color=st["color"], capsize=2,
                       zorder=st["zorder"], label=f"{m}: time average ± stderr")
        if A is not None and len(A) == len(v):
            axA.plot(v, A, ls="none", marker=st["marker"], ms=4, color=st["color"], label=m)
        ref = law(v) if law else dataset(g, "friction_law/sigma_closed_form")
        if ref is not None and len(ref) == len(v):
            rel = (s - ref) / ref
            rel_err = yerr / np.abs(ref) if yerr is not None else None
            axr.errorbar(v, rel, yerr=rel_err, ls="none", marker=st["marker"], ms=4, color=st["color"], capsize=2,
                         label=m)
        vm_fit, sc_fit = as_float(g.attrs.get("v_m_fit", math.nan)), as_float(g.attrs.get("sigma_c_fit", math.nan))
        if finite(vm_fit) and finite(sc_fit):
            for a in (ax, axz):
                a.plot([vm_fit], [sc_fit], marker="x", ms=12, mew=2.5, color=st["color"], ls="none", zorder=4,
                       label=f"{m}: fitted minimum v_m = {vm_fit:.4g}, sigma_c = {sc_fit:.5g}")
    if not vmins:
        no_data(ax, "no friction_law group")
        fig.suptitle(res.title("steady friction law", fig), fontsize=10)
        save(fig, outdir, f"{res.scene}_steady_friction.png", written, dpi)
        return
    vv = np.geomspace(min(vmins), max(vmaxs), 400)
    if p and ag:
        vm, sc = aged_law_lines(ax, axz, axA, vv, p, ag)
    elif p:
        alpha, kappa, eta = p
        for a in (ax, axz):
            a.plot(vv, sigma_ss(vv, *p), color="k", lw=1, zorder=1,
                   label=f"closed form alpha/(1+kappa v) + eta v  (alpha={alpha:g}, kappa={kappa:g}, eta={eta:g})")
        axA.plot(vv, area_ss(vv, kappa), color="k", lw=1, label="closed form 1/(1+kappa v)")
        vm, sc = minimum_of_friction(*p)
    if p:
        if finite(vm):
            ax.axvline(vm, color="0.4", ls=":", lw=1)
            ax.axhline(sc, color="0.4", ls=":", lw=1)
            for a in (ax, axz):
                a.plot([vm], [sc], marker="*", ms=14, color="gold", mec="k", ls="none", zorder=5,
                       label=f"closed form v_m = {vm:.5g}, sigma_c^d = {sc:.5g}")
            axz.axvline(vm, color="0.4", ls=":", lw=1)
            axz.axhline(sc, color="0.4", ls=":", lw=1)
            axz.set_xlim(vm / 5, vm * 5)
            axz.set_ylim(sc * 0.95, float(law(vm * 5)) * 1.02)
            axA.axvline(vm, color="0.4", ls=":", lw=1)
            axr.axvline(vm, color="0.4", ls=":", lw=1)
    else:
        for j, m in enumerate(res.models):
            g = res.group(m)
            v, ref = dataset(g, "friction_law/v"), dataset(g, "friction_law/sigma_closed_form")
            if v is not None and ref is not None and len(v) == len(ref):
                ax.plot(v, ref, color="k", lw=1, label="closed form (sigma_closed_form)")
                break
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylabel("steady friction sigma")
    ax.legend(fontsize=8.5, loc="lower center", bbox_to_anchor=(0.5, 1.01), ncol=2)  # above the axes
    axz.set_xscale("log")
    axz.set_title("near the minimum", fontsize=8)
    axz.tick_params(labelsize=8)
    ax.grid(alpha=0.3, which="both")
    axA.set_yscale("log")
    axA.set_ylabel("contact area A")
    axA.legend(fontsize=8)
    axA.grid(alpha=0.3, which="both")
    axr.axhline(0, color="k", lw=0.8)
    axr.set_ylabel("(sigma - balance's closed form) / closed form" if ag else "(sigma - closed form) / closed form")
    axr.set_xlabel("imposed slip rate v")
    if axr.has_data():
        axr.legend(fontsize=8)
    axr.grid(alpha=0.3, which="both")
    fig.suptitle(res.title("steady friction law", fig), fontsize=10)
    save(fig, outdir, f"{res.scene}_steady_friction.png", written, dpi)


def aged_law_lines(ax, axz, axA, vv, p, ag):
    """The steady law with aging (docs/model.md §11.1, §11.4): the balance's closed form (black, what mean_field and
    the ensemble must follow), the closure's (dashed, the continuum law's) and the law without aging (grey); the
    balance's minimum, found on vv. Returns (v_m, sigma_c^d) of the balance."""
    (alpha, kappa, eta), (b, tau) = p, ag
    bal, clo = aged_sigma_ss(vv, *p, b, tau), aged_sigma_ss(vv, *p, b, tau, closure=True)
    for a in (ax, axz):
        a.plot(vv, bal, color="k", lw=1, zorder=1,
               label=f"balance: alpha (1 + b e^x E1(x))/(1+kappa v) + eta v, x = kappa v tau_a (b={b:g}, tau_a={tau:g})")
        a.plot(vv, clo, color="k", lw=1, ls="--", zorder=1, label="one-variable closure: b ln(1 + 1/x) in place of b e^x E1(x)")
        a.plot(vv, sigma_ss(vv, *p), color="0.6", lw=1, ls=":", zorder=1, label="without aging (b = 0)")
    axA.plot(vv, (1.0 + b * exp_e1(kappa * vv * tau)) / (1.0 + kappa * vv), color="k", lw=1, label="balance's closed form")
    axA.plot(vv, area_ss(vv, kappa), color="0.6", lw=1, ls=":", label="without aging 1/(1+kappa v)")
    k = int(np.argmin(bal))
    return (float(vv[k]), float(bal[k])) if 0 < k < len(vv) - 1 else (math.nan, math.nan)


# --------------------------------------------------------------------------------------------
# 0D: imposed slip-rate history (velocity steps)


def plot_history(res: Results, outdir, written, dpi):
    vs = res.param("drive", "v")
    ts = res.param("drive", "switch_times")
    vs = [vs] if isinstance(vs, (int, float)) else vs
    p = interface_params(res)
    t_end = res.param("time", "t_end")
    switches = list(ts[1:5]) if isinstance(ts, list) else []
    if not switches:  # no config: find jumps of the recorded slip rate
        for m in res.models:
            t, v = dataset(res.group(m), "series/t"), dataset(res.group(m), "series/slip_rate")
            if t is not None and v is not None and len(t) > 1:
                switches = list(t[1:][np.abs(np.diff(v)) > 1e-12 * max(1.0, np.nanmax(np.abs(v)))][:4])
                break
    ncol = 1 + len(switches)
    fig, axes = plt.subplots(3, ncol, figsize=(6.5 + 3.6 * len(switches), 10), squeeze=False,
                             sharex="col", constrained_layout=True,
                             gridspec_kw=dict(width_ratios=[2] + [1] * len(switches)))
    any_data = False
    for j, m in enumerate(res.models):
        g = res.group(m)
        st = style(m, j)
        t = dataset(g, "series/t")
        if t is None or not len(t):
            continue
        cols = {k: dataset(g, f"series/{k}") for k in ("sigma", "sigma_bar", "A", "slip_rate")}
        if cols["slip_rate"] is None:
            cols["slip_rate"] = dataset(g, "series/max_v")
        for c in range(ncol):
            for r, (k, extra) in enumerate((("sigma", "sigma_bar"), ("A", None), ("slip_rate", None))):
                y = cols[k]
                if y is not None and len(y) == len(t):
                    axes[r, c].plot(t, y, color=st["color"], lw=1.1, zorder=st["zorder"], label=f"{m}: {k}")
                    any_data = True
                if extra and cols[extra] is not None and len(cols[extra]) == len(t):
                    axes[r, c].plot(t, cols[extra], color=st["color"], lw=0.9, ls="--", zorder=st["zorder"],
                                    label=f"{m}: {extra}")
        ev = events(g)
        many = len(res.models) > 1
        for c in range(ncol):
            for r in range(3):
                mark_times(axes[r, c], ev, label=(r == 0 and c == 0), color=st["color"] if many else None,
                           model=m if many else "")
    # steady states of each segment (docs/model.md §1), dotted
    if p and isinstance(vs, list) and isinstance(ts, list) and len(vs) == len(ts):
        ends = list(ts[1:]) + [t_end if t_end is not None else ts[-1] + 1.0]
        for k, (v, a, b) in enumerate(zip(vs, ts, ends)):
            for c in range(ncol):
                lab = k == 0 and c == 0
                axes[0, c].hlines(sigma_ss(v, *p), a, b, color="k", ls=":", lw=1,
                                  label="steady state sigma_ss(v)" if lab else None)
                axes[1, c].hlines(area_ss(v, p[1]), a, b, color="k", ls=":", lw=1,
                                  label="steady state A_ss(v)" if lab else None)
    for c, s in enumerate(switches, start=1):
        lo, hi = s - 0.5, s + 6.0
        for r in range(3):
            axes[r, c].set_xlim(lo, hi)
            axes[r, c].axvline(s, color="0.6", lw=0.8)
        axes[0, c].set_title(f"zoom on the jump at t = {s:g}")
        _autoscale_y(axes[:, c], lo, hi)
    for c in range(ncol):
        axes[2, c].set_xlabel("t")
    axes[0, 0].set_ylabel("sigma = sigma_bar + eta v  (dashed: sigma_bar)")
    axes[1, 0].set_ylabel("contact area A")
    axes[2, 0].set_ylabel("imposed slip rate v")
    axes[0, 0].set_title("full history")
    if any_data:
        axes[0, 0].legend(fontsize=8, loc="best")
        axes[1, 0].legend(fontsize=8, loc="best")
    else:
        no_data(axes[0, 0], "no series")
    fig.suptitle(res.title("imposed slip-rate history", fig), fontsize=10)
    save(fig, outdir, f"{res.scene}_history.png", written, dpi)
    plot_hold_peaks(res, outdir, written, dpi)


def hold_segments(t, v):
    """[(start, end, holding)] index ranges of a series where the slip rate is 0 (a hold) or not."""
    hold = v == 0.0
    edges = np.flatnonzero(np.diff(hold.astype(int))) + 1
    bounds = np.concatenate(([0], edges, [len(t)]))
    return [(a, b, bool(hold[a])) for a, b in zip(bounds[:-1], bounds[1:])]


def hold_peaks(t, v, sigma):
    """Slide-hold-slide (docs/model.md §11.1): per hold followed by a slide, (t_h, the slide's static peak max sigma,
    sigma just before the hold), t_h from the last sliding sample to the last held one."""
    out = []
    segs = hold_segments(t, v)
    for k in range(1, len(segs) - 1):
        a, b, holding = segs[k]
        if holding:
            na, nb, _ = segs[k + 1]
            out.append((t[b - 1] - t[a - 1], sigma[na:nb].max(), sigma[a - 1]))
    return np.array(out).reshape(-1, 3)


def peak_slope(peaks, fit_from=10.0):
    """Least-squares d peak / d ln t_h over the holds t_h >= fit_from (NaN with fewer than two)."""
    fit = peaks[:, 0] >= fit_from
    return float(np.polyfit(np.log(peaks[fit, 0]), peaks[fit, 1], 1)[0]) if fit.sum() >= 2 else math.nan


def model_hold_peaks(res: Results):
    """{model: hold_peaks} of every model whose series has holds (an imposed-rate history with v = 0 segments)."""
    out = {}
    for m in res.models:
        g = res.group(m)
        t, v, sg = (dataset(g, f"series/{k}") for k in ("t", "slip_rate", "sigma"))
        if t is not None and v is not None and sg is not None and len(t) == len(v) == len(sg):
            pk = hold_peaks(t, v, sg)
            if len(pk):
                out[m] = pk
    return out


def plot_hold_peaks(res: Results, outdir, written, dpi):
    """<scene>_peaks.png of a slide-hold-slide history: each model's static peak against the hold time with its
    ln t_h slope (t_h >= 10), and every model's peak minus the age-structured balance's (mean_field: the closure's
    error and the ensemble's noise). Nothing when the history has no hold."""
    pk = model_hold_peaks(res)
    if not pk:
        return
    fig, (ax, axd) = plt.subplots(2, 1, figsize=(7, 7.5), sharex=True, constrained_layout=True,
                                  gridspec_kw=dict(height_ratios=[1.6, 1]))
    ag = aging_params(res)
    ref = pk.get("mean_field")
    for j, m in enumerate(res.models):
        if m not in pk:
            continue
        st, p = style(m, j), pk[m]
        ax.semilogx(p[:, 0], p[:, 1], marker=st["marker"], color=st["color"], ls="-", lw=1,
                    label=f"{m}: d peak / d ln t_h = {peak_slope(p):.4f} (t_h >= 10)")
        if ref is not None and m != "mean_field" and len(ref) == len(p):
            axd.semilogx(p[:, 0], p[:, 1] - ref[:, 1], marker=st["marker"], color=st["color"], ls="-", lw=1,
                         label=f"{m} - mean_field")
    if ag and len(next(iter(pk.values()))):
        th = np.geomspace(max(1e-3, min(p[:, 0].min() for p in pk.values())), max(p[:, 0].max() for p in pk.values()))
        p0 = pk.get("mean_field", next(iter(pk.values())))
        ax.semilogx(th, p0[-1, 1] + ag[0] * np.log(th / p0[-1, 0]), color="0.5", ls=":", lw=1,
                    label=f"slope b = {ag[0]:g} (the contacts' own), through the longest hold")
    ax.set_ylabel("static peak max sigma after the hold")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    axd.axhline(0, color="k", lw=0.8)
    axd.set_ylabel("peak - mean_field's peak")
    axd.set_xlabel("hold time t_h")
    if axd.has_data():
        axd.legend(fontsize=8)
    axd.grid(alpha=0.3, which="both")
    fig.suptitle(res.title("slide-hold-slide: static friction peak against hold time", fig), fontsize=10)
    save(fig, outdir, f"{res.scene}_peaks.png", written, dpi)


def _autoscale_y(axes, lo, hi):
    """Fit each axis's y range to the data inside [lo, hi] (sharex zoom columns)."""
    for ax in axes:
        ys = []
        for line in ax.get_lines():
            x, y = (np.asarray(a, dtype=float) for a in line.get_data())
            if x.size == 2 and x[0] == x[1]:  # vertical marker lines
                continue
            if x.size == y.size and x.size:
                sel = (x >= lo) & (x <= hi) & np.isfinite(y)
                ys.extend(y[sel])
        if ys:
            a, b = min(ys), max(ys)
            pad = 0.05 * (b - a) if b > a else 0.05 * max(abs(a), 1e-12)
            ax.set_ylim(a - pad, b + pad)


# --------------------------------------------------------------------------------------------
# 0D: spring block


def plot_spring_block(res: Results, outdir, written, dpi):
    fig = plt.figure(figsize=(13, 13), constrained_layout=True)
    gs = fig.add_gridspec(4, 1, height_ratios=[1.3, 1, 1, 0.9])
    axF = fig.add_subplot(gs[0])
    axv = fig.add_subplot(gs[1], sharex=axF)
    axA = fig.add_subplot(gs[2], sharex=axF)
    axc = fig.add_subplot(gs[3])
    p = interface_params(res)
    vd = res.param("drive", "v_d")
    any_cycles = False
    for j, m in enumerate(res.models):
        g = res.group(m)
        st = style(m, j)
        t = dataset(g, "series/t")
        F = dataset(g, "series/drive_force")
        v = dataset(g, "series/slip_rate")
        if v is None:
            v = dataset(g, "series/max_v")
        A = dataset(g, "series/A")
        for ax, y, lab in ((axF, F, "F = K (v_d t - u)"), (axv, v, "v"), (axA, A, "A")):
            if t is not None and y is not None and len(y) == len(t):
                ax.plot(t, y, color=st["color"], lw=0.9, zorder=st["zorder"], label=f"{m}: {lab}")
        ts, Fp, Fr = (dataset(g, f"cycles/{k}") for k in ("t_start", "F_peak", "F_residual"))
        if ts is not None and Fp is not None and Fr is not None and len(ts) == len(Fp) == len(Fr) and len(ts):
            any_cycles = True
            axF.plot(ts, Fp, ls="none", marker="^", ms=7, color=st["color"], mec="k", zorder=st["zorder"] + 2,
                     label=f"{m}: F_peak (at slip start)")
            # the residual is the smallest F during the event: place it at the series minimum after t_start
            tr = np.full(len(ts), np.nan)
            if t is not None and F is not None and len(F) == len(t):
                nxt = list(ts[1:]) + [t[-1] + 1.0]
                for k, (a, b) in enumerate(zip(ts, nxt)):
                    sel = (t >= a) & (t < b)
                    if np.any(sel):
                        tr[k] = t[sel][np.argmin(F[sel])]
            axF.plot(tr, Fr, ls="none", marker="v", ms=7, color=st["color"], mec="k", zorder=st["zorder"] + 2,
                     label=f"{m}: F_residual")
            n = np.arange(1, len(ts) + 1)
            axc.plot(n, Fp, marker="^", color=st["color"], zorder=st["zorder"], label=f"{m}: F_peak")
            axc.plot(n, Fr, marker="v", color=st["color"], ls="--", zorder=st["zorder"], label=f"{m}: F_residual")
        many = len(res.models) > 1
        mark_times(axF, events(g), color=st["color"] if many else None, model=m if many else "")
    if p and vd is not None:
        axF.axhline(sigma_ss(vd, *p), color="k", ls=":", lw=1, label=f"sigma_ss(v_d) = {sigma_ss(vd, *p):.4g}")
        axv.axhline(vd, color="k", ls=":", lw=1, label=f"v_d = {vd:g}")
        axA.axhline(area_ss(vd, p[1]), color="k", ls=":", lw=1, label=f"A_ss(v_d) = {area_ss(vd, p[1]):.4g}")
    axF.set_ylabel("drive force F")
    axv.set_ylabel("slip rate v")
    axA.set_ylabel("contact area A")
    axA.set_xlabel("t")
    for ax in (axF, axv, axA):
        if ax.has_data():
            ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: cycles fill the axes
    axF.set_title("stick-slip")
    axc.set_title("peak and residual drive force, per stick-slip cycle")
    axc.set_xlabel("cycle")
    axc.set_ylabel("F")
    if any_cycles:
        axc.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        axc.grid(alpha=0.3)
    else:
        no_data(axc, "no stick-slip cycles\n(no cycles group)")
    if not axF.has_data():
        no_data(axF, "no series")
    fig.suptitle(res.title("spring-driven block", fig), fontsize=10)
    save(fig, outdir, f"{res.scene}_stick_slip.png", written, dpi)


# --------------------------------------------------------------------------------------------
# anything else: every series against t


def plot_generic(res: Results, outdir, written, dpi):
    names = sorted({k for m in res.models if "series" in res.group(m) for k in res.group(m)["series"].keys()} - {"t"})
    if not names:
        print(f"plot.py: {res.path}: nothing to plot (no series)", file=sys.stderr)
        return
    fig, axes = plt.subplots(len(names), 1, figsize=(9, 2.2 * len(names) + 1), sharex=True, squeeze=False,
                             constrained_layout=True)
    for j, m in enumerate(res.models):
        t = dataset(res.group(m), "series/t")
        for ax, k in zip(axes[:, 0], names):
            y = dataset(res.group(m), f"series/{k}")
            if t is not None and y is not None and len(y) == len(t):
                ax.plot(t, y, color=style(m, j)["color"], lw=1, label=m)
            ax.set_ylabel(k)
    axes[-1, 0].set_xlabel("t")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle(res.title("series", fig), fontsize=10)
    save(fig, outdir, f"{res.scene}_series.png", written, dpi)


def growth_rates_figure(path, outdir, dpi, title=None, rows_note="16 rows", scene_channel=None):
    """docs/model.md §12.6, §12.7: growth rates Re s against kH of homogeneous sliding on the in-plane strip under the normal-load
    coupling, every channel in the file: the linearisation (continuum::leading_growth_rate: the least-damped resolved mode,
    and the fastest of all modes) as lines, seeded grid runs (tests/test_inplane_load.cpp) as markers. `path`: a
    growth_rates.csv (columns channel, kH, kind, re_s, im_s), written by `slipfront stability` (docs/output.md) or by the
    test with SLIPFRONT_GROWTH_CSV set; `title` (default: the test's strip), `rows_note` (the rows of the fastest modes)
    and `scene_channel` (the CSV's channel the scene runs: drawn thicker) from the caller. Returns the PNGs written."""
    rows = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    rows = np.atleast_1d(rows)
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    # the uncoupled strip (grey, drawn first), the two channels, then any regularised one (docs/model.md §12.7:
    # "instantaneous L=..."), in the file's order
    colors = {"uncoupled": "0.6", "reattachment": "tab:blue", "instantaneous": "tab:red"}
    more = iter(["tab:purple", "tab:green", "tab:orange", "tab:brown"] * 8)
    for channel in dict.fromkeys(str(c) for c in rows["channel"]):
        if channel not in colors:
            colors[channel] = next(more)
    styles = {"theory_resolved": ("-", "least-damped resolved mode (omega H/c_p < 4)"),
              "theory_max": (":", f"fastest mode of all ({rows_note})")}
    for channel, color in colors.items():
        lw = 2.2 if channel == scene_channel else 1.2
        mark = " (the scene's)" if channel == scene_channel else ""
        for kind, (ls, what) in styles.items():
            sel = (rows["channel"] == channel) & (rows["kind"] == kind)
            if sel.any():
                ax.plot(rows["kH"][sel], rows["re_s"][sel], ls, color=color, lw=lw, label=f"{channel}{mark}: {what}")
        sel = (rows["channel"] == channel) & (rows["kind"] == "run")
        if sel.any():
            ax.plot(rows["kH"][sel], rows["re_s"][sel], "o", color=color, label=f"{channel}: seeded grid run")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1e-3)
    ax.set_xlabel("kH")
    ax.set_ylabel("growth rate Re s (symlog, linear within 1e-3)")
    ax.set_title(title or "in-plane strip, homogeneous sliding v0 = 2, p_0 = 0.3 (H = 4): growth rates under the coupling",
                 fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    written = []
    save(fig, outdir, "inplane_growth_rates.png", written, dpi)
    return written


def plot_growth_rates(path, outdir, dpi):
    """growth_rates_figure of a growth_rates.csv given on the command line; prints the PNG written."""
    written = growth_rates_figure(path, outdir, dpi)
    for w in written:
        print(w)
    return 0 if written else 1


PLOTTERS = {"1d": plot_1d, "sweep": plot_sweep, "history": plot_history, "spring_block": plot_spring_block,
            "unknown": plot_generic}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Plot a slipfront results file (see docs/output.md).")
    ap.add_argument("results", help="path to results.h5 written by `slipfront run`")
    ap.add_argument("--outdir", help="directory for the PNGs (default: the directory of RESULTS)")
    ap.add_argument("--dpi", type=int, default=120, help="resolution of the PNGs (default 120)")
    args = ap.parse_args(argv)
    if args.results.endswith("growth_rates.csv"):  # docs/model.md §12.6 (slipfront stability writes it)
        return plot_growth_rates(args.results, args.outdir or os.path.dirname(os.path.abspath(args.results)), args.dpi)

    try:
        res = Results(args.results)
    except OSError as e:
        print(f"plot.py: cannot open {args.results}: {e}", file=sys.stderr)
        return 1
    outdir = args.outdir or os.path.dirname(os.path.abspath(args.results))
    os.makedirs(outdir, exist_ok=True)
    if not res.models:
        print(f"plot.py: {args.results}: no model group (continuum, discrete) to plot; /meta status = {res.status}",
              file=sys.stderr)
        return 1
    written: list[str] = []
    with res.f:
        PLOTTERS[res.kind()](res, outdir, written, args.dpi)
    for path in written:
        print(path)
    return 0 if written else 1


if __name__ == "__main__":
    sys.exit(main())
