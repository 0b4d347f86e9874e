#!/usr/bin/env bash
# Remakes the LinuxCNC round-trip data of tests/dialects.rs: for each program of programs.txt,
# fmsvm's `--dialect linuxcnc` output (NAME.ngc) and the motion LinuxCNC's stand-alone interpreter
# makes of it (`rs274 -g NAME.ngc`, reduced by ../kernel/kmoves.py: NAME.moves). The test checks that
# fmsvm still writes NAME.ngc byte for byte and that NAME.moves is fmsvm's resolved motion.
# Needs `rs274` (Debian: apt-get install linuxcnc-uspace) and a built fmsvm (FMSVM=path, default the
# release binary). The committed files are the test data: tests and CI never need LinuxCNC.
# rs274 needs a tool table (`rs274 -t FILE`, any; a wrapper script named rs274 that adds it does).
# Last re-traced with rs274 2.9.0~pre1+git20230208.f1270d6ed7 after the first block began stating
# the modes (G94 G40 G49 G80 G54): every NAME.moves came out unchanged.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
fmsvm=${FMSVM:-$root/target/release/fmsvm}
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }
[ -x "$fmsvm" ] || { echo "no fmsvm at $fmsvm: cargo build --release, or FMSVM=…" >&2; exit 1; }
grep -v '^#' "$here/programs.txt" | while read -r name path flags; do
  [ -n "$name" ] || continue
  # shellcheck disable=SC2086
  (cd "$root" && "$fmsvm" run "$path" $flags --dialect linuxcnc -q --no-comments -o "$here/$name.ngc")
  trace=$(mktemp)
  # The control's own setup where the resolved output relies on it (NAME.var: LinuxCNC's
  # parameters, as the program's G10 set them for fmsvm, which resolves them away).
  var=()
  [ -f "$here/$name.var" ] && var=(-v "$name.var")
  if ! (cd "$here" && rs274 "${var[@]}" -g "$name.ngc" < /dev/null > "$trace" 2> "$trace.err"); then
    echo "$name: rs274 refused fmsvm's LinuxCNC output:" >&2
    cat "$trace.err" >&2
    exit 1
  fi
  python3 "$root/tests/kernel/kmoves.py" "$trace" > "$here/$name.moves"
  rm -f "$trace" "$trace.err"
  echo "$name: $(wc -l < "$here/$name.moves") moves"
done
