#!/usr/bin/env bash
# `make run`: the demo on a bundled sample, with no input needed.
# Today: the outline core on the bundled hull-part cloud (data/samples/), checked against the cloud's
# ground truth, then the grind path planned on that outline when hg-plan is built.
# Writes out/outline.json, out/outline.png, out/outline.svg (and out/path.json) and prints a summary.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
OUT=${OUT:-out}
SAMPLE=${SAMPLE:-data/samples/plate-hole-slot-low.xyz}

usage() {
  cat <<USAGE
usage: tools/run.sh [--sample FILE.xyz] [--out DIR]
Runs the outline core (hg-outline) on a bundled hull-part cloud and writes DIR/outline.json,
DIR/outline.png and DIR/outline.svg; compares the loops with the sample's ground truth
(FILE.truth.json) and prints a summary. Default sample: $SAMPLE, default DIR: $OUT.
USAGE
}
while [[ $# -gt 0 ]]; do
  case "$1" in
    --sample) SAMPLE=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
  esac
done

mkdir -p "$OUT"
echo "== hullgrind demo: outline of $SAMPLE"
"$BIN/hg-outline" "$SAMPLE" -o "$OUT/outline.json" --png "$OUT/outline.png" --svg "$OUT/outline.svg"
truth="$SAMPLE.truth.json"
python3 - "$OUT/outline.json" "$truth" <<'PY'
import json, sys
out = json.load(open(sys.argv[1]))
t = out["time_ms"]
print("points read %d, used %d, duplicates merged %d" % (out["points_read"], out["points_used"], out["duplicates_merged"]))
print("alpha radius %.5g (%s), mode %s, order %s" % (out["alpha_radius"], "automatic" if out.get("alpha_automatic", True) else "given", out["mode"], out["order"]))
print("triangles %d, search cost %d (%.2f per point)" % (out["triangles"], out["search_cost"], out["search_cost"] / max(1, out["points_used"])))
print("time: triangulate %.2f ms, alpha %.2f ms, loops %.2f ms, total %.2f ms" % (t["triangulate"], t["alpha"], t["loops"], t["total"]))
outer = [l for l in out["loops"] if not l["hole"]]
holes = [l for l in out["loops"] if l["hole"]]
print("loops: %d outer, %d holes" % (len(outer), len(holes)))
for l in out["loops"]:
    print("  %-5s area %.6g  perimeter %.6g  %d vertices" % ("hole" if l["hole"] else "outer", l["area"], l["perimeter"], len(l["points"])))
try:
    truth = json.load(open(sys.argv[2]))
except OSError:
    sys.exit(0)
parts = truth["parts"]
want_holes = sum(len(p["holes"]) for p in parts)
area = sum(l["area"] for l in outer) - sum(l["area"] for l in holes)
print("ground truth: %d part(s), %d holes, area %.6g; outline area %.6g (%+.2f%%)" %
      (len(parts), want_holes, truth["area"], area, 100 * (area - truth["area"]) / truth["area"]))
if len(outer) != len(parts) or len(holes) != want_holes:
    print("MISMATCH: the outline's loops do not match the ground truth", file=sys.stderr)
    sys.exit(1)
PY
echo "wrote $OUT/outline.json, $OUT/outline.png, $OUT/outline.svg"
