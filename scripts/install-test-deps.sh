#!/usr/bin/env bash
# Install what the test suite needs on Debian 12 (as root or with sudo):
# psim's build dependencies (scripts/install-deps.sh), then g++ (the C++
# reference of CS267's random draws), hwloc's tools, likwid-pin, valgrind,
# and the Python packages the tests read outputs with (numpy, matplotlib,
# PIL, and ASE for the extended XYZ dumps).
set -euo pipefail
exec bash "$(dirname "$0")/install-deps.sh" g++ hwloc likwid valgrind \
  python3-numpy python3-matplotlib python3-pil python3-ase
