#!/usr/bin/env python3
"""Check that every "docs/model.md §n" / "model.md §n" citation in the repository resolves to a section
heading of docs/model.md (issue 9: the specification lives in the repository). Exit 1 and list the
dangling citations otherwise. Usage: check_citations.py [REPO_ROOT]"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
model = (root / "docs" / "model.md").read_text(encoding="utf-8")
sections = set(re.findall(r"^#+ §([0-9]+(?:\.[0-9]+)*)\b", model, flags=re.M))
files = subprocess.run(["git", "ls-files"], cwd=root, capture_output=True, text=True, check=True).stdout.split()
bad, count = [], 0
for f in files:
    if not re.search(r"\.(hpp|cpp|py|toml|sh|md|txt|in)$", f):
        continue
    text = (root / f).read_text(encoding="utf-8", errors="replace")
    for m in re.finditer(r"model\.md §\s?([0-9]+(?:\.[0-9]+)*)", text):
        count += 1
        if m.group(1) not in sections:
            line = text.count("\n", 0, m.start()) + 1
            bad.append(f"{f}:{line}: §{m.group(1)} is not a section of docs/model.md")
    if f != "scripts/check_citations.py" and ("MODEL §" in text or "MODEL.md" in text):
        bad.append(f"{f}: cites MODEL.md, which is not in the repository (cite docs/model.md §n)")
print(f"{count} citations of docs/model.md checked against {len(sections)} sections")
for b in bad:
    print(b, file=sys.stderr)
sys.exit(1 if bad else 0)
