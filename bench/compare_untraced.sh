#!/usr/bin/env bash
# The weaver without a trace against a record of bench/compare_weave.sh.
#
#   bench/compare_untraced.sh DIR [--bin PATH] [--rules "reliable extended"]
#
# compare_weave.sh always passes --trace, and a traced weave computes every candidate's
# properties; an untraced one may take shortcuts that must not change the result (the
# reliable selection's branch and bound, select/bounded.hpp). This runs BIN (default
# build/bin/stcweave) on every input of DIR/inputs.txt that DIR did not skip, without
# --trace, and compares the written mesh and the report (timings and paths stripped, as
# compare_weave.sh does) with DIR's byte for byte. Writes into DIR.untraced; exit 0 when
# every file is identical.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
dir=${1:?usage: compare_untraced.sh DIR [--bin PATH] [--rules LIST]}
shift
bin="$root/build/bin/stcweave"
rules_list="reliable extended"
while [[ $# -gt 0 ]]; do
  case $1 in
    --bin) bin=$2; shift 2 ;;
    --rules) rules_list=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 1 ;;
  esac
done
[[ -f $dir/inputs.txt ]] || { echo "$dir/inputs.txt missing: record DIR with compare_weave.sh" >&2; exit 1; }
out="$dir.untraced"
rm -rf "$out"
mkdir -p "$out"
cp "$bin" "$out/stcweave.bin"
bin="$out/stcweave.bin"
diffs=0
runs=0
while read -r name file; do
  for rules in $rules_list; do
    base="$out/$name.$rules"
    [[ -f $dir/$name.$rules.skipped ]] && continue
    set +e
    "$bin" mesh "$file" -o "$base.vtk" --rules "$rules" --report "$base.json" -q 2>/dev/null
    rc=$?
    set -e
    runs=$((runs + 1))
    expected=$(head -1 "$dir/$name.$rules.rc")
    [[ $rc == "$expected" ]] || { echo "DIFF  $name $rules exit $rc, recorded $expected"; diffs=$((diffs + 1)); }
    if [[ -f $base.json ]]; then
      python3 "$here/strip_report.py" "$base.json"
    fi
    for ext in vtk json; do
      a="$dir/$name.$rules.$ext"
      b="$base.$ext"
      if [[ -f $a || -f $b ]] && ! cmp -s "$a" "$b"; then
        echo "DIFF  $name.$rules.$ext"
        diffs=$((diffs + 1))
      fi
    done
  done
done <"$dir/inputs.txt"
echo "$runs runs without --trace, $diffs files differ from $dir"
[[ $diffs -eq 0 ]]
