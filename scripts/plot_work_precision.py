#!/usr/bin/python3
"""Work-precision plot of the continuum integrators (docs/performance.md).

Reads the CSV written by bench/bench_work_precision and draws, log-log, the relative error (x) of
each measured quantity against the wall time (y), one line per integrator family, with the 1 %
target marked.

    scripts/plot_work_precision.py work_precision.csv [--out work_precision.png] [--integration]

--integration plots the integration time alone (without the shared measurements).
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
    "explicit": ("k", "s"),
    "adaptive": ("tab:red", "o"),
    "adaptive_retake": ("tab:orange", "v"),
    "cvode": ("tab:blue", "^"),
    "cvode_atol=rtol": ("tab:cyan", "^"),
    "cvode_roots": ("tab:green", "D"),
    "cvode_roots_atol=rtol": ("tab:olive", "D"),
    "cvode_maxord5": ("tab:purple", "x"),
}


def number(s):
    try:
        x = float(s)
    except ValueError:
        return math.nan
    return x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv")
    ap.add_argument("--out", default=None, help="output image (default: CSV name with .png)")
    ap.add_argument("--integration", action="store_true", help="integration time only")
    args = ap.parse_args()

    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{args.csv}: no rows")
    err_a = next(k for k in rows[0] if k.startswith("err_") and k not in ("err_t_star", "err_c_transient"))
    l2_keys = [k for k in rows[0] if k.startswith("l2_A_")]
    panels = [(err_a, f"relative error of {err_a[4:]}"), ("err_c_transient", "relative error of c_transient")]
    if l2_keys:
        panels.append((l2_keys[0], f"L2 distance of A at t = {l2_keys[0][5:]}"))
    wall_key = "wall_integrator" if args.integration else "wall"

    families = defaultdict(list)
    for r in rows:
        if r["status"] != "complete":
            continue
        families[r["family"]].append(r)

    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.4), squeeze=False)
    for ax, (key, label) in zip(axes[0], panels):
        for fam, rs in families.items():
            # joined in the order of the setting (cfl or rtol, loose to tight), not of the error
            pts = sorted(((number(r[key]), number(r[wall_key]), number(r["setting"])) for r in rs), key=lambda p: -p[2])
            pts = [p for p in pts if p[0] > 0 and p[1] > 0 and math.isfinite(p[0])]
            if not pts:
                continue
            color, marker = STYLE.get(fam, ("gray", "."))
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=color, label=fam, lw=1.2, ms=5)
        if key.startswith("err_"):
            ax.axvline(1e-2, color="gray", ls="--", lw=0.8)
            ax.text(1.05e-2, ax.get_ylim()[0] * 1.3, "1 %", color="gray", fontsize=8)
        ax.set_xlabel(label)
        ax.set_ylabel("integration time [s]" if args.integration else "wall time, whole run [s]")
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    axes[0][0].legend(fontsize=7, loc="best")
    scene = rows[0].get("scene", "")
    fig.suptitle(f"work-precision, scene {scene} (reference: adaptive at the tightest tolerance)", fontsize=10)
    fig.tight_layout()
    out = args.out or (args.csv.rsplit(".", 1)[0] + ".png")
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
