#!/usr/bin/env bash
# Compares the outputs of two fmsvm binaries, byte for byte, on every program under tests/, samples/
# and the shared corpus (../shared/corpus) in every mode: literal and resolved output, four output
# dialects, --verify, stats (text and JSON), plot (SVG), check, ir, and the lathe dialects on the
# turning programs; the exit code, standard output and standard error of each run too, every
# subcommand's --help, every built-in dialect shown (with its cycles and launcher) and every
# control's parameters. For a change that must not change what fmsvm writes (a refactor):
#   benches/same-output.sh OLD_BINARY NEW_BINARY
# Every output goes into a folder of its own (a DPRNT record beside its output, never beside the
# program). Prints one line per difference and a summary; exits 1 when anything differs.
set -uo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
# Both called fmsvm (the help names the binary as it was called).
mkdir -p "$work/old-bin" "$work/new-bin"
cp "$1" "$work/old-bin/fmsvm"; cp "$2" "$work/new-bin/fmsvm"
old=$work/old-bin/fmsvm; new=$work/new-bin/fmsvm
export SOURCE_DATE_EPOCH=1700000000
programs=$(find "$here/tests" "$here/samples" "$here/../shared/corpus" -name '*.nc' 2>/dev/null | sort)
runs=0; differ=0

# Runs "$@" with each binary in its own folder (the same path, so messages naming files agree) and
# compares the exit code, standard output, standard error and every file written.
compare() {
  local label=$1; shift
  for side in old new; do
    rm -rf "$work/run"; mkdir -p "$work/run"
    local bin=$old; [ $side = new ] && bin=$new
    (cd "$work/run" && timeout 120 "$bin" "$@" > stdout 2> stderr; echo $? > exit)
    rm -rf "$work/$side"; mv "$work/run" "$work/$side"
  done
  runs=$((runs + 1))
  if ! diff -r "$work/old" "$work/new" > /dev/null; then
    differ=$((differ + 1))
    echo "DIFFERS: $label: $*"
    diff -r "$work/old" "$work/new" | head -5
  fi
}

for cmd in "" run check ir stats params post dialects dnc plot lsp dap; do
  compare "help $cmd" $cmd --help
done

compare "dialects" dialects
for d in fanuc iso linuxcnc fms3000 mayak600t nc31 fanuc0itd sinumerik802d fagor8035t haaslathe n33; do
  compare "dialects --show $d" dialects --show "$d"
  compare "dialects --cycles $d" dialects --cycles "$d"
  compare "dialects --launcher $d" dialects --launcher "$d"
done
for c in fanuc-0i haas nct fms3000 fanuc-0i-t fanuc-30i haas-lathe; do
  compare "params $c" params --show --control "$c"
done

for f in $programs; do
  name=$(basename "$f"); lib=$(dirname "$f")
  lathe=""
  case "$f" in */lathe/*|*/haas*) lathe=1 ;; esac
  if [ -n "$lathe" ]; then
    for d in fanuc0itd mayak600t nc31 sinumerik802d fagor8035t haaslathe; do
      compare "$name $d" run "$f" --lib "$lib" --machine lathe --dialect "$d" -o out.nc
    done
    compare "$name lathe literal" run "$f" --lib "$lib" --machine lathe -o out.nc --verify
    compare "$name lathe stats" stats "$f" --lib "$lib" --machine lathe --json -o report.json
    continue
  fi
  compare "$name literal" run "$f" --lib "$lib" -o out.nc
  compare "$name resolve" run "$f" --lib "$lib" --resolve -o out.nc --verify
  for d in fms3000 linuxcnc iso n33; do
    compare "$name $d" run "$f" --lib "$lib" --dialect "$d" -o out.nc
  done
  compare "$name verify" run "$f" --lib "$lib" -o out.nc --verify
  compare "$name stats" stats "$f" --lib "$lib" -o report.txt
  compare "$name stats json" stats "$f" --lib "$lib" --json -o report.json
  compare "$name plot" plot "$f" --lib "$lib" -o p.svg
  compare "$name check" check "$f" --lib "$lib"
  compare "$name ir" ir "$f" --lib "$lib"
  compare "$name interp" run "$f" --lib "$lib" --engine interp -o out.nc
done
echo "$runs runs compared, $differ differ"
[ "$differ" = 0 ]
