#!/usr/bin/env bash
# Builds every sweep table in tables/ (the files with a [sweep] table) into
# OUT_DIR (default target/tables), resuming interrupted builds, and the plot
# and contact law of each. Failed points are masked in the tables; the script
# goes on with the other tables and exits 1 at the end if any table had
# failures or errors.
#
# Usage: scripts/nightly.sh [OUT_DIR] [CONFIG.toml ...]
#   TCGEN=path/to/tcgen   use this binary instead of building it
#   PYTHON=python3        the interpreter for the plots (skipped without xarray)
#   THREADS=n             worker threads (default: all cores)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$root/target/tables}"
shift || true
configs=("$@")
if [ ${#configs[@]} -eq 0 ]; then
    for f in "$root"/tables/*.toml; do
        grep -q '^\[sweep\]' "$f" && configs+=("$f")
    done
fi
if [ -z "${TCGEN:-}" ]; then
    export TCGEN_GIT_REVISION="${TCGEN_GIT_REVISION:-$(git -C "$root" describe --always --dirty --abbrev=12 2>/dev/null || echo unknown)}"
    (cd "$root" && cargo build --release -p tcgen --quiet)
    TCGEN="${CARGO_TARGET_DIR:-$root/target}/release/tcgen"
fi
python="${PYTHON:-python3}"
threads=()
[ -n "${THREADS:-}" ] && threads=(--threads "$THREADS")
mkdir -p "$out"
status=0
for cfg in "${configs[@]}"; do
    name="$(basename "$cfg" .toml)"
    table="$out/$name.h5"
    echo "== $name: $(date -u +%FT%TZ)"
    rc=0
    "$TCGEN" sweep "$cfg" -o "$table" --resume --progress log --log-interval 300 "${threads[@]}" || rc=$?
    if [ "$rc" -ne 0 ]; then
        echo "== $name: tcgen sweep exited with $rc"
        status=1
    fi
    if [ -f "$table" ]; then
        if "$python" -c "import xarray, matplotlib" 2>/dev/null; then
            "$python" "$root/scripts/inspect_table.py" "$table" --png "$out/$name.png" || status=1
        fi
        if [ "$rc" -eq 0 ]; then
            "$TCGEN" law "$table" -o "$out/$name.tclaw" || status=1
        fi
    fi
done
echo "== done: $(date -u +%FT%TZ), status $status"
exit "$status"
