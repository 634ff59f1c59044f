#!/usr/bin/env bash
# hg-mcap against readers nobody here wrote (tests/foxglove/mcap_check.js: @mcap/core, ajv, @foxglove/schemas):
#  - the committed LCM logs (tests/data/**/*.lcmlog; types older than lcmtypes/ are written raw), and a log
#    of every current type recorded here with hg-lcm-send (3 rounds of random samples), each with zstd,
#    lz4 and no compression, small chunks (many chunks and message indexes);
#  - a corrupt log (two logs with garbage between them): reported, skipped, the rest intact;
#  - bad input: exit 2 (no file, not an LCM log, bad option), a failed write: exit 1.
# Runs in its own network namespace (it records the bus). Needs build/bin and build/npm (install-deps).
#   tests/foxglove/mcap_test.sh    (env HG_BIN_DIR, HG_NPM_DIR, HG_SOURCE_DIR)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
src="${HG_SOURCE_DIR:-$(cd "$here/../.." && pwd)}"
source "$src/tools/version.sh"
hg_answer mcap_test.sh "$0" "$@"
if [[ "${HG_IN_NETNS:-}" != "1" ]]; then exec "$src/tests/netns.sh" --own-pids "$0" "$@"; fi
bin="${HG_BIN_DIR:-$src/build/bin}"
export NODE_PATH="${HG_NPM_DIR:-$src/build/npm}/node_modules"
check="node $here/mcap_check.js"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
expect_rc() {  # expect_rc WANT WHAT COMMAND...
  local want=$1 what=$2 rc=0
  shift 2
  "$@" >"$tmp/out" 2>&1 || rc=$?
  if [[ $rc -ne $want ]]; then echo "FAIL: $what: exit $rc, expected $want"; cat "$tmp/out"; fail=1; else echo "ok: $what (exit $rc)"; fi
}

# A log of every current type.
"$src/tools/record" --channels 'HG_.*' "$tmp/fresh.lcmlog" >"$tmp/fresh.name" &
rec=$!
while [[ ! -s "$tmp/fresh.name" ]]; do kill -0 $rec; sleep 0.05; done
"$bin/hg-lcm-send" sample --type all --count 3 --rate 20 >/dev/null
sleep 1
kill -TERM $rec
wait $rec || true

logs=("$tmp/fresh.lcmlog")
while IFS= read -r f; do logs+=("$f"); done < <(find "$src/tests/data" -name '*.lcmlog' | sort)
for log in "${logs[@]}"; do
  for c in zstd lz4 none; do
    out="$tmp/$(basename "$log" .lcmlog)-$c.mcap"
    expect_rc 0 "hg-mcap $(basename "$log") --compression $c" \
      "$bin/hg-mcap" "$log" -o "$out" --compression $c --chunk-size 65536 --cell "$src/config/cell-sim.yaml"
    $check "$out" "$log" --expect-tf || fail=1
  done
done
# The fresh log must have exercised every type as JSON, not raw.
if grep -q "unknown type" <("$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/f.mcap" 2>&1); then
  echo "FAIL: the fresh log has messages of an unknown type"; fail=1
fi
# Decimation: a small max-points, and all points.
for n in 7 0; do
  expect_rc 0 "hg-mcap --max-points $n" "$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/mp$n.mcap" --max-points $n
  $check "$tmp/mp$n.mcap" "$tmp/fresh.lcmlog" --max-points $n || fail=1
done

# The base frame is the cell's frames.base (no parameter of hg-mcap or hg-foxglove): a cell naming another
# one gives the camera transforms that parent; --base-frame is refused naming the cell key.
sed 's/^  base: robot_base/  base: cell_base/' "$src/config/cell-sim.yaml" >"$tmp/cell-base.yaml"
grep -q '^  base: cell_base' "$tmp/cell-base.yaml" || { echo "FAIL: no frames.base in config/cell-sim.yaml"; fail=1; }
expect_rc 0 "hg-mcap with frames.base cell_base" "$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/base.mcap" \
  --cell "$tmp/cell-base.yaml"
$check "$tmp/base.mcap" "$tmp/fresh.lcmlog" --expect-tf --base-frame cell_base || fail=1
for cmd in "hg-mcap $tmp/fresh.lcmlog -o $tmp/x.mcap" hg-foxglove; do
  read -r -a argv <<<"$cmd"
  expect_rc 2 "${argv[0]} --base-frame" "$bin/${argv[0]}" "${argv[@]:1}" --base-frame b
  grep -q "key frames.base" "$tmp/out" || { echo "FAIL: ${argv[0]} --base-frame does not name frames.base"; fail=1; }
done

# Corrupt: the fresh log, garbage, a committed log. Both logs' events must be there, the garbage reported.
second="$src/tests/data/tools/samples-all-types.lcmlog"
{ cat "$tmp/fresh.lcmlog"; head -c 5000 /dev/urandom; cat "$second"; } >"$tmp/corrupt.lcmlog"
expect_rc 0 "hg-mcap on a corrupt log" "$bin/hg-mcap" "$tmp/corrupt.lcmlog" -o "$tmp/corrupt.mcap"
grep -q "1 corrupt stretches skipped, the first at byte $(stat -c %s "$tmp/fresh.lcmlog")" "$tmp/out" ||
  { echo "FAIL: the corrupt stretch is not reported at its byte:"; cat "$tmp/out"; fail=1; }
$check "$tmp/corrupt.mcap" "$tmp/fresh.lcmlog" "$second" || fail=1
# A log cut short: the last event is dropped and reported.
head -c $(( $(stat -c %s "$tmp/fresh.lcmlog") - 3 )) "$tmp/fresh.lcmlog" >"$tmp/cut.lcmlog"
expect_rc 0 "hg-mcap on a cut log" "$bin/hg-mcap" "$tmp/cut.lcmlog" -o "$tmp/cut.mcap"
grep -q "1 corrupt stretches skipped" "$tmp/out" || { echo "FAIL: the cut event is not reported"; fail=1; }

# Bad input and failures.
expect_rc 2 "no such file" "$bin/hg-mcap" "$tmp/none.lcmlog" -o "$tmp/x.mcap"
head -c 10000 /dev/urandom >"$tmp/random.bin"
expect_rc 2 "not an LCM log" "$bin/hg-mcap" "$tmp/random.bin" -o "$tmp/x.mcap"
[[ ! -e "$tmp/x.mcap" && ! -e "$tmp/x.mcap.tmp" ]] || { echo "FAIL: a file was left for bad input"; fail=1; }
expect_rc 2 "bad compression" "$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/x.mcap" --compression gzip
expect_rc 2 "no output" "$bin/hg-mcap" "$tmp/fresh.lcmlog"
expect_rc 2 "bad cell file" "$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/x.mcap" --cell "$tmp/random.bin"
expect_rc 1 "unwritable output" "$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/no/such/dir/x.mcap"
mkfifo "$tmp/fifo"
expect_rc 2 "output not a regular file" "$bin/hg-mcap" "$tmp/fresh.lcmlog" -o "$tmp/fifo"
[[ -p "$tmp/fifo" ]] || { echo "FAIL: the fifo was replaced"; fail=1; }
exit $fail
