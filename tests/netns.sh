#!/usr/bin/env bash
# Runs a command in a fresh network namespace with only loopback, multicast routed to lo.
# LCM (udpm, ttl=0) and Cyclone DDS traffic of the command can therefore never leave the machine, and two
# tests running side by side cannot hear each other. Needs root or unprivileged user namespaces.
#   tests/netns.sh [--own-pids] COMMAND [ARGS...]
# --own-pids: a PID namespace too (and its own /proc), so that every process the command started dies with
# it, even when the command is killed (CTest's timeout, a killed ctest): a simulated pipeline left running
# would load the machine for hours. The tests use it; tools/run.sh does not, so that the PIDs the
# supervisor reports are the host's.
set -euo pipefail
# --help / --version only as the first argument: later ones belong to COMMAND.
source "$(dirname "${BASH_SOURCE[0]}")/../tools/version.sh"
hg_answer netns.sh "$0" "${1:-}"
own_pids=()
if [[ "${1:-}" == "--own-pids" ]]; then
  own_pids=(--pid --fork --kill-child --mount-proc)
  shift
fi
if [[ $# -eq 0 ]]; then echo "usage: $0 [--own-pids] COMMAND [ARGS...]" >&2; exit 2; fi

if [[ "${HG_IN_NETNS:-}" != "1" ]]; then
  pid1=${own_pids:+1}
  if [[ $(id -u) -ne 0 ]]; then own_pids+=(--map-root-user); fi
  exec env HG_IN_NETNS=1 HG_NETNS_PID1="$pid1" unshare --net "${own_pids[@]}" -- "$0" "$@"
fi

ip link set lo up
ip link set lo multicast on
ip route add 224.0.0.0/4 dev lo
if [[ "${HG_NETNS_PID1:-}" == "1" ]]; then
  # This shell is the namespace's init: it stays, to reap the processes orphaned inside, and when it ends
  # the kernel kills whatever is left.
  unset HG_NETNS_PID1
  "$@"
  exit $?
fi
exec "$@"
