#!/bin/sh
# Regenerates the LinuxCNC traces the tests of runtime/kernel/src/cycles.rs were written from.
#
# Needs LinuxCNC's stand-alone interpreter `rs274` (Debian package linuxcnc-uspace; the traces here
# were made with 2.9.0~pre1+git20230208.f1270d6ed7). For every NAME.ngc beside this script it writes
# NAME.trace: the canonical calls that matter to a cycle (moves, dwells, spindle, program stop) with
# rs274's line counter and N field cut off, then any error rs274 reported.
# The expected steps in the tests were pasted from these files; after regenerating, `git diff` shows
# whether LinuxCNC changed its mind.
set -eu
cd "$(dirname "$0")"
for ngc in *.ngc; do
    name=${ngc%.ngc}
    out=$(rs274 -g "$ngc" 2>&1 || true)
    {
        printf '%s\n' "$out" |
            sed -n 's/^ *[0-9][0-9]* N[^ ]* *//p' |
            grep -E '^(STRAIGHT_TRAVERSE|STRAIGHT_FEED|DWELL|START_SPINDLE|STOP_SPINDLE|ORIENT_SPINDLE|PROGRAM_STOP)' || true
        printf '%s\n' "$out" | grep -v '^ *[0-9][0-9]* N' | grep -v '^executing$' | sed 's/^/error: /' || true
    } > "$name.trace"
done
