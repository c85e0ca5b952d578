#!/usr/bin/env bash
# The plots of docs/validation.md in one command: builds tcgen (release),
# runs the verification cases of the page with `tcgen verify --data` into
# target/validation-data (checks.json and one CSV per case), and draws them
# with scripts/plot_validation.py into docs/validation/ (the venv of
# tests/python/run.sh, pinned matplotlib).
#   scripts/validation.sh            # default resolution (a few minutes on 2 cores)
#   TCGEN_LONG_TESTS=1 scripts/validation.sh   # finer meshes, more points
# Environment: CARGO_TARGET_DIR (default target/), PYTHON (default python3),
# VALIDATION_DATA (default $CARGO_TARGET_DIR/validation-data),
# VALIDATION_OUT (default docs/validation).
# Exit status: that of `tcgen verify` (1 if a check failed; the plots are
# drawn anyway).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
. "$root/tests/python/venv.sh"
data="${VALIDATION_DATA:-$target/validation-data}"
out="${VALIDATION_OUT:-$root/docs/validation}"
cases="mms_,newton_quadratic,contact_hertz,contact_wavy,lateral"
cases="$cases,size_effects_resistive,scale_separation,textured_conforming"
cases="$cases,self_consistency,height_saturation,hbp_validation,plane_strain"
(cd "$root" && cargo build --release -p tcgen --quiet)
rm -rf "$data"
status=0
"$target/release/tcgen" verify --filter "$cases" --data "$data" || status=$?
"$venv/bin/python" "$root/scripts/plot_validation.py" "$data" "$out"
exit "$status"
