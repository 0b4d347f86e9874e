#!/usr/bin/env bash
# Compares fmsvm (interpreter and JIT) with LinuxCNC's stand-alone interpreter `rs274 -g` on the same
# programs, in one run on this machine: the corpus hemisphere and sine (their `.ngc` twins), and the
# hemisphere at finer raster steps. Prints generated moves/blocks, median wall times over RUNS runs and
# the per-block ratios. LinuxCNC prints a canonical trace, not G-code, so both sides are counted per
# generated move. Needs: cargo, python3, rs274 (Debian/Ubuntu: apt-get install linuxcnc-uspace).
#   benches/compare.sh [RUNS]      (default 5)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
runs=${1:-5}
command -v rs274 >/dev/null || { echo "rs274 not found: apt-get install linuxcnc-uspace" >&2; exit 1; }
cargo build --release --quiet --manifest-path "$here/Cargo.toml"
bin="$here/target/release/fmsvm"
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
corpus="$here/tests/corpus"

# Programs: name, macro program, LinuxCNC twin.
cp "$corpus/003-hemisphere.nc" "$work/hemisphere.nc"; cp "$corpus/003-hemisphere.ngc" "$work/hemisphere.ngc"
cp "$corpus/003-sine.nc" "$work/sine.nc"; cp "$corpus/003-sine.ngc" "$work/sine.ngc"
for step in 0.25 0.1; do
  sed "s/#2=#2+1/#2=#2+$step/; s/#2=#2-1/#2=#2-$step/; s/#1=#1+1/#1=#1+$step/g" "$corpus/003-hemisphere.nc" > "$work/hemisphere-$step.nc"
  sed "s/\[#2+1\]/[#2+$step]/; s/\[#2-1\]/[#2-$step]/; s/\[#1+1\]/[#1+$step]/g" "$corpus/003-hemisphere.ngc" > "$work/hemisphere-$step.ngc"
done

# Median wall time in seconds of a command over $runs runs (output discarded).
median() {
  python3 - "$runs" "$@" <<'PY'
import subprocess, sys, time
runs, cmd = int(sys.argv[1]), sys.argv[2:]
ts = []
for _ in range(runs):
    t = time.perf_counter()
    subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    ts.append(time.perf_counter() - t)
ts.sort()
print(f"{ts[len(ts) // 2]:.6f}")
PY
}

printf '%-18s %9s %9s %10s %10s %10s %12s %12s %8s %8s\n' program moves blocks rs274_s interp_s jit_s rs274_blk/s jit_blk/s jit/rs274 interp/rs274
for name in sine hemisphere hemisphere-0.25 hemisphere-0.1; do
  nc="$work/$name.nc"; ngc="$work/$name.ngc"
  rs274 -g "$ngc" < /dev/null > "$work/$name.trace" 2>/dev/null
  moves=$(grep -cE 'STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED' "$work/$name.trace")
  "$bin" run "$nc" -q --engine jit > "$work/$name.flat"
  blocks=$(grep -cvE '^(%|O[0-9])' "$work/$name.flat")
  python3 "$here/../shared/tools/ncmotion.py" diff "$work/$name.flat" "$work/$name.trace" > /dev/null \
    || { echo "$name: motion differs from rs274" >&2; exit 1; }
  t_rs=$(median rs274 -g "$ngc")
  t_in=$(median "$bin" run "$nc" -q --engine interp)
  t_jit=$(median "$bin" run "$nc" -q --engine jit)
  python3 - "$name" "$moves" "$blocks" "$t_rs" "$t_in" "$t_jit" <<'PY'
import sys
name, moves, blocks = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rs, it, jt = (float(x) for x in sys.argv[4:7])
per_rs, per_it, per_jt = rs / moves, it / blocks, jt / blocks
print(f"{name:<18} {moves:9d} {blocks:9d} {rs:10.4f} {it:10.4f} {jt:10.4f} {1/per_rs:12.0f} {1/per_jt:12.0f} {per_rs/per_jt:8.1f} {per_rs/per_it:8.1f}")
PY
done
echo "Times are whole processes (start-up included), medians of $runs runs; ratios are per generated move."
