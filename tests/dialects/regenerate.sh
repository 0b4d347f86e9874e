#!/usr/bin/env bash
# Remakes the LinuxCNC round-trip data of tests/dialects.rs: for each program of programs.txt,
# fmsvm's `--dialect linuxcnc` output (NAME.ngc) and the motion LinuxCNC's stand-alone interpreter
# makes of it (`rs274 -g NAME.ngc`, reduced by ../kernel/kmoves.py: NAME.moves). The test checks that
# fmsvm still writes NAME.ngc byte for byte and that NAME.moves is fmsvm's resolved motion.
# Needs `rs274` (Debian: apt-get install linuxcnc-uspace) and a built fmsvm (FMSVM=path, default the
# release binary). The committed files are the test data: tests and CI never need LinuxCNC.
# The .ngc files were last written by fmsvm without rs274 at hand, when the first move stopped
# writing axes the program had not positioned (`G0 X0 Y0`, was `G0 X0 Y0 Z0`: LinuxCNC starts at
# Z0) and returns became `G91 G28`/`G91 G30` (LinuxCNC's G28/G30 positions are machine zero as rs274
# starts, which references-at-zero.toml declares): the same motion for rs274 by construction, not
# yet re-traced. Run this script where rs274 installs to re-trace them.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
fmsvm=${FMSVM:-$root/target/release/fmsvm}
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }
[ -x "$fmsvm" ] || { echo "no fmsvm at $fmsvm: cargo build --release, or FMSVM=…" >&2; exit 1; }
grep -v '^#' "$here/programs.txt" | while read -r name path flags; do
  [ -n "$name" ] || continue
  # shellcheck disable=SC2086
  (cd "$root" && "$fmsvm" run "$path" $flags --dialect linuxcnc -q -o "$here/$name.ngc")
  trace=$(mktemp)
  if ! (cd "$here" && rs274 -g "$name.ngc" < /dev/null > "$trace" 2> "$trace.err"); then
    echo "$name: rs274 refused fmsvm's LinuxCNC output:" >&2
    cat "$trace.err" >&2
    exit 1
  fi
  python3 "$root/tests/kernel/kmoves.py" "$trace" > "$here/$name.moves"
  rm -f "$trace" "$trace.err"
  echo "$name: $(wc -l < "$here/$name.moves") moves"
done
