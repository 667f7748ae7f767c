#!/usr/bin/env bash
# Install what the test suite needs on Debian 12 (as root or with sudo):
# psim's build dependencies (scripts/install-deps.sh), then g++ (the C++
# reference of CS267's random draws), hwloc's tools, valgrind, LIKWID (the
# marker build's test, tests/likwid), and the Python packages the tests
# read outputs with (numpy, matplotlib, PIL).
set -euo pipefail
bash "$(dirname "$0")/install-deps.sh"
pkgs=(g++ hwloc valgrind likwid python3-numpy python3-matplotlib python3-pil)
missing=()
for p in "${pkgs[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq "${missing[@]}"
fi
