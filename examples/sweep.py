"""A parameter sweep in a Python loop: the first yield time t* of the edge-loaded interface against the drive
speed v_d, measured by runs of the continuum model and compared with the closed form
t* = (K + sqrt(alpha mu)) / (alpha K v_d) (docs/model.md §1).

    python3 examples/sweep.py [--out DIR] [--small]"""
import argparse
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import slipfront  # noqa: E402

HERE = Path(__file__).resolve().parent
args = argparse.ArgumentParser(description=__doc__.splitlines()[0])
args.add_argument("--out", default="out/examples/sweep")
args.add_argument("--small", action="store_true")
opts = args.parse_args()
out = Path(opts.out)

base = slipfront.Scene.from_toml(HERE.parent / "configs" / "fig1.toml").set("models", ["continuum"])
base.set("bulk.length", 60.0 if opts.small else 300.0).set("grid.dx", 1.0 if opts.small else 0.5)
config = base.check().config
K, mu, alpha = config["drive"]["K"], config["bulk"]["mu"], config["interface"]["alpha"]

speeds = [0.3, 0.6, 1.2] if opts.small else [0.15, 0.3, 0.6, 1.2, 2.4]
measured = []
for v_d in speeds:
    t_star = (K + np.sqrt(alpha * mu)) / (alpha * K * v_d)
    scene = base.copy().set("drive.v_d", v_d).set("time.t_end", 1.2 * t_star).set("output.snapshot_dt", 0.0)
    res = slipfront.run(scene, out=out / ("v_d=%g" % v_d), force=True, progress=False)
    measured.append(res["continuum"].events["t_star"])
    print("v_d = %-5g t* = %.3f (closed form %.3f)" % (v_d, measured[-1], t_star))

v = np.array(speeds)
fig, ax = plt.subplots(figsize=(5, 4), constrained_layout=True)
ax.loglog(v, measured, "o", label="runs")
ax.loglog(v, (K + np.sqrt(alpha * mu)) / (alpha * K * v), "-", label="closed form")
ax.set(xlabel="v_d", ylabel="t*", title="first yield against drive speed")
ax.legend()
fig.savefig(out / "sweep.png", dpi=80)
print("figure:", out / "sweep.png")
