#!/usr/bin/env bash
# Builds the Cortex-M4F firmware examples (firmware/src/bin/: CANopen nodes with NMT, heartbeat,
# SDO server, 4+4 PDOs, SYNC and EMCY over each example's OD, and ec_tx508, an EtherCAT
# SubDevice with CoE over a LAN9252 on SPI) and prints their flash and RAM use: text/data/bss
# from the image, and the node's RAM on main's stack (the size of the Node, or SubDevice, with its
# OD, which the image records in EDSGEN_NODE_RAM_BYTES).
#
# Three configurations: the default one, comparable with CANopenNode v4's default configuration
# (segmented SDO server without block transfer, no node guarding), and `full` (firmware feature
# `full`: SDO block transfer with CRC and node/life guarding too), and `lss` (the default one
# with the LSS slave, CiA 305), built into the workspace's target directory
# (scripts/target-dir.sh: CARGO_TARGET_DIR or target/), in firmware/, firmware-full/ and
# firmware-lss/.
#
# Fails (exit 1) when an image's flash or RAM exceeds its budget in budgets.toml.
set -euo pipefail
cd "$(dirname "$0")/.."
budgets=$(pwd)/budgets.toml
target=$(scripts/target-dir.sh)
cd firmware
rustup target add thumbv7em-none-eabihf >/dev/null 2>&1 || true
cargo build --release --quiet --locked --target-dir "$target/firmware"
cargo build --release --quiet --locked --features full --target-dir "$target/firmware-full"
cargo build --release --quiet --locked --features lss --target-dir "$target/firmware-lss"
size_tool=$(command -v llvm-size || true)
if [ -z "$size_tool" ]; then
    rustup component add llvm-tools >/dev/null 2>&1 || true
    size_tool=$(find "$(rustc --print sysroot)" -name llvm-size -type f | head -1)
fi
[ -n "$size_tool" ] || { echo "llvm-size not found (apt-get install llvm, or rustup component add llvm-tools)"; exit 2; }
# The budget `key` in budgets.toml.
budget() {
    awk -v key="$1" '$1 == key && $2 == "=" { print $3 }' "$budgets"
}
failed=0
# Checks `value` (bytes) against the budget `key`.
check() {
    local key=$1 value=$2 limit
    limit=$(budget "$key")
    [ -n "$limit" ] || { echo "no budget $key in $budgets"; exit 2; }
    if [ "$value" -gt "$limit" ]; then
        echo "OVER BUDGET: $key is $value bytes, the budget is $limit (budgets.toml)"
        failed=1
    else
        echo "$key: $value bytes (budget $limit)"
    fi
}
report() {
    local name=$1 elf=$2 key=$3
    echo "== $name"
    "$size_tool" "$elf"
    local ram
    ram=$(python3 - "$elf" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
# ELF32 little-endian: section headers, then the symbol table.
shoff, = struct.unpack_from("<I", data, 0x20)
shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
sections = [struct.unpack_from("<IIIIIIIIII", data, shoff + i * shentsize) for i in range(shnum)]
symtab = next(s for s in sections if s[1] == 2)
strtab = sections[symtab[6]]
for off in range(symtab[4], symtab[4] + symtab[5], 16):
    name, value, size, info, other, shndx = struct.unpack_from("<IIIBBH", data, off)
    end = data.index(b"\0", strtab[4] + name)
    if data[strtab[4] + name:end] == b"EDSGEN_NODE_RAM_BYTES":
        sec = sections[shndx]
        ram, = struct.unpack_from("<I", data, sec[4] + value - sec[3])
        print(ram)
        break
PY
)
    echo "node RAM (state + OD values, on main's stack): $ram bytes"
    check "$key.flash" "$("$size_tool" "$elf" | awk 'NR == 2 { print $1 + $2 }')"
    check "$key.ram" "$ram"
}
for src in src/bin/*.rs; do
    bin=$(basename "$src" .rs)
    report "$bin (segmented SDO, no node guarding: CANopenNode's default services)" \
        "$target/firmware/thumbv7em-none-eabihf/release/$bin" "$bin"
done
for src in src/bin/*.rs; do
    bin=$(basename "$src" .rs)
    report "$bin full (with SDO block transfer and node guarding)" \
        "$target/firmware-full/thumbv7em-none-eabihf/release/$bin" "${bin}_full"
done
# LSS is a CANopen service: the EtherCAT SubDevice image (ec_tx508) has no LSS set.
for src in src/bin/*.rs; do
    bin=$(basename "$src" .rs)
    [ "$bin" = ec_tx508 ] && continue
    report "$bin lss (the default services and the LSS slave, CiA 305)" \
        "$target/firmware-lss/thumbv7em-none-eabihf/release/$bin" "${bin}_lss"
done
exit "$failed"
