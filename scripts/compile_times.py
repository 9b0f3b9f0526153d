#!/usr/bin/env python3
"""Compile time of each translation unit of the libraries and the program (issue 17's table).

Recompiles every unit of build/compile_commands.json under core/, continuum/, discrete/, compare/, studies/ and
apps/ one at a time (output to a scratch file, so the build is untouched) and prints the slowest.
Usage: scripts/compile_times.py [--build build] [--source DIR] [--top 10] [--filter SUBSTRING]
One core, sequential: the numbers compare between two trees timed on the same quiet machine.
"""
import argparse, json, os, shlex, subprocess, sys, tempfile, time

ap = argparse.ArgumentParser()
ap.add_argument("--build", default="build")
ap.add_argument("--top", type=int, default=10)
ap.add_argument("--filter", default="")
ap.add_argument("--source", default=None, help="source tree of that build (default: this repository)")
a = ap.parse_args()
root = a.source or os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
db = json.load(open(os.path.join(a.build, "compile_commands.json")))
rows = []
with tempfile.TemporaryDirectory() as scratch:
    for e in db:
        rel = os.path.relpath(e["file"], root)
        if rel.split(os.sep)[0] not in ("core", "continuum", "discrete", "compare", "studies", "apps") or a.filter not in rel:
            continue
        args = shlex.split(e["command"]) if "command" in e else e["arguments"]
        if "-o" in args:
            args[args.index("-o") + 1] = os.path.join(scratch, "unit.o")
        t0 = time.perf_counter()
        subprocess.run(args, cwd=e["directory"], check=True)
        rows.append((time.perf_counter() - t0, rel))
rows.sort(reverse=True)
print(f"{'seconds':>8}  unit   (total {sum(r[0] for r in rows):.1f} s over {len(rows)} units)")
for t, rel in rows[: a.top]:
    print(f"{t:8.2f}  {rel}")
