#!/usr/bin/env bash
# Extra Debian 12 packages for the benchmarks and profiles (not the tests):
# matplotlib for bench/scaling, hyperfine, GNU time, perf and valgrind.
set -euo pipefail
bash "$(dirname "$0")/install-deps.sh"
pkgs=(python3-matplotlib hyperfine time linux-perf valgrind)
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
