#!/usr/bin/env bash
# Remakes tests/lathe/*.moves from the LinuxCNC twins (.ngc) with the stand-alone interpreter
# (`rs274 -t tool.tbl -g NAME.ngc`, reduced by ../kernel/kmoves.py), and checks that fmsvm's own
# `--dialect linuxcnc --machine lathe` output of NAME.nc moves the same under rs274 (within the
# 0.001 mm of the output: the trace's arc centres may differ in the fourth decimal).
# Needs `rs274` (Debian: apt-get install linuxcnc-uspace) and a built fmsvm (FMSVM, default
# target/debug/fmsvm). The committed .moves are the test data: tests and CI never need LinuxCNC.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
fmsvm=${FMSVM:-$root/target/debug/fmsvm}
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
trace() { (cd "$here" && rs274 -t tool.tbl -g "$1" < /dev/null 2> "$tmp/err") | python3 "$here/../kernel/kmoves.py" /dev/stdin; }
for ngc in "$here"/*.ngc; do
  name=${ngc%.ngc}
  trace "$ngc" > "$name.moves.new"
  if cmp -s "$name.moves.new" "$name.moves" 2>/dev/null; then
    echo "$(basename "$name"): unchanged ($(wc -l < "$name.moves") moves)"; rm "$name.moves.new"
  else
    mv "$name.moves.new" "$name.moves"; echo "$(basename "$name"): UPDATED"
  fi
  # fmsvm's own output of the Fanuc program (T0101 written `T1 M6 G43`), through rs274.
  # NAME.toml, where there is one, holds the tools' nose radius and tip (the twin sets them by G10 L1).
  offsets=(); [ -f "$name.toml" ] && offsets=(--offsets "$name.toml" --comp-style linuxcnc)
  "$fmsvm" run "$name.nc" --dialect linuxcnc --machine lathe --start-point "X0 Z0" "${offsets[@]}" -q -o "$tmp/out.ngc"
  cp "$tmp/out.ngc" "$here/.fmsvm-out.ngc"
  trace "$here/.fmsvm-out.ngc" > "$tmp/fmsvm.moves"
  rm -f "$here/.fmsvm-out.ngc"
  python3 - "$tmp/fmsvm.moves" "$name.moves" <<'PY'
import sys
a = [l.split() for l in open(sys.argv[1]) if l.strip()]
b = [l.split() for l in open(sys.argv[2]) if l.strip()]
assert len(a) == len(b), f"{len(a)} moves against the twin's {len(b)}"
for x, y in zip(a, b):
    assert x[0] == y[0] and all(abs(float(p) - float(q)) <= 0.0011 for p, q in zip(x[1:], y[1:]) if p[0] != 'G'), (x, y)
print("  fmsvm's linuxcnc output moves as the twin under rs274")
PY
done
