#!/usr/bin/env bash
# Runs a command in a fresh network namespace with only loopback, multicast routed to lo.
# LCM (udpm, ttl=0) and Cyclone DDS traffic of the command can therefore never leave the machine, and two
# tests running side by side cannot hear each other. Needs root or unprivileged user namespaces.
#   tests/netns.sh COMMAND [ARGS...]
set -euo pipefail
# --help / --version only as the first argument: later ones belong to COMMAND.
source "$(dirname "${BASH_SOURCE[0]}")/../tools/version.sh"
hg_answer netns.sh "$0" "${1:-}"
if [[ $# -eq 0 ]]; then echo "usage: $0 COMMAND [ARGS...]" >&2; exit 2; fi

if [[ "${HG_IN_NETNS:-}" != "1" ]]; then
  if [[ $(id -u) -eq 0 ]]; then
    exec env HG_IN_NETNS=1 unshare --net -- "$0" "$@"
  else
    exec env HG_IN_NETNS=1 unshare --net --map-root-user -- "$0" "$@"
  fi
fi

ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
exec "$@"
