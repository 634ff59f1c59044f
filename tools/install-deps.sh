#!/usr/bin/env bash
# Installs the Debian 12 packages hullgrind needs to build, run and test. Idempotent: when everything
# is present it only checks (a fraction of a second) and installs nothing.
# Not root: prints the exact apt-get line to run and exits 1.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/version.sh"
hg_answer install-deps "$0" "$@"

packages=(
  # build
  cmake ninja-build ccache g++ pkg-config
  # runtime libraries
  liblcm-dev liblcm-bin liblcm-java libopenni2-dev libaravis-dev libusb-1.0-0-dev libeigen3-dev libopencv-dev
  cyclonedds-dev cyclonedds-tools libpolyclipping-dev nlohmann-json3-dev libpng-dev libyaml-cpp-dev
  # lcm-spy, tools and tests
  default-jdk-headless default-jre libjchart2d-java libgtest-dev iproute2 xvfb python3 openssl
  # lint (tools/lint: make test runs the function-length check; formatting with clang-format)
  universal-ctags clang-format
  # test-only oracle for the outline core (never needed to build or run the product)
  libcgal-dev libgmp-dev
  # operator station (HTTP/WebSocket, password hashing, the 3-D view) and MCAP chunks
  libboost-dev libssl-dev libsodium-dev libjs-three libzstd-dev liblz4-dev
  # browser tests (a real Chromium through Selenium), fuzzing (libFuzzer with clang)
  chromium chromium-driver python3-selenium clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
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
