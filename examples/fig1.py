"""fig1 of the paper (docs/model.md §4): the edge-loaded interface, its slow front, the fast transient and the
arrest — run from Python and plotted: the slip rate v(x, t) as a space-time map and the drive force F(t).

    python3 examples/fig1.py [--out DIR] [--small]
--small runs a shorter, coarser fig1 (seconds; what the tests run)."""
import argparse
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import slipfront  # noqa: E402

HERE = Path(__file__).resolve().parent
args = argparse.ArgumentParser(description=__doc__.splitlines()[0])
args.add_argument("--out", default="out/examples/fig1")
args.add_argument("--small", action="store_true")
opts = args.parse_args()

scene = slipfront.Scene.from_toml(HERE.parent / "configs" / "fig1.toml")
if opts.small:
    scene.set("bulk.length", 100.0).set("grid.dx", 1.0).set("time.t_end", 60.0)
print(scene.check())
res = slipfront.run(scene, models=["continuum"], out=opts.out, force=True)
c = res["continuum"]
print("status:", res.status, "| t* = %.2f, t^ = %.2f" % (c.events["t_star"], c.events["t_hat"]))

snaps = c.snapshots
fig, (ax_v, ax_f) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
im = ax_v.pcolormesh(c.x, snaps["t"], np.log10(np.abs(snaps["v"]) + 1e-6), shading="auto")
fig.colorbar(im, ax=ax_v, label="log10 |v|")
ax_v.set(xlabel="x", ylabel="t", title="slip rate")
ax_f.plot(c.series["t"], c.series["drive_force"])
ax_f.axvline(c.events["t_star"], ls="--", c="k", lw=0.8, label="t*")
ax_f.set(xlabel="t", ylabel="F", title="drive force")
ax_f.legend()
fig.savefig(Path(opts.out) / "fig1.png", dpi=80)
print("figure:", Path(opts.out) / "fig1.png")
