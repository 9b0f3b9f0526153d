#!/usr/bin/python3
"""Accuracy of compare::estimate (docs/robustness.md §3): for a set of scenes, the estimate printed by
`slipfront check` (steps per model, peak memory, run time) against a real run of `slipfront run`
(steps from /<model> attribute `steps`, peak resident memory from /usr/bin/time, wall time from
/meta wall_seconds). Prints one table row per case; the ratio columns are estimate / measured.

Usage: /usr/bin/python3 scripts/estimate_accuracy.py [--slipfront build/apps/slipfront] [--quick]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import h5py

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (name, config, overrides)
CASES = [
    ("fig1 continuum explicit", "configs/fig1.toml", ['models=["continuum"]']),
    ("fig1 both, count N=1e3, explicit", "configs/fig1.toml", ["discrete.contacts_per_site=1000"]),
    ("fig1 both, count, implicit dt 0.02", "configs/fig1.toml",
     ["discrete.contacts_per_site=1000", "time.integrator=implicit", "time.dt=0.02"]),
    ("fig1 continuum adaptive", "configs/fig1.toml", ['models=["continuum"]', "time.integrator=adaptive"]),
    ("fig1 adaptive rtol 1e-4", "configs/fig1.toml",
     ['models=["continuum"]', "time.integrator=adaptive", "time.rtol=1e-4", "time.atol=1e-6"]),
    ("fig1 count w=0.1 uniform, 64 bins", "configs/fig1.toml",
     ['models=["discrete"]', "discrete.threshold=uniform", "discrete.width=0.1", "time.t_end=60"]),
    ("fig1 count noise off, 256 bins", "configs/fig1.toml",
     ['models=["discrete"]', "discrete.threshold=gaussian", "discrete.width=0.1", "discrete.bins=256",
      "discrete.noise=false", "time.t_end=60"]),
    ("fig1 agent N=1e3", "configs/fig1.toml",
     ['models=["discrete"]', "discrete.representation=agent", "discrete.contacts_per_site=1000"]),
    ("fig1 agent N=1e4 t_end 60", "configs/fig1.toml",
     ['models=["discrete"]', "discrete.representation=agent", "discrete.contacts_per_site=10000", "time.t_end=60"]),
    ("fig1 naive N=100 t_end 30", "configs/fig1.toml",
     ['models=["discrete"]', "discrete.representation=naive", "discrete.contacts_per_site=100", "time.t_end=30"]),
    ("fig1 snapshots every 0.01", "configs/fig1.toml", ['models=["continuum"]', "output.snapshot_dt=0.01"]),
    ("fig1 L=3000 t_end 20 both", "configs/fig1.toml", ["bulk.length=3000", "time.t_end=20"]),
    ("homogeneous_front", "configs/homogeneous_front.toml", []),
    ("homogeneous_front adaptive", "configs/homogeneous_front.toml", ['models=["continuum"]', "time.integrator=adaptive"]),
    ("homogeneous_front count w=0.1, 64 bins", "configs/homogeneous_front.toml",
     ['models=["discrete"]', "discrete.threshold=uniform", "discrete.width=0.1", "time.t_end=5"]),
    ("homogeneous_front agent N=1e3", "configs/homogeneous_front.toml",
     ['models=["discrete"]', "discrete.representation=agent", "discrete.contacts_per_site=1000"]),
    ("spring_block", "configs/spring_block.toml", []),
    ("spring_block adaptive", "configs/spring_block.toml", ['models=["continuum"]', "time.integrator=adaptive"]),
    ("friction_law (sweep)", "configs/friction_law.toml", []),
    ("friction_law agent N=1e3", "configs/friction_law.toml",
     ['models=["discrete"]', "discrete.representation=agent", "discrete.contacts_per_site=1000"]),
    ("velocity_step (history)", "configs/velocity_step.toml", []),
    # contact aging and a normal-load profile (issue 40; compare/estimate.cpp add_aging_cost, turnover_fraction)
    ("fig1_aging mean_field t_end 200", "configs/fig1_aging.toml", ['models=["mean_field"]', "time.t_end=200"]),
    ("fig1_aging closure t_end 200", "configs/fig1_aging.toml", ['models=["continuum"]', "time.t_end=200"]),
    ("slide_hold_slide (agent N=1e4 with aging)", "configs/slide_hold_slide.toml", []),
    ("friction_law_aging agent N=1e3", "configs/friction_law_aging.toml", ["discrete.contacts_per_site=1000"]),
    ("fig1_load_profile discrete", "configs/fig1_load_profile.toml", ['models=["discrete"]']),
    # the leap integrator (the discrete and mean_field models under time.integrator = adaptive) and the implicit
    # integrator's error control (issue 36: time.leap_epsilon and time.implicit_tolerance in the estimate)
    ("fig1 discrete leap", "configs/fig1.toml", ['models=["discrete"]', "time.integrator=adaptive"]),
    ("fig1 discrete leap eps 0.02", "configs/fig1.toml",
     ['models=["discrete"]', "time.integrator=adaptive", "time.leap_epsilon=0.02"]),
    ("fig1 discrete leap tol 1e-10", "configs/fig1.toml",
     ['models=["discrete"]', "time.integrator=adaptive", "time.implicit_tolerance=1e-10"]),
    ("fig1 mean_field leap w=0.1", "configs/fig1.toml",
     ['models=["mean_field"]', "time.integrator=adaptive", "discrete.threshold=uniform", "discrete.width=0.1"]),
    ("homogeneous_front discrete leap", "configs/homogeneous_front.toml",
     ['models=["discrete"]', "time.integrator=adaptive"]),
    ("homogeneous_front discrete leap eps 0.05", "configs/homogeneous_front.toml",
     ['models=["discrete"]', "time.integrator=adaptive", "time.leap_epsilon=0.05"]),
    ("spring_block discrete leap", "configs/spring_block.toml", ['models=["discrete"]', "time.integrator=adaptive"]),
    ("fig1_strip discrete leap", "configs/fig1_strip.toml", ['models=["discrete"]', "time.integrator=adaptive"]),
    ("fig1 implicit dt 0.02 tol 1e-6", "configs/fig1.toml",
     ['models=["continuum"]', "time.integrator=implicit", "time.dt=0.02", "time.implicit_tolerance=1e-6"]),
]
QUICK = {"fig1 continuum explicit", "fig1 continuum adaptive", "spring_block", "friction_law (sweep)",
         "homogeneous_front"}

UNITS = {"s": 1.0, "min": 60.0, "h": 3600.0}
MEM = {"KiB": 1024.0, "MiB": 1024.0 ** 2, "GiB": 1024.0 ** 3}


def estimate(slipfront, config, overrides):
    args = [slipfront, "check", config] + [a for o in overrides for a in ("--set", o)]
    out = subprocess.run(args, capture_output=True, text=True, check=True).stdout
    steps, seconds, memory = {}, None, None
    for line in out.splitlines():
        m = re.match(r"#\s+(continuum|discrete|mean_field): (\S+) steps .*~([\d.e+]+) (s|min|h)$", line)
        if m:
            steps[m.group(1)] = float(m.group(2))
        m = re.match(r"#\s+memory: ~([\d.e+]+) (KiB|MiB|GiB) peak", line)
        if m:
            memory = float(m.group(1)) * MEM[m.group(2)]
        m = re.match(r"#\s+run time: ~([\d.e+]+) (s|min|h) ", line)
        if m:
            seconds = float(m.group(1)) * UNITS[m.group(2)]
    return steps, memory, seconds


def measure(slipfront, config, overrides, out):
    args = ["/usr/bin/time", "-f", "%M", slipfront, "run", config, "--out", out, "--force", "--quiet"]
    args += [a for o in overrides for a in ("--set", o)]
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(r.stderr)
    rss = float(r.stderr.strip().splitlines()[-1]) * 1024.0
    with h5py.File(os.path.join(out, "results.h5"), "r") as f:
        wall = float(f["meta"].attrs["wall_seconds"])
        steps = {m: float(f[m].attrs["steps"]) for m in ("continuum", "discrete", "mean_field")
                 if m in f and "steps" in f[m].attrs}
    return steps, rss, wall


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--slipfront", default=os.path.join(ROOT, "build", "apps", "slipfront"))
    p.add_argument("--quick", action="store_true", help="five fast cases only")
    p.add_argument("--only", default="", help="only the cases whose name contains this text (e.g. 'leap')")
    a = p.parse_args()
    print(f"{'case':38s} {'model':9s} {'steps est':>10s} {'measured':>10s} {'ratio':>6s}   "
          f"{'mem est':>9s} {'peak RSS':>9s} {'ratio':>6s}   {'time est':>8s} {'wall':>8s} {'ratio':>6s}")
    ratios = {"steps": [], "memory": [], "time": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name, config, overrides in CASES:
            if (a.quick and name not in QUICK) or a.only not in name:
                continue
            cfg = os.path.join(ROOT, config)
            est_steps, est_mem, est_s = estimate(a.slipfront, cfg, overrides)
            steps, rss, wall = measure(a.slipfront, cfg, overrides, os.path.join(tmp, "run"))
            first = True
            for model, n in est_steps.items():
                measured = steps.get(model, float("nan"))
                ratio = n / measured if measured else float("nan")
                ratios["steps"].append((name + " " + model, ratio))
                if first:
                    ratios["memory"].append((name, est_mem / rss))
                    ratios["time"].append((name, est_s / wall))
                    print(f"{name:38s} {model:9s} {n:10.4g} {measured:10.4g} {ratio:6.2f}   "
                          f"{est_mem / 2**20:7.1f}Mi {rss / 2**20:7.1f}Mi {est_mem / rss:6.2f}   "
                          f"{est_s:8.3g} {wall:8.3g} {est_s / wall:6.2f}")
                else:
                    print(f"{'':38s} {model:9s} {n:10.4g} {measured:10.4g} {ratio:6.2f}")
                first = False
            sys.stdout.flush()
    for k, v in ratios.items():
        vals = [r for _, r in v if r == r]
        if vals:
            print(f"{k}: estimate/measured from {min(vals):.2f} to {max(vals):.2f} over {len(vals)} cases")


if __name__ == "__main__":
    main()
