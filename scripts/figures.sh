#!/usr/bin/env bash
# Every ratio the README's Performance table claims, measured side by side in one run, with the
# load average it ran at (before and after): a figure measured on a loaded machine says so.
#
#   scripts/figures.sh           the reader against python `canopen` and generate against
#                                validate (a release build of `edsgen`; about a minute)
#   scripts/figures.sh --all     also the benches and scripts behind the other rows: generated
#                                code (codegen's emit bench), the node's instructions per frame
#                                (scripts/node-cost.sh), the firmware sizes
#                                (scripts/firmware-size.sh) and the simulators' cost per frame
#                                (sim's frames bench); long
#
# The reader's figure is a process, start-up and JSON output included: `edsgen validate --format
# json` over the 93 corpus files python imports (both cores read files), best of 10 runs,
# against python's `canopen.import_od` over the same files, best of 5 passes in one process
# (scripts/bench_canopen.py). Throughput is the files' bytes over edsgen's time.
# The corpus is ../shared/eds-corpus, or EDSGEN_CORPUS.
set -euo pipefail
cd "$(dirname "$0")/.."
all=false
[ "${1:-}" = "--all" ] && all=true
load() { cut -d' ' -f1-3 /proc/loadavg; }
echo "load average at start: $(load) ($(nproc) cores)"

target=$(scripts/target-dir.sh)
cargo build --release --quiet --bin edsgen
edsgen="$target/release/edsgen"
corpus=${EDSGEN_CORPUS:-../shared/eds-corpus}
table="$corpus/python_canopen_baseline.tsv"
[ -f "$table" ] || { echo "no corpus at $corpus (set EDSGEN_CORPUS)"; exit 2; }
python=$(scripts/python-venv.sh)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
awk -F'\t' -v dir="$corpus" 'NR > 1 && $2 == "ok" { print dir "/" $1 }' "$table" >"$work/importable"
awk -F'\t' -v dir="$corpus" 'NR > 1 { print dir "/" $1 }' "$table" >"$work/all"

# best_ms RUNS COMMAND...: the best wall-clock time of RUNS runs, in ms (output discarded).
best_ms() {
    python3 - "$@" <<'PY'
import subprocess, sys, time
runs, command = int(sys.argv[1]), sys.argv[2:]
best = float("inf")
for _ in range(runs):
    start = time.perf_counter()
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    best = min(best, time.perf_counter() - start)
print(f"{best * 1e3:.1f}")
PY
}
ratio() { python3 -c "print(f'{$1 / $2:.1f}')"; }

mapfile -t importable <"$work/importable"
mapfile -t every <"$work/all"
bytes=$(cat "${importable[@]}" | wc -c)
ours=$(best_ms 10 "$edsgen" validate --format json "${importable[@]}")
theirs=$(python3 -c "print(f'{$("$python" scripts/bench_canopen.py "${importable[@]}") * 1e3:.1f}')")
all_ms=$(best_ms 10 "$edsgen" validate --format json "${every[@]}")
echo
echo "read + validate the ${#importable[@]} corpus files python imports ($bytes bytes), as a process:"
echo "  edsgen $ours ms ($(python3 -c "print(f'{$bytes / 1e3 / $ours:.0f}')") MB/s), python canopen import_od $theirs ms: $(ratio "$theirs" "$ours")x faster"
echo "read + validate all ${#every[@]} corpus files, as a process: $all_ms ms"

generate=$(best_ms 10 "$edsgen" generate eds/rd11.eds -o "$work/rd11.rs")
validate=$(best_ms 10 "$edsgen" validate eds/rd11.eds)
echo "RD11 (eds/rd11.eds), as processes: generate $generate ms, validate $validate ms: generate costs $(ratio "$generate" "$validate")x validate"

if $all; then
    echo
    echo "== generated code and generation (cargo bench -p edsgen-codegen --bench emit)"
    cargo bench -q -p edsgen-codegen --bench emit 2>/dev/null | grep -E "^[a-zA-Z].*|time:"
    echo "== the simulators' cost per frame (cargo bench -p edsgen-sim --bench frames)"
    cargo bench -q -p edsgen-sim --bench frames 2>/dev/null | grep -E "^[a-zA-Z].*|time:"
    echo "== the node's instructions per frame (scripts/node-cost.sh)"
    scripts/node-cost.sh || true
    echo "== firmware sizes (scripts/firmware-size.sh)"
    scripts/firmware-size.sh || true
fi
echo
echo "load average at end: $(load)"
