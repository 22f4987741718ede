#!/usr/bin/env bash
# Instructions per frame of the device node (valgrind --tool=callgrind), for an SDO expedited
# upload of 1017h:00 and a 2-byte RPDO. Two runs per case with different frame counts; the
# difference of their instruction totals over the difference of counts cancels the setup.
# Fails (exit 1) when a count exceeds its budget in budgets.toml.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "valgrind is required (apt-get install valgrind)"; exit 2; }
target=$(scripts/target-dir.sh)
cargo build --release -q -p edsgen-runtime --example frame_cost
cargo build --release -q -p edsgen --example node_frame_cost
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
total() {
    valgrind --tool=callgrind --callgrind-out-file="$out/cg" "$1" "$2" "$3" >/dev/null 2>"$out/log"
    grep -E '^(summary|totals):' "$out/cg" | head -1 | awk '{print $2}'
}
budget() {
    awk -v key="$1" '$1 == key && $2 == "=" { print $3 }' budgets.toml
}
failed=0
for od in "table:test OD (runtime/tests/node_support):$target/release/examples/frame_cost" \
          "generated:generated Goodrive350 OD (eds/goodrive350.eds):$target/release/examples/node_frame_cost"; do
    key=${od%%:*}
    rest=${od#*:}
    bin=${rest##*:}
    echo "== ${rest%%:*}"
    for case in sdo rpdo; do
        small=$(total "$bin" "$case" 1000)
        large=$(total "$bin" "$case" 11000)
        per_frame=$(( (large - small) / 10000 ))
        limit=$(budget "cost.$key.$case")
        [ -n "$limit" ] || { echo "no budget cost.$key.$case in budgets.toml"; exit 2; }
        echo "$case: $per_frame instructions per frame (budget $limit)"
        if [ "$per_frame" -gt "$limit" ]; then
            echo "OVER BUDGET: cost.$key.$case is $per_frame instructions, the budget is $limit (budgets.toml)"
            failed=1
        fi
    done
done
exit "$failed"
