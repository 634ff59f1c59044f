#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in a build directory of their own that compiles only
# them (the top CMakeLists.txt with -DHG_FUZZ=ON) and runs each for SECONDS (default 60), seeded with its
# fixtures. Exit status 0 when every target ran clean, 1 if any crashed (the crashing inputs are kept in
# $BUILD/artifacts and reproduce with: $BUILD/bin/BINARY FILE), 2 for a bad command line or no clang.
# `make test` runs every target for 30 s (CTest fuzz_build, fuzz_TARGET; label fuzz).
#
#   tools/fuzz-readers.sh [--build-only | --no-build] [SECONDS] [TARGET ...]
#   TARGET: text pcd ply (the point-cloud readers), station (hg-station's request handling); default: every
#           target of the table below
#   HG_FUZZ_BUILD=dir  build directory (default build-fuzz)   HG_FUZZ_JOBS=n  build jobs (default 2)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer fuzz-readers "$0" "$@"

root=$(cd "$(dirname "$0")/.." && pwd)

# The fuzz targets: name, executable (a CMake target of the fuzz build), dictionary ("-": none), seed files
# (globs relative to the source tree). A new target is one line here and its CMake target in the top
# CMakeLists.txt's HG_FUZZ branch.
TARGETS=(
  "text fuzz_read_text outline_io/fuzz/text.dict tests/data/outline_io/*.xyz tests/data/outline_io/*.csv tests/data/outline_io/*.txt"
  "pcd fuzz_read_pcd outline_io/fuzz/pcd.dict tests/data/outline_io/*.pcd"
  "ply fuzz_read_ply outline_io/fuzz/ply.dict tests/data/outline_io/*.ply"
  "station fuzz_station_request - station/fuzz/seeds/*"
)

die() { echo "fuzz-readers: $*" >&2; exit 2; }
target_line() {  # the table's line of target $1
  local line
  for line in "${TARGETS[@]}"; do [[ ${line%% *} == "$1" ]] && { echo "$line"; return 0; }; done
  return 1
}

build_step=1 run_step=1
case "${1:-}" in
  --build-only) run_step=0; shift ;;
  --no-build) build_step=0; shift ;;
esac
seconds=60
if [[ $# -gt 0 && "$1" =~ ^[0-9]+$ ]]; then seconds=$1; shift; fi
names=("$@")
[[ ${#names[@]} -gt 0 ]] || for line in "${TARGETS[@]}"; do names+=("${line%% *}"); done
for n in "${names[@]}"; do
  [[ $n == -* || $n =~ ^[0-9] ]] && die "SECONDS must be a whole number and come first, got '$n' (see --help)"
  target_line "$n" >/dev/null || die "unknown target '$n' (known: $(printf '%s ' "${TARGETS[@]%% *}"))"
done
build=${HG_FUZZ_BUILD:-$root/build-fuzz}
jobs=${HG_FUZZ_JOBS:-2}

if [[ $build_step == 1 ]]; then
  command -v clang++ >/dev/null || die "clang++ not found (tools/install-deps.sh installs clang)"
  mkdir -p "$build"
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ -DHG_FUZZ=ON >"$build/configure.log" 2>&1 ||
    { cat "$build/configure.log" >&2; exit 1; }
  executables=()
  for n in "${names[@]}"; do read -r _ exe _ <<<"$(target_line "$n")"; executables+=("$exe"); done
  cmake --build "$build" --target "${executables[@]}" -j "$jobs"
fi
[[ $run_step == 1 ]] || exit 0

status=0
summary=()
mkdir -p "$build/artifacts"
for n in "${names[@]}"; do
  read -r _ exe dict seeds <<<"$(target_line "$n")"
  [[ -x "$build/bin/$exe" ]] || die "$build/bin/$exe is not built (run without --no-build)"
  corpus="$build/corpus/$n"
  mkdir -p "$corpus"
  (cd "$root" && shopt -s nullglob && for f in $seeds; do cp -n "$f" "$corpus/"; done)
  dict_arg=()
  [[ $dict == - ]] || dict_arg=(-dict="$root/$dict")
  log="$build/fuzz_$n.log"
  echo "fuzz-readers: $n for ${seconds}s (log $log)"
  before=$(ls "$build/artifacts" | grep -c "^$n-" || true)
  set +e
  "$build/bin/$exe" "$corpus" "${dict_arg[@]}" -max_total_time="$seconds" -max_len=16384 -timeout=10 \
    -rss_limit_mb=2048 -artifact_prefix="$build/artifacts/$n-" -print_final_stats=1 >"$log" 2>&1
  rc=$?
  set -e
  after=$(ls "$build/artifacts" | grep -c "^$n-" || true)
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 || true)
  if [[ $rc -ne 0 || $after -gt $before ]]; then
    status=1
    summary+=("$n: FAILED (exit $rc), $((after - before)) new artifact(s) in $build/artifacts; see $log")
    grep -m3 -E "ERROR|runtime error|SUMMARY|uncaught" "$log" >&2 || true
  else
    summary+=("$n: ok, $runs inputs in ${seconds}s, $cov, corpus $(ls "$corpus" | wc -l) files")
  fi
done
printf 'fuzz-readers: %s\n' "${summary[@]}"
exit $status
