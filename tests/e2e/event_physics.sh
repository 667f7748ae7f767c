#!/usr/bin/env bash
# The event model against hard-disk physics (bench/event_physics.py
# --check): the virial pressure and the collision rate within 3% of
# Henderson's equation of state, speeds Maxwell-Boltzmann (Kolmogorov's
# test), kinetic energy to 1e-12, at a dilute and a dense area fraction.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
PY=$(command -v python3) || fail "python3 is needed"
bench="$(dirname "$0")/../../bench/event_physics.py"
"$PY" "$bench" --psim "$PSIM" --n 1500 --etas "0.2 0.5" --steps 60,240 --check \
    >"$tmp/table.md" || { cat "$tmp/table.md" >&2; fail "the event model's physics is off"; }
cat "$tmp/table.md"
[[ $(grep -c '^| 0\.' "$tmp/table.md") == 2 ]] || fail "expected two rows in the table"
