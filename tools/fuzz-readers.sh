#!/usr/bin/env bash
# Builds the libFuzzer targets of the point-cloud readers (clang, ASan + UBSan) in their own build dir
# and runs each for SECONDS (default 60), seeded with the fixtures in tests/data/outline_io.
# Not part of `make test`. Exit status 1 if any reader crashed; the crashing inputs are kept in
# $BUILD/artifacts and reproduce with: $BUILD/bin/fuzz_read_<reader> <file>
#
#   tools/fuzz-readers.sh [SECONDS] [text|pcd|ply ...]
#   HG_FUZZ_BUILD=dir  build directory (default build-fuzz)   HG_FUZZ_JOBS=n  build jobs (default 2)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer fuzz-readers "$0" "$@"

root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
shift || true
readers=("$@")
[[ ${#readers[@]} -gt 0 ]] || readers=(text pcd ply)
build=${HG_FUZZ_BUILD:-$root/build-fuzz}
jobs=${HG_FUZZ_JOBS:-2}
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "fuzz-readers: SECONDS must be a whole number, got '$seconds'" >&2; exit 2; }
command -v clang++ >/dev/null || { echo "fuzz-readers: clang++ not found (apt-get install clang)" >&2; exit 2; }

mkdir -p "$build"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DHG_FUZZ=ON -DHG_BUILD_TESTS=OFF >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log" >&2; exit 1; }
targets=()
for r in "${readers[@]}"; do targets+=("fuzz_read_$r"); done
cmake --build "$build" --target "${targets[@]}" -j "$jobs"

seeds_of() {  # fixture files a reader should start from
  case $1 in
    text) ls "$root"/tests/data/outline_io/*.{xyz,csv,txt} 2>/dev/null ;;
    pcd) ls "$root"/tests/data/outline_io/*.pcd ;;
    ply) ls "$root"/tests/data/outline_io/*.ply ;;
  esac
}

status=0
summary=()
mkdir -p "$build/artifacts"
for r in "${readers[@]}"; do
  corpus="$build/corpus/$r"
  mkdir -p "$corpus"
  seeds_of "$r" | while read -r f; do cp -n "$f" "$corpus/"; done
  log="$build/fuzz_$r.log"
  echo "fuzz-readers: $r for ${seconds}s (log $log)"
  before=$(ls "$build/artifacts" | grep -c "^$r-" || true)
  set +e
  "$build/bin/fuzz_read_$r" "$corpus" -dict="$root/cloud_io/fuzz/$r.dict" -max_total_time="$seconds" \
    -max_len=16384 -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$build/artifacts/$r-" -print_final_stats=1 >"$log" 2>&1
  rc=$?
  set -e
  after=$(ls "$build/artifacts" | grep -c "^$r-" || true)
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
  if [[ $rc -ne 0 || $after -gt $before ]]; then
    status=1
    summary+=("$r: FAILED (exit $rc), $((after - before)) new artifact(s) in $build/artifacts; see $log")
    grep -m3 -E "ERROR|runtime error|SUMMARY" "$log" >&2 || true
  else
    summary+=("$r: ok, $runs inputs in ${seconds}s, $cov, corpus $(ls "$corpus" | wc -l) files")
  fi
done
printf 'fuzz-readers: %s\n' "${summary[@]}"
exit $status
