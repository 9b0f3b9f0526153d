#!/usr/bin/env python3
"""Static friction peaks of a slide-hold-slide run (configs/slide_hold_slide.toml, docs/model.md §11).

Reads DIR/results.h5 (slipfront run of a 0D imposed-rate history), finds each hold (a stretch with slip rate 0)
and the slide after it, and prints per model the peak friction max sigma of that slide against the hold time t_h,
and the least-squares slope d peak / d ln t_h over the holds t_h >= --fit-from (default 10). With --plot FILE it
draws peak - sigma before the hold against t_h on a log axis.

    /usr/bin/python3 scripts/slide_hold_slide.py out/slide_hold_slide [--plot shs.png]
"""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot import hold_peaks, peak_slope  # noqa: E402  (one implementation: scripts/plot.py draws <scene>_peaks.png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--fit-from", type=float, default=10.0)
    ap.add_argument("--plot")
    a = ap.parse_args()
    rows = {}
    with h5py.File(f"{a.dir}/results.h5", "r") as f:
        models = [m for m in ("discrete", "mean_field", "continuum") if m in f and "series" in f[m]]
        for m in models:
            s = f[m]["series"]
            rows[m] = hold_peaks(s["t"][()], s["slip_rate"][()], s["sigma"][()])
    if not rows:
        sys.exit("no 0D series in " + a.dir)
    for m, p in rows.items():
        slope = peak_slope(p, a.fit_from)
        print(f"{m}: slope d peak / d ln t_h over t_h >= {a.fit_from:g}: {slope:.5f}")
        for t_h, pk, before in p:
            print(f"  t_h = {t_h:8.3f}  peak = {pk:.6f}  peak - sigma before hold = {pk - before:.6f}")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 3.5))
        for m, p in rows.items():
            ax.semilogx(p[:, 0], p[:, 1], "o-", label=m)
        ax.set_xlabel("hold time $t_h$")
        ax.set_ylabel("static peak $\\max\\sigma$")
        ax.legend()
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)


if __name__ == "__main__":
    main()
