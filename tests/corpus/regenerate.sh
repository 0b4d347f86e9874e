#!/usr/bin/env bash
# Regenerates the expected motion of the corpus from LinuxCNC's stand-alone interpreter.
# Needs `rs274` (Debian: apt-get install linuxcnc-uspace) and ../../../shared/tools/ncmotion.py.
# The .moves files committed here are what this printed; tests and CI never need LinuxCNC.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
ncmotion=${NCMOTION:-$here/../../../shared/tools/ncmotion.py}
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }
for ngc in "$here"/*.ngc; do
  name=${ngc%.ngc}
  rs274 -g "$ngc" < /dev/null > "$name.trace"
  python3 "$ncmotion" moves "$name.trace" > "$name.moves.new"
  if cmp -s "$name.moves.new" "$name.moves"; then
    echo "$(basename "$name"): unchanged ($(wc -l < "$name.moves") moves)"
    rm "$name.moves.new"
  else
    mv "$name.moves.new" "$name.moves"
    echo "$(basename "$name"): UPDATED"
  fi
  rm -f "$name.trace"
done
