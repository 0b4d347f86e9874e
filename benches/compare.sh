#!/usr/bin/env bash
# Compares fmsvm (interpreter and JIT) with LinuxCNC's stand-alone interpreter `rs274 -g` on the same
# programs, in one run on this machine: the corpus hemisphere and sine (their `.ngc` twins), and the
# hemisphere at finer raster steps down to the fine hemisphere (step 0.05, 4 004 007 blocks). Prints
# generated moves/blocks, median wall times over RUNS runs and the per-block ratios. LinuxCNC prints a
# canonical trace, not G-code, so both sides are counted per generated move. Then, on the fine
# hemisphere: resolved and dialect output and --verify against literal output; the JIT against the
# hand-written ceiling (criterion); a CAM file; and the compile of a long macro program.
# Needs: cargo, python3, rs274 (Debian/Ubuntu: apt-get install linuxcnc-uspace).
#   benches/compare.sh [RUNS]      (default 5; FINE=0 leaves out the fine hemisphere against rs274,
#                                   which takes rs274 about a minute a run; CRITERION=0 the ceiling)
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
for step in 0.25 0.1 0.05; do
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
names="sine hemisphere hemisphere-0.25 hemisphere-0.1"
[ "${FINE:-1}" = 0 ] || names="$names hemisphere-0.05"
for name in $names; do
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

# The fine hemisphere's output kinds, each to a file (JIT): literal (its plain blocks written by a
# second thread), resolved, the FMS-3000 and LinuxCNC dialects, and --verify on top of literal and of
# resolved output (the reader beside the writer), each against the run it verifies.
fine="$work/hemisphere-0.05.nc"
t_lit=$(median "$bin" run "$fine" -q -o "$work/fine.out")
t_res=$(median "$bin" run "$fine" -q --resolve -o "$work/fine.out")
t_fms=$(median "$bin" run "$fine" -q --dialect fms3000 -o "$work/fine.out")
t_lcn=$(median "$bin" run "$fine" -q --dialect linuxcnc -o "$work/fine.out")
t_rver=$(median "$bin" run "$fine" -q --resolve --verify -o "$work/fine.out")
t_lver=$(median "$bin" run "$fine" -q --verify -o "$work/fine.out")
python3 - "$t_lit" "$t_res" "$t_fms" "$t_lcn" "$t_rver" "$t_lver" <<'PY'
import sys
lit, res, fms, lcn, rver, lver = (float(x) for x in sys.argv[1:7])
print("\nfine hemisphere (4 004 007 blocks), JIT, to a file:")
print(f"  literal                  {lit:8.3f} s")
print(f"  --resolve                {res:8.3f} s  {res/lit:5.2f}x literal   (target <= 1.3)")
print(f"  --dialect fms3000        {fms:8.3f} s  {fms/lit:5.2f}x literal   (target <= 1.3)")
print(f"  --dialect linuxcnc       {lcn:8.3f} s  {lcn/lit:5.2f}x literal   (target <= 1.3)")
print(f"  --resolve --verify       {rver:8.3f} s  {rver/res:5.2f}x --resolve (target <= 1.3)")
print(f"  --verify (literal)       {lver:8.3f} s  {lver/lit:5.2f}x literal")
PY

# The JIT against the honest hand-written ceiling (criterion, in-process, output to a sink).
if [ "${CRITERION:-1}" != 0 ]; then
  crit=$(cd "$here" && cargo bench --quiet --bench expand -- 'expand/fine-hemisphere/(jit-pipelined|native-direct)$' 2>/dev/null \
    | grep -E '^expand/fine-hemisphere/(jit-pipelined|native-direct)|^ *time:' || true)
  python3 - "$crit" <<'PY'
import re, sys
text, name, times = sys.argv[1], None, {}
unit = {"ns": 1e-9, "µs": 1e-6, "us": 1e-6, "ms": 1e-3, "s": 1.0}
for line in text.splitlines():
    m = re.match(r"^(expand/fine-hemisphere/\S+)", line)
    if m:
        name = m.group(1).split("/")[-1]
    m = re.search(r"time:\s*\[\S+ \S+ (\S+) (\S+) \S+ \S+\]", line)
    if m and name:
        times[name] = float(m.group(1)) * unit[m.group(2)]
        name = None
if "jit-pipelined" in times and "native-direct" in times:
    j, n = times["jit-pipelined"], times["native-direct"]
    print(f"\nfine hemisphere in-process (criterion medians): jit-pipelined {j*1e3:.1f} ms, native-direct {n*1e3:.1f} ms: JIT {n/j:.2f}x the ceiling (target >= 0.8)")
else:
    print("\nfine hemisphere in-process: criterion gave no figures")
PY
fi

# A CAM-size file (no macro statement: it runs straight from the file, driver/src/flat.rs): CAM_LINES lines
# of G1 X Y Z F (default 5 000 000), through fmsvm and through rs274, with the peak memory of each.
cam_lines=${CAM_LINES:-5000000}
python3 - "$cam_lines" "$work/cam.nc" "$work/cam.ngc" <<'PY'
import random, sys
n, nc, ngc = int(sys.argv[1]), sys.argv[2], sys.argv[3]
random.seed(1)
with open(nc, "w") as a, open(ngc, "w") as b:
    a.write("%\nO1000 (CAM)\n"); b.write("%\n")
    for f in (a, b):
        f.write("G21 G90 G17\nG0 X0 Y0 Z5\n")
    for i in range(n):
        line = "G1 X%.3f Y%.3f Z%.3f F%d\n" % (random.uniform(-100, 100), random.uniform(-100, 100), random.uniform(-10, 0), 800 + (i % 3) * 200)
        a.write(line); b.write(line)
    for f in (a, b):
        f.write("M30\n%\n")
PY
peak() {  # peak resident set size of a command, kB
  python3 - "$@" <<'PY'
import resource, subprocess, sys
subprocess.run(sys.argv[1:], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
PY
}
t_rs=$(median rs274 -g "$work/cam.ngc")
t_fm=$(median "$bin" run "$work/cam.nc" -q -o "$work/cam.out")
t_fr=$(median "$bin" run "$work/cam.nc" -q --resolve -o "$work/cam.out")
m_rs=$(peak rs274 -g "$work/cam.ngc")
m_fm=$(peak "$bin" run "$work/cam.nc" -q -o "$work/cam.out")
python3 - "$cam_lines" "$t_rs" "$t_fm" "$t_fr" "$m_rs" "$m_fm" <<'PY'
import sys
n = int(sys.argv[1]); rs, fm, fr = (float(x) for x in sys.argv[2:5]); mrs, mfm = (int(x) for x in sys.argv[5:7])
print(f"\ncam file, {n} lines of G1 X Y Z F:")
print(f"  rs274 -g          {rs:8.3f} s  {n/rs/1e6:6.2f} M lines/s  peak {mrs/1024:7.1f} MB")
print(f"  fmsvm run         {fm:8.3f} s  {n/fm/1e6:6.2f} M lines/s  peak {mfm/1024:7.1f} MB  ({rs/fm:.1f}x rs274)")
print(f"  fmsvm --resolve   {fr:8.3f} s  {n/fr/1e6:6.2f} M lines/s")
PY

# A long program with macros (the issue-14 compile target): MACRO_LINES lines (default 300 000) of
# `#1=#1*0.5+c`, `G1 X[#1/100000+c] Y[#1*0.5-c] F1000` and `G1 Z[#1/3+1]`, one distinct constant c
# per three lines (100 000 in all), compiled by `fmsvm check` (nothing runs).
macro_lines=${MACRO_LINES:-300000}
python3 - "$macro_lines" "$work/macro.nc" <<'PY'
import sys
n, path = int(sys.argv[1]), sys.argv[2]
out = ["O1", "#1=0"]
k = 0
while len(out) < n - 1:
    k += 1
    c = "%d.%03d" % (k // 1000, k % 1000)
    out += ["#1=#1*0.5+%s" % c, "G1 X[#1/100000+%s] Y[#1*0.5-%s] F1000" % (c, c), "G1 Z[#1/3+1]"]
out.append("M30")
open(path, "w").write("\n".join(out) + "\n")
PY
t_ck=$(median "$bin" check "$work/macro.nc")
m_ck=$(peak "$bin" check "$work/macro.nc")
python3 - "$macro_lines" "$t_ck" "$m_ck" <<'PY'
import sys
n, t, m = int(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
print(f"\nmacro program, {n} lines, {n // 3} distinct constants, compiled:")
print(f"  fmsvm check       {t:8.3f} s  peak {m/1024:7.1f} MB  ({m*1024/n:.0f} bytes a line; target < 0.15 s, < 40 MB)")
PY

# The CAM file with one macro line after its O line (`#1=1`), so that it is compiled, not run from the file:
# every line is then a plain line the compiler decodes straight from the text into a literal block
# (ARCHITECTURE.md, "Compiling a long program"). Compiled by `fmsvm check`, then run to a file.
sed '2a #1=1' "$work/cam.nc" > "$work/cam-macro.nc"
t_cc=$(median "$bin" check "$work/cam-macro.nc")
m_cc=$(peak "$bin" check "$work/cam-macro.nc")
t_cr=$(median "$bin" run "$work/cam-macro.nc" -q -o "$work/cam-macro.out")
cmp -s "$work/cam.out" "$work/cam-macro.out" || { echo "cam file with a macro line: output differs" >&2; exit 1; }
python3 - "$cam_lines" "$t_cc" "$m_cc" "$t_cr" "$(stat -c %s "$work/cam-macro.nc")" <<'PY'
import sys
n, tc, m, tr, size = int(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
print(f"\ncam file with a macro line, {n} lines, compiled:")
print(f"  fmsvm check       {tc:8.3f} s  peak {m/1024:7.1f} MB  ({(m*1024-size)/n:.0f} bytes a line beyond the text)")
print(f"  fmsvm run         {tr:8.3f} s  {n/tr/1e6:6.2f} M lines/s")
PY
