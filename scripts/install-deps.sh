#!/usr/bin/env bash
# Install psim's build and test dependencies on Debian 12 (as root or with sudo).
set -euo pipefail
pkgs=(build-essential g++ cmake ninja-build pkg-config libjemalloc-dev libhwloc-dev
      hwloc python3 python3-matplotlib python3-pil valgrind)
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
