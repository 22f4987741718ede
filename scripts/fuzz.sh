#!/usr/bin/env bash
# Runs the cargo-fuzz targets (fuzz/fuzz_targets/) for a while; not part of CI (too long).
#
#   scripts/fuzz.sh [eds|xml|node|all] [SECONDS]      (defaults: all, 900 seconds per target)
#
# Works on the stable toolchain: cargo-fuzz's nightly flags are allowed with RUSTC_BOOTSTRAP=1.
# Debug assertions are on (-a), so arithmetic overflow panics. FUZZ_SANITIZER picks the sanitizer:
# the default `none` runs the EDS target about 5 times faster than `address` (the crates under test
# have no `unsafe`; the point is panics, overflows, timeouts and memory blow-ups).
# One libFuzzer process at a time, single job.
#
# Seeds are copied at run time into fuzz/corpus/<target>/ (git-ignored): for eds the bundled cards
# (eds/*.eds) and the corpus's *.eds/*.dcf files up to the length limit; for xml the corpus's
# *.xdd/*.xdc files, each shrunk to fit the limit by fuzz/shrink_xml.py (a cut XML file is not
# well-formed, so it would only exercise the parser), plus codegen/tests/esi/*.xml and the ESI
# corpus's files under the limit. The corpus is EDSGEN_CORPUS, else ../shared/eds-corpus (the ESI
# corpus EDSGEN_ESI_CORPUS, else ../shared/esi-corpus). Findings land in fuzz/artifacts/<target>/ (git-ignored too).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

target=${1:-all}
seconds=${2:-900}
sanitizer=${FUZZ_SANITIZER:-none}
max_len=65536
corpus_src=${EDSGEN_CORPUS:-$root/../shared/eds-corpus}
esi_corpus_src=${EDSGEN_ESI_CORPUS:-$root/../shared/esi-corpus}

case "$target" in
eds | xml | node) targets=("$target") ;;
all) targets=(eds xml node) ;;
*)
    echo "usage: scripts/fuzz.sh [eds|xml|node|all] [SECONDS]" >&2
    exit 2
    ;;
esac

if ! cargo fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi
export RUSTC_BOOTSTRAP=1

seed() {
    local name=$1 dir=fuzz/corpus/$1
    mkdir -p "$dir"
    case "$name" in
    eds)
        cp eds/*.eds "$dir"/
        if [ -d "$corpus_src" ]; then
            find "$corpus_src" -type f \( -iname '*.eds' -o -iname '*.dcf' \) -size -"$max_len"c -print0 |
                while IFS= read -r -d '' f; do
                    cp "$f" "$dir/$(basename "$(dirname "$f")")__$(basename "$f")"
                done
        fi
        ;;
    xml)
        if [ -d "$corpus_src" ]; then
            find "$corpus_src" -type f \( -iname '*.xdd' -o -iname '*.xdc' \) -print0 |
                while IFS= read -r -d '' f; do
                    python3 fuzz/shrink_xml.py "$f" "$dir/$(basename "$(dirname "$f")")__$(basename "$f")" "$max_len"
                done
        fi
        # ESI files (read by the same target through `fuzz.xml`): the project's own, and the
        # ESI corpus's that fit the limit.
        cp codegen/tests/esi/*.xml "$dir"/
        if [ -d "$esi_corpus_src" ]; then
            find "$esi_corpus_src" -type f \( -iname '*.xml' -o -iname '*.esi' \) -size -"$max_len"c -print0 |
                while IFS= read -r -d '' f; do
                    cp "$f" "$dir/esi__$(basename "$f")"
                done
        fi
        ;;
    node) ;; # arbitrary bytes: no seeds needed
    esac
    if [ "$name" != node ] && [ ! -d "$corpus_src" ]; then
        echo "note: no corpus at $corpus_src (set EDSGEN_CORPUS); seeding from what there is" >&2
    fi
}

for name in "${targets[@]}"; do
    seed "$name"
    args=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1)
    case "$name" in
    eds | xml) args+=(-max_len="$max_len" -dict="fuzz/dict/$name.dict") ;;
    node) args+=(-max_len=4096) ;;
    esac
    log=fuzz/artifacts/$name.log
    mkdir -p fuzz/artifacts
    echo "== $name: ${seconds}s, sanitizer $sanitizer, log $log"
    status=0
    cargo fuzz run "$name" -s "$sanitizer" -a -- "${args[@]}" >"$log" 2>&1 || status=$?
    grep -E "^(==[0-9]+==|thread '|SUMMARY|Test unit written)" "$log" || true
    # libFuzzer's last status line (executions, coverage, features) and its run count.
    grep -E '^#[0-9]+' "$log" | tail -1 || true
    grep -E '^Done [0-9]+ runs' "$log" || true
    if [ "$status" -ne 0 ]; then
        tail -20 "$log" >&2
        echo "$name: failed (exit $status); findings are in fuzz/artifacts/$name/" >&2
        exit 1
    fi
done
