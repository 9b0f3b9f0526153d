#!/usr/bin/env python3
"""Speed of this checkout against an earlier commit, measured in one run (issue 9: "speed unchanged").

Builds BASE (a commit, default HEAD~1) in a temporary git worktree, then runs the same commands with
both builds, alternating (base, new, base, new, ...) so that both see the same machine load, and prints
for each the best wall time of each build and the ratio new/base. Commands: `slipfront run` on fig1
with each integrator (continuum alone, and with the discrete model alongside), and the work-precision
and discrete benchmarks in their --quick / SLIPFRONT_BENCH_QUICK form (whole process).

Usage: /usr/bin/python3 scripts/compare_speed.py [BASE] [--repeat R] [--keep] [--base-tree DIR] [--only REGEX]
  --base-tree DIR  a checkout of BASE already configured in DIR/build (used as is, never removed)
  --only REGEX     run only the cases whose name matches (e.g. --only adaptive)
  --cpu            time each command by its CPU time (user + system) instead of its wall time: steadier on a
                   shared machine (the commands are single-threaded)
"""
import argparse
import os
import pathlib
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

root = pathlib.Path(__file__).resolve().parent.parent
ap = argparse.ArgumentParser()
ap.add_argument("base", nargs="?", default="HEAD~1")
ap.add_argument("--repeat", type=int, default=5)
ap.add_argument("--keep", action="store_true", help="keep the base worktree and build")
ap.add_argument("--base-tree", help="an existing checkout of BASE, configured in its build/ (kept)")
ap.add_argument("--only", help="run only the cases whose name matches this regular expression")
ap.add_argument("--cpu", action="store_true", help="CPU time (user + system) of each command instead of wall time")
args = ap.parse_args()

rev = subprocess.run(["git", "rev-parse", "--short", args.base], cwd=root, capture_output=True, text=True,
                     check=True).stdout.strip()
base = pathlib.Path(args.base_tree) if args.base_tree else pathlib.Path(tempfile.gettempdir()) / f"slipfront-speed-base-{rev}"
targets = ["slipfront", "bench_work_precision", "bench_discrete_implicit", "bench_strip_work_precision"]
if args.base_tree:
    subprocess.run(["cmake", "--build", str(base / "build"), "--target", *targets], check=True,
                   stdout=subprocess.DEVNULL)
elif not (base / "build" / "apps" / "slipfront").exists():
    if base.exists():
        shutil.rmtree(base)
    subprocess.run(["git", "worktree", "add", "--detach", str(base), rev], cwd=root, check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "-S", str(base), "-B", str(base / "build"), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                    "-DSLIPFRONT_BUILD_TESTS=OFF"], check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(base / "build"), "--target", *targets], check=True,
                   stdout=subprocess.DEVNULL)
subprocess.run(["cmake", "--build", str(root / "build"), "--target", *targets], check=True, stdout=subprocess.DEVNULL)

scratch = pathlib.Path(tempfile.mkdtemp(prefix="slipfront-speed-"))
fig1 = str(root / "configs" / "fig1.toml")
fig1_strip = str(root / "configs" / "fig1_strip.toml")
cases = {
    "fig1 continuum, explicit": ["run", fig1, "--set", 'models=["continuum"]'],
    "fig1 continuum, adaptive": ["run", fig1, "--set", 'models=["continuum"]', "--set", "time.integrator=adaptive"],
    "fig1 continuum, implicit dt 0.02": ["run", fig1, "--set", 'models=["continuum"]', "--set",
                                         "time.integrator=implicit", "--set", "time.dt=0.02"],
    "fig1 both models (count N=1e4), explicit": ["run", fig1],
    "fig1 count N=1000, implicit dt 0.02": ["run", fig1, "--set", 'models=["discrete"]', "--set",
                                            "time.integrator=implicit", "--set", "time.dt=0.02", "--set",
                                            "discrete.contacts_per_site=1000"],
    "fig1 continuum, adaptive rtol 1e-4": ["run", fig1, "--set", 'models=["continuum"]', "--set",
                                           "time.integrator=adaptive", "--set", "time.rtol=1e-4"],
    "fig1_strip continuum, adaptive": ["run", fig1_strip, "--set", 'models=["continuum"]', "--set",
                                       "time.integrator=adaptive"],
}
# The implicit integrator's error control (issue 10, time.implicit_tolerance, default 1e-3) re-linearises
# every step; these cases switch it off in the new build only (the base has no such key), to separate
# its cost from the rest.
new_only = {}  # case -> arguments given to the new build only
for name in [k for k in cases if "implicit" in k]:
    cases[name + ", new without error control"] = cases[name]
    new_only[name + ", new without error control"] = ["--set", "time.implicit_tolerance=0"]

benches = {
    "bench_work_precision --quick": (["bench_work_precision", "--quick"], {}),
    "bench_discrete_implicit (quick)": (["bench_discrete_implicit"], {"SLIPFRONT_BENCH_QUICK": "1"}),
    "bench_strip_work_precision, adaptive rtol 1e-2 only": (["bench_strip_work_precision"],
                                                             {"SLIPFRONT_BENCH_ONLY": "1e-2"}),
}
if args.only:
    cases = {k: v for k, v in cases.items() if re.search(args.only, k)}
    benches = {k: v for k, v in benches.items() if re.search(args.only, k)}


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(cmd, env=None):
    clock = cpu_children if args.cpu else time.perf_counter
    t0 = clock()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=scratch,
                   env={**os.environ, **(env or {})})
    return clock() - t0


rows = []
for name, argv in list(cases.items()) + [(k, v) for k, v in benches.items()]:
    best = {"base": float("inf"), "new": float("inf")}
    reps = args.repeat if name in cases else max(1, args.repeat // 2)
    for _ in range(reps):
        for which, tree in (("base", base), ("new", root)):
            if name in cases:
                args_ = argv + (new_only.get(name, []) if which == "new" else [])
                cmd = [str(tree / "build" / "apps" / "slipfront"), *args_, "--out", str(scratch / which), "--force",
                       "--quiet"]
                env = None
            else:
                cmd = [str(tree / "build" / "bench" / argv[0][0]), *argv[0][1:]]
                env = argv[1]
            best[which] = min(best[which], timed(cmd, env))
    rows.append((name, best["base"], best["new"]))
    print(f"{name:45s} base {best['base']:8.3f} s   new {best['new']:8.3f} s   new/base {best['new'] / best['base']:.3f}",
          flush=True)
shutil.rmtree(scratch, ignore_errors=True)
if not args.keep and not args.base_tree:
    subprocess.run(["git", "worktree", "remove", "--force", str(base)], cwd=root, stdout=subprocess.DEVNULL)
print(f"base = {rev}, new = this checkout; best of {args.repeat} alternating runs (benchmarks: {max(1, args.repeat // 2)})"
      f"{', CPU time' if args.cpu else ', wall time'}")
