#!/usr/bin/env bash
# Weave time against hexes on k x k x k boxes, for one or more stcweave binaries side by side
# in one run, with the fitted exponent (least squares of log time on log hexes).
#
#   bench/weave_scaling.sh [--rules reliable|extended] [--sizes "8 12 16 ..."] [--repeat N]
#                          [--untangle] [--stages] BIN [BIN ...]
#
# Each run is `stcweave mesh box.obj --no-untangle` (positioning is not what is measured);
# the weave time is the report's seconds.weave, the least of N runs (default 3; the machine
# is shared). Prints one row per size and binary (binary index, k, hexes, weave seconds, then
# the total seconds of that same run), then per binary and stage (weave, total) the exponent
# fitted over all sizes and over the sizes of 4,096 hexes and more. The total includes
# recovery, validation, quality and writing, but no untangling (`--no-untangle`; `--untangle`
# runs the default positioning instead). With `--stages`, every stage of the report's seconds
# of the kept runs is also listed and fitted.
set -euo pipefail
rules=reliable
sizes="8 12 16 20 24 32"
repeat=3
untangle=--no-untangle
stages=0
bins=()
while [[ $# -gt 0 ]]; do
  case $1 in
    --rules) rules=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    --untangle) untangle=; shift ;;
    --stages) stages=1; shift ;;
    *) bins+=("$1"); shift ;;
  esac
done
[[ ${#bins[@]} -gt 0 ]] || { echo "usage: weave_scaling.sh [--rules R] [--sizes S] BIN..." >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rows="$tmp/rows.txt"
: >"$rows"
for k in $sizes; do
  "${bins[0]}" generate box "$k" "$k" "$k" -o "$tmp/box$k.obj" -q
  for i in "${!bins[@]}"; do
    for ((r = 0; r < repeat; ++r)); do
      "${bins[$i]}" mesh "$tmp/box$k.obj" -o "$tmp/out.vtk" --rules "$rules" $untangle -q \
        --report "$tmp/r.json"
      python3 - "$tmp/r.json" "$i" "$k" >>"$tmp/runs.txt" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["seconds"]
print(sys.argv[2], sys.argv[3], r["hexes"], s["weave"], s["total"], json.dumps(s, separators=(",", ":")))
EOF
    done
    sort -k4 -g "$tmp/runs.txt" | head -1 >>"$rows"
    rm -f "$tmp/runs.txt"
    tail -1 "$rows" | cut -d" " -f1-5
  done
done
python3 - "$rows" "$stages" "${bins[@]}" <<'EOF'
import json, math, sys
rows = [l.split() for l in open(sys.argv[1])]
stages = sys.argv[2] == "1"
bins = sys.argv[3:]
seconds = [json.loads(r[5]) for r in rows]
names = ["weave", "total"]
if stages:
  names = [k for k in seconds[0] if k != "total"] + ["total"]
  print("binary k hexes " + " ".join(names))
  for r, s in zip(rows, seconds):
    print(r[0], r[1], r[2], " ".join(f"{s.get(k, 0):.3f}" for k in names))
for i, b in enumerate(bins):
  for stage in names:
    allpts = [(int(r[2]), s[stage]) for r, s in zip(rows, seconds)
              if int(r[0]) == i and s.get(stage, 0) > 0]
    for label, pts in (("all", allpts), (">=4096", [p for p in allpts if p[0] >= 4096])):
        if len(pts) < 2:
            continue
        xs = [math.log(h) for h, _ in pts]
        ys = [math.log(t) for _, t in pts]
        n = len(xs)
        mx, my = sum(xs) / n, sum(ys) / n
        slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        print(f"{b}: {stage} time ~ hexes^{slope:.2f} over {n} sizes ({label}: "
              f"{pts[0][0]}..{pts[-1][0]} hexes, {pts[0][1]:.3f}..{pts[-1][1]:.3f} s)")
EOF
