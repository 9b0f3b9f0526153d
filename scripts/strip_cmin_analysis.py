#!/usr/bin/env python3
"""c_min(H) of the strip against the paper's 2D argument (docs/fronts.md §10.12), from the CSV written by
build/bench/strip_cmin_height or the study strip_cmin_height. Per H: c/s, the local exponent, the 1D ratio; the paper's intermediate regime
c/s ~ sqrt(H/l_k) (l/H)^(eps/2) with tan(pi eps/2) = c/s (eps from the measured c/s; its prefactor taken from
the 1D line, 0.576 sqrt(H/l_k) = c_min_1D/s in the 1D regime) and its local exponent 1/2 - eps/2; the large-H
(Brener-Marchenko) eps_BM = ln(H/l_k)/ln(H/l) against eps = (2/pi) atan(c/s). Usage: strip_cmin_analysis.py CSV"""
import csv, math, sys

rows = list(csv.DictReader(open(sys.argv[1])))
mu, alpha, kappa, eta = 300.0, 1.05, 8.0, 0.1
if len(sys.argv) > 2:
    mu, alpha, kappa, eta = map(float, sys.argv[2:6])
ell, ellk, s = mu, mu * kappa / (eta * alpha), mu / eta
print("| H | H/l | H/l_k | c_min | c/s | c_min/c_min,1D | local exp. | 1/2 - eps/2 | c/s over the intermediate form | eps = (2/pi) atan(c/s) | eps_BM |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for k, r in enumerate(rows):
    H, c, c1 = float(r["H"]), float(r["c_min"]), float(r["c_min_1d"])
    cs_ = c / s
    eps = 2 / math.pi * math.atan(cs_)
    # the local exponent and the prediction at the interval's midpoint (geometric)
    if k + 1 < len(rows):
        H2, c2 = float(rows[k + 1]["H"]), float(rows[k + 1]["c_min"])
        expo = math.log(c2 / c) / math.log(H2 / H)
        eps_mid = 2 / math.pi * math.atan(math.sqrt(c * c2) / s)
        pred = 0.5 - eps_mid / 2
        es = f"{expo:.4f}"
        ps = f"{pred:.4f}"
    else:
        es = ps = "—"
    a1d = c1 / (s * math.sqrt(H / ellk))  # the measured 1D prefactor: c_min,1D/s = a1d sqrt(H/l_k) (0.5697 here)
    inter = a1d * math.sqrt(H / ellk) * (ell / H) ** (eps / 2) if H > ell else float("nan")
    bm = math.log(H / ellk) / math.log(H / ell) if H > ellk else float("nan")
    print(f"| {H:.4g} | {H/ell:.3g} | {H/ellk:.3g} | {c:.6g} | {cs_:.4g} | {c/c1:.5f} | {es} | {ps} | "
          f"{(cs_/inter if inter == inter else float('nan')):.3g} | {eps:.3f} | {bm:.3f} |")
