#!/bin/sh
# The cycle figures of the README: `edsgen simulate --ethercat --card ec-tx508` on one end of a veth
# pair in a private network namespace, examples/ethercat_cycles.rs (ethercrab) on the other, both
# release builds; CYCLES cycles (100000 unless given). Needs root. The namespace, its veth pair
# and the simulator are removed on exit, also on failure.
#
#   sudo scripts/ethercat-cycles.sh [CYCLES]
set -eu
cycles=${1:-100000}
cd "$(dirname "$0")/.."
if [ "$(id -u)" != 0 ]; then
    echo "ethercat-cycles: needs root for a network namespace and a veth pair" >&2
    exit 2
fi
cargo build --release --features ethercrab --bin edsgen --example ethercat_cycles
target=${CARGO_TARGET_DIR:-target}/release
ns="edsgen-cycles-$$"
sim=""
cleanup() {
    if [ -n "$sim" ]; then kill "$sim" 2>/dev/null || true; wait "$sim" 2>/dev/null || true; fi
    ip netns del "$ns" 2>/dev/null || true
}
trap cleanup EXIT INT TERM
ip netns add "$ns"
ip -n "$ns" link add ecm type veth peer name ecs
ip -n "$ns" link set ecm up
ip -n "$ns" link set ecs up
ip netns exec "$ns" "$target/edsgen" simulate --ethercat ecs --card ec-tx508 &
sim=$!
sleep 1
ip netns exec "$ns" "$target/examples/ethercat_cycles" ecm "$cycles"
