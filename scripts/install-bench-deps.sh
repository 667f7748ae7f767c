#!/usr/bin/env bash
# Extra Debian 12 packages for the benchmarks and profiles (not the tests):
# matplotlib for bench/scaling, hyperfine, GNU time, perf and valgrind.
set -euo pipefail
bash "$(dirname "$0")/install-deps.sh"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get install -y -qq python3-matplotlib hyperfine time linux-perf valgrind
