#!/usr/bin/env bash
# Install what building and running psim need on Debian 12 (as root or with
# sudo): the compiler, CMake, Ninja, pkg-config, hwloc, jemalloc, Open MPI and
# python3 (the man page and the completion are written from --help at build
# time).  Package names given as arguments are installed with them
# (scripts/install-test-deps.sh, scripts/install-bench-deps.sh).
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config libjemalloc-dev libhwloc-dev libopenmpi-dev
      openmpi-bin python3 "$@")
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
