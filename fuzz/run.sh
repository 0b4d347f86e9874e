#!/usr/bin/env bash
# Runs every fuzz target for SECONDS (default 60) each, seeded from the project's test programs.
# Needs cargo-fuzz (`cargo install cargo-fuzz`); on a stable toolchain RUSTC_BOOTSTRAP=1 lets it use the
# nightly flags it needs. Findings land in fuzz/artifacts/<target>/; turn each into a regression test.
#   fuzz/run.sh [SECONDS] [TARGET…]
set -euo pipefail
cd "$(dirname "$0")"
secs=${1:-60}; shift || true
targets=${*:-parse run engines emit verify}
export RUSTC_BOOTSTRAP=1
for t in $targets; do
  mkdir -p "corpus/$t"
  if [ "$t" != emit ] && [ "$t" != verify ]; then
    find ../tests ../samples -name '*.nc' -size -64k -exec cp {} "corpus/$t/" \; 2>/dev/null || true
  fi
  echo "== $t: ${secs}s"
  cargo fuzz run -O "$t" "corpus/$t" -- -max_total_time="$secs" -max_len=4096 -timeout=10 2>&1 \
    | grep -E '^(#[0-9]+ +DONE|Done|==[0-9]+==|SUMMARY|artifact_prefix|Test unit written)' || true
done
echo "artifacts (findings):"; find artifacts -type f 2>/dev/null || true
