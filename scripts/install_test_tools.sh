#!/usr/bin/env bash
# System tools the test suite uses beyond the Rust toolchain, gcc and Python:
#   gfortran — compiles the Fortran GAPCON examples (lookup/examples/*.f)
#              against the C ABI (lookup/tests/fortran_examples.rs);
#   ccx      — the CalculiX solver (Debian package calculix-ccx), which runs
#              the *GAP CONDUCTANCE export end to end
#              (generator/tests/suite/calculix_end_to_end.rs).
# Installed with apt-get when missing and the machine allows it (root or
# passwordless sudo). Where it cannot be installed the script says so; the
# Fortran test then reports that it did not compile the examples, and the
# CalculiX test fails with that message.
set -uo pipefail
missing=()
command -v gfortran >/dev/null 2>&1 || missing+=(gfortran)
command -v ccx >/dev/null 2>&1 || missing+=(calculix-ccx)
[ ${#missing[@]} -eq 0 ] && exit 0
if ! command -v apt-get >/dev/null 2>&1; then
    echo "install_test_tools: apt-get not found; please install: ${missing[*]}" >&2
    exit 0
fi
if [ "$(id -u)" -eq 0 ]; then
    sudo=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    sudo=(sudo -n)
else
    echo "install_test_tools: not root and no passwordless sudo; please install: ${missing[*]}" >&2
    exit 0
fi
echo "install_test_tools: installing ${missing[*]} (apt-get)"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq >/dev/null 2>&1 || true
if ! "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null 2>&1; then
    echo "install_test_tools: apt-get install ${missing[*]} failed" >&2
fi
exit 0
