#!/usr/bin/env bash
# The project's test command (README "Set-up", and .ci/run):
#   1. the Rust test suite of the whole workspace, release mode;
#   2. the Python tests (xarray, h5py, netCDF4 read the demo table; meshio
#      reads the `tcgen solve --vtk` output):
#      tests/python/run.sh creates its own virtual environment (pinned
#      requirements from PyPI), builds the demo table and runs pytest.
# Long validation runs are opt-in: TCGEN_LONG_TESTS=1 tests/run.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_test_tools.sh   # gfortran (Fortran GAPCON examples) and ccx (CalculiX end-to-end test), if missing
cargo test --release --workspace
tests/python/run.sh
