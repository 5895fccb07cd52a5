#!/usr/bin/env python3
"""Rewrite a stcweave report in place without what differs between identical runs.

    bench/strip_report.py REPORT.json

Drops the input and output paths and every timing (any "seconds" or "*_seconds" key, at any
depth), then writes the rest sorted, so that two runs that made the same mesh give the same
bytes. Used by bench/compare_weave.sh and bench/compare_untraced.sh.
"""
import json
import sys


def timeless(x):
    if isinstance(x, dict):
        return {k: timeless(v) for k, v in x.items()
                if k != "seconds" and not k.endswith("_seconds")}
    if isinstance(x, list):
        return [timeless(v) for v in x]
    return x


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: strip_report.py REPORT.json")
    path = sys.argv[1]
    with open(path) as f:
        report = json.load(f)
    for key in ("input", "output"):
        report.pop(key, None)
    with open(path, "w") as f:
        json.dump(timeless(report), f, indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
