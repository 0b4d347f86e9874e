#!/usr/bin/env bash
# Runs every row of cases.tsv through an fmsvm binary and prints PASS/FAIL per row with the first difference.
#   FMSVM=path/to/fmsvm ./check.sh [ID-PREFIX]      (default FMSVM: ../../target/release/fmsvm)
# For a motion row the flat output is compared with the `moves` file by ncmotion.py and the DPRNT output
# (--print) with the `printed` file via printnorm.py. When ncmotion cannot read the flat output (a canned cycle
# left in it) and rs274 is installed, the flat output is also run through rs274 and that motion compared, as a
# diagnostic only: the row still FAILs.
# Exit 0 when every row passes. This script is a tool for people; the Rust tests are separate.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
fmsvm=${FMSVM:-$here/../../target/release/fmsvm}
ncmotion=${NCMOTION:-$here/../../../shared/tools/ncmotion.py}
only=${1:-}
[ -x "$fmsvm" ] || { echo "no fmsvm binary at $fmsvm (set FMSVM)" >&2; exit 2; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
failed=0
while IFS=$'\t' read -r id kind nc options exit alarm moves printed orig rs274; do
  case "$id" in ''|'#'*) continue ;; esac
  case "$id" in "$only"*) ;; *) continue ;; esac
  opts=()
  [ "$options" != - ] && read -r -a opts <<< "$options"
  rm -f "$scratch"/out.*
  "$fmsvm" run "${opts[@]}" "$here/$nc" -o "$scratch/out.nc" --print "$scratch/out.prn" \
    > "$scratch/stdout" 2> "$scratch/stderr"
  rc=$?
  first=$(grep -m1 -E '^(error|warning)' "$scratch/stderr")
  why=""
  if [ "$rc" != "$exit" ]; then
    why="exit $rc, expected $exit${first:+ ($first)}"
  elif [ "$alarm" != - ] && ! grep -q "$alarm" "$scratch/stderr"; then
    why="stderr has no '$alarm'${first:+ (first line: $first)}"
  fi
  if [ -z "$why" ] && [ "$moves" != - ]; then
    if ! d=$(python3 "$ncmotion" diff "$scratch/out.nc" "$here/$moves" 2>&1); then
      why="moves: $(echo "$d" | tr '\n' ' ')"
      if echo "$d" | grep -q 'must be resolved' && command -v rs274 >/dev/null; then
        (cd "$scratch" && rs274 -g out.nc < /dev/null > out.trace 2> /dev/null)
        why="$why[via rs274 on the flat output: $(python3 "$ncmotion" diff "$scratch/out.trace" "$here/$moves" 2>&1 | tr '\n' ' ')]"
      fi
    fi
  fi
  if [ -z "$why" ] && [ "$printed" != - ]; then
    if [ -f "$scratch/out.prn" ]; then
      python3 "$here/printnorm.py" prn "$scratch/out.prn" > "$scratch/out.printed"
    else
      : > "$scratch/out.printed"
    fi
    if ! d=$(diff "$here/$printed" "$scratch/out.printed"); then
      why="printed: $(echo "$d" | head -4 | tr '\n' ' ')"
    fi
  fi
  if [ -z "$why" ]; then
    echo "PASS $id (exit $rc${first:+; $first})"
  else
    echo "FAIL $id: $why"
    failed=1
  fi
done < "$here/cases.tsv"
exit $failed
