#!/usr/bin/env bash
# Instructions per SDO expedited-upload request/response pair, counted by callgrind.
#
# Runs runtime/examples/sdo_loop (release) with 0 and with 10000 pairs under
# `valgrind --tool=callgrind` and prints (Ir(10000) - Ir(0)) / 10000, so process start-up and
# printing cancel out. Needs valgrind. Fails (exit 1) above the budget `cost.sdo_server.pair` in
# budgets.toml.
set -euo pipefail
cd "$(dirname "$0")/.."
pairs=10000
cargo build --release --quiet -p edsgen-runtime --example sdo_loop
binary="$(scripts/target-dir.sh)/release/examples/sdo_loop"
workdir=$(mktemp -d)
trap 'rm -rf "$workdir"' EXIT

instructions() {
    valgrind --tool=callgrind --callgrind-out-file="$workdir/out.$1" "$binary" "$1" \
        >/dev/null 2>"$workdir/log.$1"
    sed -n 's/^summary: *\([0-9]*\).*/\1/p' "$workdir/out.$1"
}

base=$(instructions 0)
loaded=$(instructions "$pairs")
echo "instructions: $base (0 pairs), $loaded ($pairs pairs)"
per_pair=$(( (loaded - base) / pairs ))
limit=$(awk '$1 == "cost.sdo_server.pair" && $2 == "=" { print $3 }' budgets.toml)
echo "per pair: $per_pair (budget $limit)"
if [ "$per_pair" -gt "$limit" ]; then
    echo "OVER BUDGET: cost.sdo_server.pair is $per_pair instructions, the budget is $limit (budgets.toml)"
    exit 1
fi
