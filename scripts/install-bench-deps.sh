#!/usr/bin/env bash
# Extra Debian 12 packages for the benchmarks and profiles (not the tests):
# matplotlib for bench/scaling, hyperfine, GNU time, perf and valgrind,
# with psim's build dependencies (scripts/install-deps.sh).
set -euo pipefail
exec bash "$(dirname "$0")/install-deps.sh" python3-matplotlib hyperfine time linux-perf valgrind
