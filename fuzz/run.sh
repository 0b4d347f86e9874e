#!/usr/bin/env bash
# Runs every fuzz target for SECONDS (default 60) each, seeded from the project's test programs.
# Needs cargo-fuzz (`cargo install cargo-fuzz`); on a stable toolchain RUSTC_BOOTSTRAP=1 lets it use the
# nightly flags it needs. Findings land in fuzz/artifacts/<target>/; turn each into a regression test.
#   fuzz/run.sh [SECONDS] [TARGET…]
set -euo pipefail
cd "$(dirname "$0")"
secs=${1:-60}; shift || true
targets=${*:-parse run engines emit verify settings readback outline frame neutral launcher}
export RUSTC_BOOTSTRAP=1
for t in $targets; do
  mkdir -p "corpus/$t"
  case "$t" in
    parse|run|engines|outline)
      find ../tests ../samples -name '*.nc' -size -64k -exec cp {} "corpus/$t/" \; 2>/dev/null || true ;;
    settings)
      # The first byte picks the reader: 0 profile, 1 parameters, 2 offsets, 3 commons, 4 points.
      i=0
      for f in ../dialects/*.toml ../docs/*.toml ../tests/*/*.toml; do
        [ -f "$f" ] || continue
        for k in 0 1 2; do { printf "\\$(printf %o $k)"; cat "$f"; } > "corpus/$t/$k-$i"; done
        i=$((i + 1))
      done ;;
    readback)
      # The first byte picks the dialect (the built-in ones in order, then the Н33-2М tape).
      i=0
      for f in ../tests/*/*.nc ../tests/dialects/*; do
        [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 16384 ] || continue
        { printf "\\$(printf %o $((i % 10)))"; cat "$f"; } > "corpus/$t/$i"
        i=$((i + 1))
      done ;;
  esac
  echo "== $t: ${secs}s"
  cargo fuzz run -O "$t" "corpus/$t" -- -max_total_time="$secs" -max_len=4096 -timeout=10 2>&1 \
    | grep -E '^(#[0-9]+ +DONE|Done|==[0-9]+==|SUMMARY|artifact_prefix|Test unit written)' || true
done
echo "artifacts (findings):"; find artifacts -type f 2>/dev/null || true
