#!/usr/bin/env bash
# Installs the Debian 12 packages hullgrind needs to build, run and test. Idempotent: when everything
# is present it only checks (a fraction of a second) and installs nothing.
# Not root: prints the exact apt-get line to run and exits 1.
#
# usage: tools/install-deps.sh [--run]
#   (no option)  everything: build, run and test (`make test`, CI)
#   --run        only what `make run` needs: build the pipeline's programs and run them (no JDK, browser,
#                clang, CGAL or lint tools; `make test` installs those later)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer install-deps "$0" "$@"

run_packages=(
  # build (GoogleTest and GMP too: configuring the tree configures the tests, and the outline core's exact
  # checker needs GMP to configure)
  cmake ninja-build ccache g++ pkg-config libgtest-dev libgmp-dev
  # runtime libraries
  liblcm-dev liblcm-bin libopenni2-dev libaravis-dev libusb-1.0-0-dev libeigen3-dev
  # OpenCV: only the three modules the pipeline uses (libopencv-dev pulls every module's dependencies)
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev
  cyclonedds-dev cyclonedds-tools libpolyclipping-dev nlohmann-json3-dev libpng-dev libyaml-cpp-dev
  # operator station (HTTP/WebSocket, password hashing, the 3-D view) and MCAP chunks
  libboost-dev libssl-dev libsodium-dev libjs-three libzstd-dev liblz4-dev
  # MCAP and the live server: shortest float text (Dragonbox), CRC32 with PCLMUL
  libfmt-dev libdeflate-dev
  # tools/run.sh: its network namespace, python3 for the supervisor, the test DDS Security set
  iproute2 python3 openssl
)
test_packages=(
  # OpenCV's CMake package and calib3d (the hand-eye calibration, hg-calibrate and its tests)
  libopencv-dev
  # lcm-spy and its tests (headless)
  liblcm-java default-jdk-headless default-jre libjchart2d-java xvfb
  # lint (tools/lint: make test runs the function-length check; formatting with clang-format)
  universal-ctags clang-format
  # test-only oracle for the outline core (never needed to build or run the product)
  libcgal-dev
  # browser tests (a real Chromium through Selenium), fuzzing (libFuzzer with clang)
  chromium chromium-driver python3-selenium clang libclang-rt-14-dev
)
packages=("${run_packages[@]}")
case "${1:-}" in
  --run) ;;
  "") packages+=("${test_packages[@]}") ;;
  *) echo "install-deps: unknown option '$1' (--run or nothing)" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
# The tests' npm readers need Node.js and npm: Debian's, unless the machine has its own already.
with_npm=false
if [[ -z "${1:-}" ]]; then
  with_npm=true
  command -v npm >/dev/null || missing+=(nodejs npm)
fi

# npm packages of the tests (readers nobody here wrote: @mcap/core, ajv, @foxglove/ws-protocol, ...): exactly
# tests/npm/package-lock.json, installed with `npm ci` into build/npm/ (HG_NPM_DIR). Skipped quickly when
# the installed lock file is the committed one.
npm_packages() {
  local root npm_dir
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  npm_dir="${HG_NPM_DIR:-$root/build/npm}"
  if [[ -d "$npm_dir/node_modules" ]] && cmp -s "$root/tests/npm/package-lock.json" "$npm_dir/installed.lock.json"; then
    return 0
  fi
  if ! command -v npm >/dev/null; then
    echo "install-deps: npm (Node.js 18 or newer) is missing: the Foxglove tests need it" >&2
    return 1
  fi
  echo "install-deps: npm ci into $npm_dir (tests/npm/package-lock.json)" >&2
  mkdir -p "$npm_dir"
  cp "$root/tests/npm/package.json" "$root/tests/npm/package-lock.json" "$npm_dir/"
  (cd "$npm_dir" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
  cp "$root/tests/npm/package-lock.json" "$npm_dir/installed.lock.json"
}

if [[ ${#missing[@]} -eq 0 ]]; then
  ! $with_npm || npm_packages
  exit 0
fi

cmd="apt-get install -y --no-install-recommends ${missing[*]}"
if [[ $(id -u) -ne 0 ]]; then
  echo "install-deps: missing Debian packages: ${missing[*]}" >&2
  echo "install-deps: run as root:  apt-get update && $cmd" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
$cmd -qq
! $with_npm || npm_packages
