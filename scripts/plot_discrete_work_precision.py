#!/usr/bin/python3
"""Discrete work-precision plot (docs/scaling.md §4).

Reads the CSV written by bench/bench_discrete_work_precision and draws, log-log, the mean error
against the continuum (x, with its standard error over seeds) against the mean wall time (y), one line
per representation (and integrator) through increasing N, one panel per measured quantity:
friction_law (RMS relative error of sigma over the rates), fig1 t_hat and fig1 c_transient.
The continuum's wall time is drawn as a horizontal line in each panel.

    /usr/bin/python3 scripts/plot_discrete_work_precision.py discrete_wp.csv [--out discrete_wp.png]
"""
import argparse
import csv
import math
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    ("count", "exact"): ("tab:red", "o"),
    ("count", "explicit"): ("tab:red", "o"),
    ("count", "implicit"): ("tab:orange", "s"),
    ("agent", "exact"): ("tab:blue", "^"),
    ("agent", "explicit"): ("tab:blue", "^"),
    ("naive", "exact"): ("k", "x"),
    ("naive", "explicit"): ("k", "x"),
}


def mean_se(xs):
    n = len(xs)
    m = sum(xs) / n
    if n < 2:
        return m, 0.0
    return m, math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv")
    ap.add_argument("--out", default=None, help="output image (default: CSV name with .png)")
    args = ap.parse_args()
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{args.csv}: no rows")

    groups = defaultdict(list)  # (scene, repr, integrator, N) -> rows
    for r in rows:
        groups[(r["scene"], r["representation"], r["integrator"], int(r["N"]))].append(r)

    panels = [("friction_law", "err1", "friction_law: RMS relative error of sigma_ss(v)"),
              ("fig1", "err1", "fig1: relative error of t_hat"),
              ("fig1", "err2", "fig1: relative error of c_transient")]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.4))
    for ax, (scene, key, title) in zip(axes, panels):
        lines = defaultdict(list)  # (repr, integrator) -> [(N, err, se, wall)]
        cont_wall = None
        for (sc, rep, integ, n), rs in groups.items():
            if sc != scene:
                continue
            e, se = mean_se([float(r[key]) for r in rs])
            w, _ = mean_se([float(r["wall"]) for r in rs])
            cont_wall = float(rs[0]["continuum_wall"])
            lines[(rep, integ)].append((n, e, se, w))
        for (rep, integ), pts in sorted(lines.items()):
            pts.sort()
            color, marker = STYLE.get((rep, integ), ("tab:gray", "."))
            label = rep if integ in ("exact", "explicit") else f"{rep} ({integ}, dt 0.02)"
            ax.errorbar([p[1] for p in pts], [p[3] for p in pts], xerr=[p[2] for p in pts], color=color,
                        marker=marker, label=label, capsize=2)
            for n, e, _, w in pts:
                ax.annotate(f"N={n:g}", (e, w), textcoords="offset points", xytext=(4, 3), fontsize=7, color=color)
        if cont_wall:
            ax.axhline(cont_wall, color="gray", ls="--", lw=1, label="continuum (explicit / sweep)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("error against the continuum (mean over seeds, ± SE)")
        ax.set_ylabel("wall time per run [s]")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    out = args.out or args.csv.rsplit(".", 1)[0] + ".png"
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
