#!/usr/bin/env bash
# Runs the cargo-fuzz targets (fuzz/fuzz_targets/) for a while; not part of CI (too long).
#
#   scripts/fuzz.sh [TARGET[,TARGET...]|all] [SECONDS]     (defaults: all, 900 seconds per target)
#
# TARGET: the readers eds, xml, esi, odva, gsd, gsdml, overlay; the CANopen runtime node,
# sdo_client, socketcand; the logs decode, decode_log; the wires enip, enip_scanner, pn_dcp,
# pn_rpc, pn_alarm, dp_fdl, ethercat_frame, ethercat_coe; demo_report. `scripts/fuzz.sh all 60`
# is the smoke run.
#
# Works on the stable toolchain: cargo-fuzz's nightly flags are allowed with RUSTC_BOOTSTRAP=1.
# Debug assertions are on (-a), so arithmetic overflow panics. FUZZ_SANITIZER picks the sanitizer:
# the default `none` runs the EDS target about 5 times faster than `address` (the crates under test
# have no `unsafe`; the point is panics, overflows, timeouts and memory blow-ups). Every target is
# built first, once; then FUZZ_JOBS targets (default 1) run at a time, each one libFuzzer process,
# single job. Run it under `nice -n 19` on a machine others build on.
#
# Seeds are copied at run time into fuzz/corpus/<target>/ (git-ignored): for eds the bundled cards
# (eds/*.eds) and the corpus's *.eds/*.dcf files up to the length limit; for xml the corpus's
# *.xdd/*.xdc files, each shrunk to fit the limit by fuzz/shrink_xml.py (a cut XML file is not
# well-formed, so it would only exercise the parser); for esi the bundled ESI and the ESI corpus's
# files, shrunk by fuzz/shrink_esi.py; for odva, gsd and gsdml the bundled cards and the ODVA EDS,
# GSD and GSDML corpora's files up to the length limit; for overlay the bundled overlays after the
# byte that picks their description; for decode, decode_log and socketcand short sessions written
# here; for the wire targets and demo_report fuzz/seeds/<target>/ (good exchanges recorded from
# the project's masters and simulated devices by fuzz/examples/seeds.rs). node and sdo_client
# start empty. The corpora are EDSGEN_CORPUS (else ../shared/eds-corpus), EDSGEN_ESI_CORPUS,
# EDSGEN_ODVA_CORPUS, EDSGEN_GSD_CORPUS and EDSGEN_GSDML_CORPUS (else ../shared/esi-corpus, ...);
# a missing corpus is noted and skipped. Logs go to fuzz/logs/<target>.log, findings to
# fuzz/artifacts/<target>/ (both git-ignored).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

target=${1:-all}
seconds=${2:-900}
sanitizer=${FUZZ_SANITIZER:-none}
max_len=65536
corpus_src=${EDSGEN_CORPUS:-$root/../shared/eds-corpus}
esi_src=${EDSGEN_ESI_CORPUS:-$root/../shared/esi-corpus}
odva_src=${EDSGEN_ODVA_CORPUS:-$root/../shared/odva-eds-corpus}
gsd_src=${EDSGEN_GSD_CORPUS:-$root/../shared/gsd-corpus}
gsdml_src=${EDSGEN_GSDML_CORPUS:-$root/../shared/gsdml-corpus}
jobs=${FUZZ_JOBS:-1}
all=(eds xml esi odva gsd gsdml overlay node sdo_client socketcand decode decode_log
    enip enip_scanner pn_dcp pn_rpc pn_alarm dp_fdl ethercat_frame ethercat_coe demo_report)

usage() {
    echo "usage: scripts/fuzz.sh [TARGET[,TARGET...]|all] [SECONDS]; TARGET one of: ${all[*]}" >&2
    exit 2
}
if [ "$target" = all ]; then
    targets=("${all[@]}")
else
    IFS=, read -r -a targets <<<"$target"
    for name in "${targets[@]}"; do
        [[ " ${all[*]} " == *" $name "* ]] || usage
    done
fi
[[ "$seconds" =~ ^[0-9]+$ && "$jobs" =~ ^[1-9][0-9]*$ ]] || usage

if ! cargo fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi
export RUSTC_BOOTSTRAP=1

# Copies the files of corpus $1 whose names end in one of the extensions $3... (any case) and
# that fit the length limit into $2, each named after its repository directory.
copy_corpus() {
    local src=$1 dir=$2
    shift 2
    if [ ! -d "$src" ]; then
        echo "note: no corpus at $src; seeding from what there is" >&2
        return
    fi
    local names=() ext
    for ext in "$@"; do names+=(-o -iname "*.$ext"); done
    find "$src" -type f \( "${names[@]:1}" \) -size -"$max_len"c -print0 |
        while IFS= read -r -d '' f; do
            cp "$f" "$dir/$(basename "$(dirname "$f")")__$(basename "$f")"
        done
}

seed() {
    local name=$1 dir=fuzz/corpus/$1
    mkdir -p "$dir"
    case "$name" in
    eds)
        cp eds/*.eds "$dir"/
        copy_corpus "$corpus_src" "$dir" eds dcf
        ;;
    xml)
        [ -d "$corpus_src" ] || echo "note: no corpus at $corpus_src; no seeds" >&2
        find "$corpus_src" -type f \( -iname '*.xdd' -o -iname '*.xdc' \) -print0 2>/dev/null |
            while IFS= read -r -d '' f; do
                python3 fuzz/shrink_xml.py "$f" "$dir/$(basename "$(dirname "$f")")__$(basename "$f")" "$max_len"
            done
        ;;
    esi)
        python3 fuzz/shrink_esi.py eds/ec-tx508.xml "$dir/ec-tx508.xml" "$max_len"
        [ -d "$esi_src" ] || echo "note: no ESI corpus at $esi_src; one seed" >&2
        find "$esi_src" -type f \( -iname '*.xml' -o -iname '*.esi' \) -print0 2>/dev/null |
            while IFS= read -r -d '' f; do
                python3 fuzz/shrink_esi.py "$f" "$dir/$(basename "$(dirname "$f")")__$(basename "$f")" "$max_len"
            done
        ;;
    odva)
        # The hand-written test file, the card's ODVA EDS and the ODVA EDS corpus's files.
        cp codegen/tests/odva/io.eds eds/goodrive350-enip.eds "$dir"/
        copy_corpus "$odva_src" "$dir" eds
        ;;
    gsd)
        # Even lengths are read as GSD by name, odd ones by content; five files are over the limit.
        cp eds/*.gsd "$dir"/
        copy_corpus "$gsd_src" "$dir" gsd gse gsg gsi gsf
        ;;
    gsdml)
        # Three files are over the limit (two Siemens files and a SEW one, 100 KiB to 1.1 MiB).
        cp eds/goodrive350-pn.xml "$dir"/
        copy_corpus "$gsdml_src" "$dir" xml
        ;;
    overlay)
        # The first byte picks the description: 0 GSDML, 1 GSD, 2 ODVA EDS, 3 CiA 306 EDS.
        local pick=0 toml
        for toml in eds/goodrive350-{pn,dp,enip}.toml eds/rd11.toml; do
            { printf "\\x0$pick"; cat "$toml"; } >"$dir/$pick-$(basename "$toml")"
            pick=$((pick + 1))
        done
        ;;
    socketcand)
        # A client's session with the hub and the frames it is sent (< > delimit each message).
        printf '%s' '< hi >< open can0 >< ok >< rawmode >< ok >' \
            '< send 602 8 40 18 10 01 00 00 00 00 >' \
            '< frame 582 1764000000.000100 4318100178563412 >< echo >< bcmmode >' \
            '< add 0 100000 123 2 AA BB >< update 0 100000 123 2 CC DD >< delete 0 0 123 >' \
            '< filter 0 0 1 602 >< frame 12345678 23.424242 >< error 0 >' >"$dir/session.txt"
        ;;
    enip | enip_scanner | pn_dcp | pn_rpc | pn_alarm | dp_fdl | ethercat_* | demo_report)
        cp fuzz/seeds/"$name"/* "$dir"/
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
    node | sdo_client) ;; # arbitrary bytes: no seeds needed
    esac
}

# libFuzzer's options for `name`: the length limit and the dictionary that fit its input.
options() {
    local name=$1
    case "$name" in
    eds | odva) echo -max_len="$max_len" -dict=fuzz/dict/eds.dict ;;
    xml | esi | gsd | gsdml) echo -max_len="$max_len" -dict="fuzz/dict/$name.dict" ;;
    decode | decode_log) echo -max_len=4096 -dict=fuzz/dict/decode.dict ;;
    socketcand | overlay) echo -max_len=4096 -dict="fuzz/dict/$name.dict" ;;
    *) echo -max_len=4096 ;;
    esac
}

# Runs one target; prints libFuzzer's findings and its last status line; fails with the target.
run() {
    local name=$1 log=fuzz/logs/$1.log status=0
    # shellcheck disable=SC2046 # the options are words
    cargo fuzz run "$name" -s "$sanitizer" -a -- -max_total_time="$seconds" -rss_limit_mb=2048 \
        -timeout=10 -print_final_stats=1 $(options "$name") >"$log" 2>&1 || status=$?
    {
        echo "== $name: ${seconds}s, log $log"
        grep -E "^(==[0-9]+==|thread '|SUMMARY|Test unit written)" "$log" || true
        # libFuzzer's last status line (executions, coverage, features) and its run count.
        grep -E '^#[0-9]+' "$log" | tail -1 || true
        grep -E '^Done [0-9]+ runs' "$log" || true
        if [ "$status" -ne 0 ]; then
            tail -20 "$log"
            echo "$name: failed (exit $status); findings are in fuzz/artifacts/$name/"
        fi
    } >&2
    return "$status"
}

mkdir -p fuzz/logs
for name in "${targets[@]}"; do
    seed "$name"
done
echo "== building ${#targets[@]} target(s), sanitizer $sanitizer" >&2
cargo fuzz build -s "$sanitizer" -a >fuzz/logs/build.log 2>&1 || {
    tail -20 fuzz/logs/build.log >&2
    exit 1
}
# FUZZ_JOBS targets at a time; `wait -n -p` says which one ended.
declare -A pids=()
failed=()
finish() {
    local pid status=0
    wait -n -p pid || status=$?
    [ "$status" -eq 0 ] || failed+=("${pids[$pid]}")
    unset "pids[$pid]"
}
for name in "${targets[@]}"; do
    [ "${#pids[@]}" -lt "$jobs" ] || finish
    run "$name" &
    pids[$!]=$name
done
while [ "${#pids[@]}" -gt 0 ]; do
    finish
done
if [ "${#failed[@]}" -ne 0 ]; then
    echo "failed: ${failed[*]}; findings are in fuzz/artifacts/" >&2
    exit 1
fi
