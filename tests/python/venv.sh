# Sourced by tests/python/run.sh and scripts/validation.sh: creates (or
# reuses) the virtual environment with the pinned requirements under the
# target directory and sets `venv` to it.
# Needs `root` (the repository); environment: CARGO_TARGET_DIR (default
# target/), PYTHON (default python3).
target="${CARGO_TARGET_DIR:-$root/target}"
venv="$target/python-venv"
req="$root/tests/python/requirements.txt"
if [ ! -x "$venv/bin/python" ] || ! cmp -s "$req" "$venv/requirements.txt"; then
    rm -rf "$venv"
    "${PYTHON:-python3}" -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --upgrade pip
    "$venv/bin/python" -m pip install --quiet -r "$req"
    cp "$req" "$venv/requirements.txt"
fi
