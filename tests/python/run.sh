#!/usr/bin/env bash
# The Python table tests in one command: creates a virtual environment under
# the target directory, installs the pinned requirements, builds tcgen
# (release) and the demo table, and runs pytest.
#   tests/python/run.sh [pytest args]
# Environment: CARGO_TARGET_DIR (default target/), PYTHON (default python3),
# TCGEN_DEMO_TABLE (reuse this demo table instead of building it).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
. "$root/tests/python/venv.sh"
(cd "$root" && cargo build --release -p tcgen --quiet)
export TCGEN_BIN="$target/release/tcgen"
export TCGEN_PYTHON="$venv/bin/python"
export TCGEN_TEST_DIR="$target/python-tests"
mkdir -p "$TCGEN_TEST_DIR"
if [ -z "${TCGEN_DEMO_TABLE:-}" ]; then
    export TCGEN_DEMO_TABLE="$TCGEN_TEST_DIR/demo.h5"
    rm -f "$TCGEN_DEMO_TABLE" "$TCGEN_DEMO_TABLE.checkpoint"
    "$TCGEN_BIN" sweep "$root/tables/demo.toml" -o "$TCGEN_DEMO_TABLE" --progress log --log-interval 30
fi
cd "$root"
exec "$venv/bin/python" -m pytest -q "$root/tests/python" "$@"
