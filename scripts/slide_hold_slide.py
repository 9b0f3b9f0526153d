#!/usr/bin/env python3
"""Static friction peaks of a slide-hold-slide run (configs/slide_hold_slide.toml, docs/model.md §11).

Reads DIR/results.h5 (slipfront run of a 0D imposed-rate history), finds each hold (a stretch with slip rate 0)
and the slide after it, and prints per model the peak friction max sigma of that slide against the hold time t_h,
and the least-squares slope d peak / d ln t_h over the holds t_h >= --fit-from (default 10). With --plot FILE it
draws peak - sigma before the hold against t_h on a log axis.

    /usr/bin/python3 scripts/slide_hold_slide.py out/slide_hold_slide [--plot shs.png]
"""
import argparse
import sys

import h5py
import numpy as np


def segments(t, v):
    """[(start, end, holding)] index ranges of constant slip-rate sign (v == 0: a hold)."""
    hold = v == 0.0
    edges = np.flatnonzero(np.diff(hold.astype(int))) + 1
    bounds = np.concatenate(([0], edges, [len(t)]))
    return [(a, b, bool(hold[a])) for a, b in zip(bounds[:-1], bounds[1:])]


def peaks(t, v, sigma):
    """(t_h, peak after the hold, sigma just before the hold) per hold followed by a slide."""
    out = []
    segs = segments(t, v)
    for k in range(1, len(segs) - 1):
        a, b, holding = segs[k]
        if not holding:
            continue
        t_h = t[b - 1] - t[a - 1]  # from the last sliding sample to the last held one
        na, nb, _ = segs[k + 1]
        out.append((t_h, sigma[na:nb].max(), sigma[a - 1]))
    return np.array(out)


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
            rows[m] = peaks(s["t"][()], s["slip_rate"][()], s["sigma"][()])
    if not rows:
        sys.exit("no 0D series in " + a.dir)
    for m, p in rows.items():
        fit = p[:, 0] >= a.fit_from
        slope = np.polyfit(np.log(p[fit, 0]), p[fit, 1], 1)[0] if fit.sum() >= 2 else float("nan")
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
