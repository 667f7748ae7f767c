#!/usr/bin/env bash
# unit.cs267_random_vs_cxx: psim's C versions of std::mt19937 and libstdc++'s
# distributions (src/io/cs267_random.c, printed by `test_cs267_random dump`)
# against the real ones (tests/unit/cs267_random_ref.cpp, built by g++),
# byte for byte.  Usage: cs267_random_vs_cxx.sh TEST_EXE REF_EXE
set -u
c_exe=$1 ref_exe=${2:-}
if [ -z "$ref_exe" ] || [ ! -x "$ref_exe" ]; then
  echo "FAIL: no C++ reference program: CMake found no C++ compiler (install g++: scripts/install-test-deps.sh)" >&2
  exit 1
fi
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
"$c_exe" dump >"$tmp/c.txt" || { echo "FAIL: $c_exe dump exited $?" >&2; exit 1; }
"$ref_exe" >"$tmp/cxx.txt" || { echo "FAIL: $ref_exe exited $?" >&2; exit 1; }
if ! cmp -s "$tmp/c.txt" "$tmp/cxx.txt"; then
  echo "FAIL: C and C++ draws differ:" >&2
  diff "$tmp/cxx.txt" "$tmp/c.txt" | head -20 >&2
  exit 1
fi
echo "OK: $(wc -l <"$tmp/c.txt") lines identical"
