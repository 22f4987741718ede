#!/usr/bin/env bash
# Instructions per frame of the device node (valgrind --tool=callgrind), for an SDO expedited
# upload of 1017h:00 and a 2-byte RPDO. Two runs per case with different frame counts; the
# difference of their instruction totals over the difference of counts cancels the setup.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "valgrind is required (apt-get install valgrind)"; exit 2; }
cargo build --release -q -p edsgen-runtime --example frame_cost
cargo build --release -q -p edsgen --example node_frame_cost
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
total() {
    valgrind --tool=callgrind --callgrind-out-file="$out/cg" "$1" "$2" "$3" >/dev/null 2>"$out/log"
    grep -E '^(summary|totals):' "$out/cg" | head -1 | awk '{print $2}'
}
for od in "test OD (runtime/tests/node_support):target/release/examples/frame_cost" \
          "generated Goodrive350 OD (eds/goodrive350.eds):target/release/examples/node_frame_cost"; do
    bin=${od##*:}
    echo "== ${od%%:*}"
    for case in sdo rpdo; do
        small=$(total "$bin" "$case" 1000)
        large=$(total "$bin" "$case" 11000)
        echo "$case: $(( (large - small) / 10000 )) instructions per frame"
    done
done
