#!/usr/bin/env bash
# Regenerates the bundled sample clouds (and their ground truth) with hg-gen. Deterministic: running it
# again with the same hg-gen reproduces the same bytes. Usage: data/samples/regenerate.sh [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/../../tools/version.sh"
hg_answer regenerate.sh "$0" "$@"
gen=${1:-$here/../../build}/bin/hg-gen
[[ -x $gen ]] || { echo "regenerate.sh: $gen not built (cmake --build BUILD_DIR --target hg-gen)" >&2; exit 1; }

# Test piece 1 of the paper's Table 1 (plate with a lightening hole and a slot, Percipio-like density),
# with camera-like imperfections: 0.3 mm in-plane noise, 0.5 mm depth noise, 1 % dropout, jagged edges.
"$gen" --preset low-1 --noise 0.0003 --depth-noise 0.0005 --dropout 0.01 --jagged --seed 1 \
  -o "$here/plate-hole-slot-low.xyz"
# Four different parts on one table at 8 mm pitch, same imperfections.
"$gen" --scene demo --pitch 0.008 --noise 0.0003 --depth-noise 0.0005 --dropout 0.01 --jagged --seed 2 \
  -o "$here/demo-scene.xyz"
