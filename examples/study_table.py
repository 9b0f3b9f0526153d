"""Reading a study's table: the friction-law study of docs/studies.md (the discrete model's steady friction
against the continuum as N grows), run on a few points, its table read as arrays (and a pandas DataFrame when
pandas is installed) and plotted: the error against N.

    python3 examples/study_table.py [--out DIR] [--small]"""
import argparse
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import slipfront  # noqa: E402

HERE = Path(__file__).resolve().parent
args = argparse.ArgumentParser(description=__doc__.splitlines()[0])
args.add_argument("--out", default="out/examples/study")
args.add_argument("--small", action="store_true")
opts = args.parse_args()
out = Path(opts.out)
out.mkdir(parents=True, exist_ok=True)

counts = [100, 1000, 10000] if opts.small else [10, 100, 1000, 10000, 100000]
study_file = out / "friction_law_N.toml"
study_file.write_text(f'''study = "friction_law_N"
kind = "friction_law"
scene = "{HERE.parent / 'configs' / 'friction_law.toml'}"
set = ['models=["continuum","discrete"]', "drive.points={5 if opts.small else 13}", "time.steps={400 if opts.small else 4000}"]
seeds = {2 if opts.small else 8}
[vary]
"discrete.contacts_per_site" = {counts}
''')
st = slipfront.study(study_file, out=out)
print(st, "|", ", ".join(st.tables))
table = st.tables["friction_law_error"]
for name in table:
    print("%-14s %s" % (name, table.descriptions[name]))
try:
    print(table.to_pandas())
except ImportError:
    print(table.to_records())
fig, ax = plt.subplots(figsize=(5, 4), constrained_layout=True)
for col in ("total", "random", "bias"):
    ax.loglog(table["N"], abs(table[col]), "o-", label=col)
ax.set(xlabel="contacts per site N", ylabel="friction error", title=st.name)
ax.legend()
fig.savefig(out / "study.png", dpi=80)
print("figure:", out / "study.png")
