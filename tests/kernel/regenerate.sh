#!/usr/bin/env bash
# Remakes every .moves of the kernel tests from its LinuxCNC twin (.ngc) with the stand-alone
# interpreter: `rs274 -t tool.tbl -g NAME.ngc`, reduced by kmoves.py (ncmotion.py's reduction, with
# arcs in every plane and the tool length offset applied; see its header).
# Needs `rs274` (Debian: apt-get install linuxcnc-uspace). The committed .moves are the test data:
# tests and CI never need LinuxCNC. A twin rs274 refuses stops this script.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }
shopt -s nullglob
for ngc in "$here"/*.ngc "$here"/linuxcnc/*.ngc "$here"/../textbook/*.ngc; do
  name=${ngc%.ngc}
  folder=$(dirname "$ngc")
  # The textbook's twins without expected motion stay so (the corpus keeps those for acceptance checks).
  case "$ngc" in */textbook/*) [ -f "$name.moves" ] || continue ;; esac
  table=$here/tool.tbl
  [ -f "$folder/tool.tbl" ] && table=$folder/tool.tbl
  trace=$(mktemp)
  if ! (cd "$folder" && rs274 -t "$table" -g "$ngc" < /dev/null > "$trace" 2> "$trace.err"); then
    echo "$(basename "$name"): rs274 refused it:" >&2
    cat "$trace.err" >&2
    rm -f "$trace" "$trace.err"
    exit 1
  fi
  python3 "$here/kmoves.py" "$trace" > "$name.moves.new"
  rm -f "$trace" "$trace.err"
  if cmp -s "$name.moves.new" "$name.moves" 2>/dev/null; then
    echo "$(basename "$name"): unchanged ($(wc -l < "$name.moves") moves)"
    rm "$name.moves.new"
  else
    mv "$name.moves.new" "$name.moves"
    echo "$(basename "$name"): UPDATED"
  fi
done
