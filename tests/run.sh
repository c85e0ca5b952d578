#!/usr/bin/env bash
# The project's test command (README "Set-up", and .ci/run).
# Runs the Rust test suite of the whole workspace in release mode.
# Long validation runs are opt-in: TCGEN_LONG_TESTS=1 tests/run.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --workspace
