#!/usr/bin/env bash
# The table of malformed inputs (tests/e2e/data/malformed.table): every
# case across the scene formats, the models' own rules and the command
# line exits with its status (1 bad input, 2 bad usage), writes one line on
# stderr naming the file and line where a line is at fault, and leaves no
# output file and no temporary file behind.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"
TABLE=$(dirname "$0")/data/malformed.table
[[ -r $TABLE ]] || fail "no table $TABLE"

H='2\n10\n1\n5\n'
P='0 1 1 0 0\n1 5 5 0 0\n'

trim()
{
    local s=$1
    s=${s#"${s%%[![:space:]]*}"}
    printf '%s' "${s%"${s##*[![:space:]]}"}"
}

cases=0
while IFS='|' read -r name rc line want args content; do
    name=$(trim "$name")
    [[ -z $name || $name == \#* ]] && continue
    rc=$(trim "$rc") line=$(trim "$line") want=$(trim "$want") args=$(trim "$args")
    content=$(trim "$content")
    content=${content//\{H\}/$H}
    content=${content//\{P\}/$P}
    scene=$tmp/$name.in
    # shellcheck disable=SC2059 # the table's content is a printf format
    printf -- "$content" >"$scene"
    args=${args//\{SCENE\}/$scene}
    args=${args//\{TMP\}/$tmp}
    local_scene=("$scene")
    if [[ $args == *"{NOSCENE}"* ]]; then
        args=${args//\{NOSCENE\}/}
        local_scene=()
    fi
    read -ra a <<<"$args"
    expect_fail --rc "$rc" "$want" "$PSIM" --out "$tmp/o.txt" --trace "$tmp/t.txt" \
        --stats "$tmp/s.json" "${a[@]}" "${local_scene[@]}"
    if [[ $line != - ]]; then
        [[ $FAIL_LINE == "psim: $scene:$line: "* ]] ||
            fail "$name: expected 'psim: $scene:$line: ...', got: $FAIL_LINE"
    fi
    left=$(cd "$tmp" && ls -- o.txt* t.txt* s.json* 2>/dev/null || true)
    [[ -z $left ]] || fail "$name: output left behind: $left"
    cases=$((cases + 1))
done <"$TABLE"
((cases >= 100)) || fail "the table has $cases cases, fewer than 100"
echo "malformed: $cases cases ok"
