#!/usr/bin/python3
"""Check that a report.md is non-empty UTF-8 and that every image it names exists and is a non-empty PNG;
exit 1 otherwise."""
import os
import re
import sys


def main(argv):
    if len(argv) != 2:
        print("usage: check_report.py REPORT.md", file=sys.stderr)
        return 2
    report = argv[1]
    root = os.path.dirname(os.path.abspath(report))
    with open(report, "rb") as f:
        raw = f.read()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        print(f"check_report: {report} is not UTF-8: {e}", file=sys.stderr)
        return 1
    if not text.strip():
        print(f"check_report: {report} is empty", file=sys.stderr)
        return 1
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    bad = []
    for rel in images:
        path = os.path.join(root, rel)
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            bad.append(f"{rel}: missing or empty")
            continue
        with open(path, "rb") as f:
            if f.read(8) != b"\x89PNG\r\n\x1a\n":
                bad.append(f"{rel}: not a PNG")
    for b in bad:
        print(f"check_report: {b}", file=sys.stderr)
    if not images:
        print("check_report: the report names no plot", file=sys.stderr)
        return 1
    print(f"check_report: {len(images)} plots named in {report}, all present and non-empty" if not bad else
          f"check_report: {len(bad)} of {len(images)} plots bad")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
