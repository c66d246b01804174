#!/usr/bin/env bash
# Two "hosts" on one machine for test_dds_veth (docs/ros2.md, "Across a network"): runs
# PROGRAM [ARGS...] on host A, a network namespace of its own with the address 10.77.0.1/24 on
# veth_a, joined by a veth pair to host B, a second network namespace with 10.77.0.2/24 on veth_b.
# PROGRAM starts what runs on host B with `$FLIPPER_VETH_NSENTER -t $FLIPPER_VETH_HOST_B -n --`.
#
# No root needed: `unshare -Urn` makes a user namespace (this user is root inside it) with host A's
# network namespace; host B is a child network namespace of the same user namespace, held by one
# process (`cat` on a pipe from this script: it goes when this script goes). Neither namespace
# has any interface but its own `lo` and its end of the veth pair, so nothing run here can reach
# or open anything on the machine's real network. Multicast is off on both ends of the pair:
# discovery can only use the unicast peers the Cyclone configuration lists.
#
# A machine that cannot make the namespaces or the pair (no unshare/nsenter/ip, user namespaces
# disabled, a container's seccomp profile, no veth driver) gets the reason on stdout and exit 77,
# which ctest reports as skipped (SKIP_RETURN_CODE): never a silent pass.
set -euo pipefail

readonly kSkip=77
readonly kAddrA=10.77.0.1 kAddrB=10.77.0.2

skip() {
  echo "SKIPPED: $*"
  exit "$kSkip"
}

if [ "${FLIPPER_VETH_STAGE:-}" != inside ]; then
  [ $# -ge 1 ] || { echo "usage: $0 PROGRAM [ARGS...]" >&2; exit 2; }
  for tool in unshare nsenter ip; do
    command -v "$tool" >/dev/null || skip "'$tool' is not installed (util-linux, iproute2)"
  done
  # The probe makes (and drops) a namespace with a pair, as the run below does.
  if ! err=$(unshare -Urn ip link add vprobe_a type veth peer name vprobe_b 2>&1); then
    skip "this machine cannot make a network namespace with a veth pair as this user" \
      "(unshare -Urn; ip link add ... type veth): ${err:-no message}"
  fi
  FLIPPER_VETH_STAGE=inside exec unshare -Urn -- "$BASH" "$0" "$@"
fi

# Inside: root of the new user namespace, in host A's network namespace.
# Host B: its holder prints "up" once it is in a network namespace of its own.
coproc HOLDER { exec unshare -n -- sh -c 'echo up; exec cat >/dev/null'; }
host_b=$HOLDER_PID
read -r -t 10 up <&"${HOLDER[0]}" || true
[ "${up:-}" = up ] || { echo "host B's network namespace did not come up" >&2; exit 1; }

ip link add veth_a type veth peer name veth_b netns "$host_b"
ip addr add "$kAddrA/24" dev veth_a
ip link set veth_a multicast off up
ip link set lo up
nsenter -t "$host_b" -n -- sh -c "ip addr add $kAddrB/24 dev veth_b &&
  ip link set veth_b multicast off up && ip link set lo up"

export FLIPPER_VETH_HOST_B=$host_b
FLIPPER_VETH_NSENTER=$(command -v nsenter)
export FLIPPER_VETH_NSENTER
set +e
"$@"
status=$?
kill "$host_b" 2>/dev/null
exit "$status"
