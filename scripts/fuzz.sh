#!/usr/bin/env bash
# Runs the cargo-fuzz targets (fuzz/fuzz_targets/) for a while; not part of CI (too long).
#
#   scripts/fuzz.sh [TARGET|all] [SECONDS]      (defaults: all, 900 seconds per target)
#
# TARGET: eds, xml, esi, node, socketcand, decode, decode_log, sdo_client.
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
# well-formed, so it would only exercise the parser); for esi the ESI corpus's files, shrunk by
# fuzz/shrink_esi.py; for decode a short candump -L session written here; node, socketcand and
# sdo_client start empty. The corpus is EDSGEN_CORPUS, else ../shared/eds-corpus; the ESI corpus
# EDSGEN_ESI_CORPUS, else ../shared/esi-corpus. Findings land in fuzz/artifacts/<target>/
# (git-ignored too).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

target=${1:-all}
seconds=${2:-900}
sanitizer=${FUZZ_SANITIZER:-none}
max_len=65536
corpus_src=${EDSGEN_CORPUS:-$root/../shared/eds-corpus}
esi_src=${EDSGEN_ESI_CORPUS:-$root/../shared/esi-corpus}
all=(eds xml esi node socketcand decode decode_log sdo_client)

case "$target" in
eds | xml | esi | node | socketcand | decode | decode_log | sdo_client) targets=("$target") ;;
all) targets=("${all[@]}") ;;
*)
    echo "usage: scripts/fuzz.sh [eds|xml|esi|node|socketcand|decode|decode_log|sdo_client|all] [SECONDS]" >&2
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
        ;;
    esi)
        if [ -d "$esi_src" ]; then
            find "$esi_src" -type f \( -iname '*.xml' -o -iname '*.esi' \) -print0 |
                while IFS= read -r -d '' f; do
                    python3 fuzz/shrink_esi.py "$f" "$dir/$(basename "$(dirname "$f")")__$(basename "$f")" "$max_len"
                done
        else
            echo "note: no ESI corpus at $esi_src (set EDSGEN_ESI_CORPUS); no seeds" >&2
        fi
        ;;
    decode)
        # Node 5 (described by eds/cp301.eds in odd-length inputs): NMT, boot-up, expedited,
        # segmented and block SDO, an abort, a mapping write, SYNC, PDOs, EMCY, TIME, guarding.
        cat >"$dir/session.log" <<'EOF'
(1764000000.000100) can0 000#8105
(1764000000.000800) can0 705#00
(1764000000.001000) can0 605#4000100000000000
(1764000000.001100) can0 585#4300100091010200
(1764000000.002000) can0 605#2B17100032000000
(1764000000.002100) can0 585#6017100000000000
(1764000000.003000) can0 605#4008100000000000
(1764000000.003100) can0 585#4108100009000000
(1764000000.003200) can0 605#6000000000000000
(1764000000.003300) can0 585#0043503330312D31
(1764000000.003400) can0 605#7000000000000000
(1764000000.003500) can0 585#1B6F6E0000000000
(1764000000.004000) can0 605#C600180204000000
(1764000000.004100) can0 585#A400180204000000
(1764000000.004200) can0 605#8191010000000000
(1764000000.004300) can0 585#A2017F0000000000
(1764000000.004400) can0 605#D500000000000000
(1764000000.004500) can0 585#A100000000000000
(1764000000.005000) can0 605#4000500000000000
(1764000000.005100) can0 585#8000500000000206
(1764000000.006000) can0 605#2F001A0000000000
(1764000000.006100) can0 585#60001A0000000000
(1764000000.007000) can0 000#0105
(1764000000.008000) can0 080#
(1764000000.008100) can0 185#0102
(1764000000.008200) can0 205#0304
(1764000000.009000) can0 085#1081110000000000
(1764000000.010000) can0 100#00E4C6014A38
(1764000000.011000) can0 705#R
(1764000000.011100) can0 705#85
(1764000000.012000) can0 12345678#DEADBEEF
(1764000000.013000) can0 7E5#1234
(1764000000.014000) can0 605#4000600000000000
EOF
        ;;
    decode_log)
        # One short session in each format the log reader recognises.
        printf '%s\n' '(1764000000.000100) can0 000#0105' '(1764000000.1) can0 705#7F R' \
            '(1764000000.2) can0 123##1AABB' >"$dir/candump-L.log"
        printf '%s\n' '  can0  701   [1]  05' '(000.000100)  can0  TX - -  605   [4]  40 18 10 01' \
            '  can0  705   [1]  remote request' >"$dir/candump.log"
        printf '%s\n' 'date Mon Nov 24 16:00:00.000 2025' 'base hex  timestamps absolute' \
            'Begin Triggerblock Mon Nov 24 16:00:00.000 2025' ' 0.001000 1  7E5  Rx   d 8 04 01 00 00 00 00 00 00' \
            ' 0.002000 1  18FF0005x  Tx   d 1 AA' ' 0.003000 1  ErrorFrame' 'End TriggerBlock' >"$dir/session.asc"
        printf '%s\n' ';$FILEVERSION=2.1' ';$STARTTIME=45985.666666666664' ';$COLUMNS=N,O,T,B,I,d,R,L,D' \
            '      1         1.000 DT  1     0585 Rx -  4    19 6C 6F 67' >"$dir/session-2.1.trc"
        printf '%s\n' ';   Start time: 24.11.2025 16:00:00.000.0' '     1)      1841.0  Rx         0701  1  05' \
            >"$dir/session-1.1.trc"
        ;;
    node | socketcand | sdo_client) ;; # arbitrary bytes: no seeds needed
    esac
    if [[ "$name" == eds || "$name" == xml ]] && [ ! -d "$corpus_src" ]; then
        echo "note: no corpus at $corpus_src (set EDSGEN_CORPUS); seeding from what there is" >&2
    fi
}

for name in "${targets[@]}"; do
    seed "$name"
    args=(-max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1)
    case "$name" in
    eds | xml | esi) args+=(-max_len="$max_len" -dict="fuzz/dict/$name.dict") ;;
    decode | socketcand) args+=(-max_len=4096 -dict="fuzz/dict/$name.dict") ;;
    decode_log) args+=(-max_len=4096 -dict=fuzz/dict/decode.dict) ;;
    node | sdo_client) args+=(-max_len=4096) ;;
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
