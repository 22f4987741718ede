#!/usr/bin/env bash
# Prints the workspace's cargo target directory (absolute): `CARGO_TARGET_DIR` or the
# `[build] target-dir` of a cargo config when set, else `target/` at the workspace root; as
# cargo itself resolves it (`cargo metadata`). The scripts build and write only there.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cargo metadata --format-version 1 --no-deps --manifest-path "$root/Cargo.toml" |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])'
