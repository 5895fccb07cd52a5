#!/usr/bin/env bash
# Byte-for-byte regression check of the weaver through the CLI.
#
#   bench/compare_weave.sh DIR [--bin PATH] [--timeout S] [--shared N] [--weavable] [--no-trace]
#
# First invocation (DIR absent): runs `stcweave mesh` on data/lblock.obj, every input of
# bench/generated.manifest and the first N (default 40) inputs of bench/shared.manifest,
# under `--rules reliable` and `--rules extended`, and keeps in DIR, per run:
#   NAME.RULES.vtk    the written mesh
#   NAME.RULES.json   the report without timings and paths (hexes, quality, weave stats, ...)
#   NAME.RULES.trace  the --trace JSONL
#   NAME.RULES.rc     the exit code (and the first stderr line)
# A run over the time limit (default 60 s) is recorded as skipped. With --weavable, the shared
# inputs taken are those the manifest marks genus 0 without self-intersecting loops (the ones
# that reach the weaver), and lblock and the generated shapes are left out. With --no-trace the
# runs have no --trace (and no .trace files): a trace makes the weaver compute every candidate
# of every selection, so only these runs check the path a user without --trace gets (the
# candidates after the first computed in part: weave/src/select/bounded.hpp, candidates.hpp).
# Second invocation (DIR present): runs the same list into DIR.new and diffs every file
# against DIR (inputs skipped in DIR are skipped again). Exit 0 when every file is identical.
#
# Shared inputs live in ../shared/data (paths in the manifest are relative to bench/); they are
# read in place, never copied. Generated inputs are written to DIR/inputs by `stcweave generate`.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
dir=${1:?usage: compare_weave.sh DIR [--bin PATH] [--timeout S] [--shared N]}
shift
bin="$root/build/bin/stcweave"
limit=60
shared=40
weavable=0
trace=1
while [[ $# -gt 0 ]]; do
  case $1 in
    --bin) bin=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --shared) shared=$2; shift 2 ;;
    --weavable) weavable=1; shift ;;
    --no-trace) trace=0; shift ;;
    *) echo "unknown option $1" >&2; exit 1 ;;
  esac
done
[[ -x $bin ]] || { echo "no stcweave binary at $bin" >&2; exit 1; }

if [[ -d $dir ]]; then
  mode=compare
  out="$dir.new"
  rm -rf "$out"
else
  mode=record
  out="$dir"
fi
mkdir -p "$out/inputs"
# Run a copy, so that a rebuild during the run does not change the binary under it.
cp "$bin" "$out/stcweave.bin"
bin="$out/stcweave.bin"

# The input list: "NAME PATH" lines.
list="$out/inputs.txt"
: >"$list"
[[ $weavable -eq 1 ]] || echo "lblock $root/data/lblock.obj" >>"$list"
while [[ $weavable -eq 0 ]] && read -r spec _; do
  [[ $spec == generate:* ]] || continue
  rest=${spec#generate:}
  kind=${rest%%:*}
  arg=${rest#*:}
  name="gen_${kind}_${arg}"
  file="$out/inputs/$name.obj"
  if [[ $kind == box ]]; then
    IFS=x read -r a b c <<<"$arg"
    "$bin" generate box "$a" "$b" "$c" -o "$file" -q
  else
    "$bin" generate bar "$arg" -o "$file" -q
  fi
  echo "$name $file" >>"$list"
done < <(grep -v '^\s*#' "$here/generated.manifest" | grep -v '^\s*$')
count=0
while read -r path rest; do
  [[ $count -lt $shared ]] || break
  if [[ $weavable -eq 1 ]]; then
    [[ $rest == *"genus 0"* && $rest != *self-intersecting* ]] || continue
  fi
  count=$((count + 1))
  abs="$here/$path"
  [[ -f $abs ]] || { echo "missing shared input $abs (is ../shared/data there?)" >&2; continue; }
  name="shared_$(basename "$(dirname "$path")")_$(basename "$path")"
  echo "$name $abs" >>"$list"
done < <(grep -v '^\s*#' "$here/shared.manifest" | grep -v '^\s*$')

strip_report() {
  python3 "$here/strip_report.py" "$1"
}

runs=0
skipped=0
while read -r name file; do
  for rules in reliable extended; do
    base="$out/$name.$rules"
    if [[ $mode == compare && -f $dir/$name.$rules.skipped ]]; then
      touch "$base.skipped"
      skipped=$((skipped + 1))
      continue
    fi
    # In compare mode an input the baseline finished gets four times the limit (a loaded
    # machine must not turn into a difference).
    run_limit=$limit
    [[ $mode == compare ]] && run_limit=$((4 * limit))
    set +e
    trace_args=()
    [[ $trace -eq 1 ]] && trace_args=(--trace "$base.trace")
    timeout "$run_limit" "$bin" mesh "$file" -o "$base.vtk" --rules "$rules" --report "$base.json" \
      "${trace_args[@]}" -q 2>"$base.err"
    rc=$?
    set -e
    if [[ $rc -eq 124 ]]; then
      rm -f "$base.vtk" "$base.json" "$base.trace" "$base.err"
      touch "$base.skipped"
      skipped=$((skipped + 1))
      echo "skip  $name $rules (over ${run_limit} s)"
      continue
    fi
    # the output folder's name (in messages naming a written file) is not a difference
    { echo "$rc"; head -c 2000 "$base.err" | sed "s#$out/#DIR/#g"; } >"$base.rc"
    rm -f "$base.err"
    [[ -f $base.json ]] && strip_report "$base.json"
    runs=$((runs + 1))
    echo "done  $name $rules rc=$rc"
  done
done <"$list"
echo "$runs runs, $skipped skipped, into $out"

if [[ $mode == compare ]]; then
  bad=0
  files=0
  for f in "$dir"/*.vtk "$dir"/*.json "$dir"/*.trace "$dir"/*.rc; do
    [[ -e $f ]] || continue
    files=$((files + 1))
    g="$out/$(basename "$f")"
    if ! cmp -s "$f" "$g"; then
      echo "DIFFERS: $(basename "$f")"
      bad=$((bad + 1))
    fi
  done
  for g in "$out"/*.vtk "$out"/*.json "$out"/*.trace "$out"/*.rc; do
    [[ -e $g ]] || continue
    [[ -e $dir/$(basename "$g") ]] || { echo "NEW: $(basename "$g")"; bad=$((bad + 1)); }
  done
  echo "compared $files files of $runs runs: $bad differ"
  [[ $bad -eq 0 ]]
fi
