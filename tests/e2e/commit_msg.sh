#!/usr/bin/env bash
# The commit message rule (scripts/git-hooks/commit-msg): a subject of at
# most 72 characters, then a blank line, then the body.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
hook=$(cd "$(dirname "$0")/../.." && pwd)/scripts/git-hooks/commit-msg
[[ -x $hook ]] || fail "$hook is not executable"

msg() { printf '%s' "$1" >"$tmp/msg"; }

msg $'engine: drop the sort the models never used\n\nBody with figures.\n'
run_ok "$hook" "$tmp/msg"
msg $'# a comment git strips\nsubject\n'
run_ok "$hook" "$tmp/msg"
msg "$(printf 'x%.0s' {1..72})"
run_ok "$hook" "$tmp/msg"
msg "$(printf 'é%.0s' {1..72})"            # characters, not bytes
run_ok "$hook" "$tmp/msg"

msg "$(printf 'x%.0s' {1..73})"
expect_fail --rc 1 "73 characters" "$hook" "$tmp/msg"
msg $'subject\nbody without a blank line\n'
expect_fail --rc 1 "blank line" "$hook" "$tmp/msg"
msg $'\n\n'
expect_fail --rc 1 "empty subject" "$hook" "$tmp/msg"
echo "ok"
