#!/usr/bin/env bash
# Restart files are not taken on trust.  For every model (psim models
# lists them), a restart file psim wrote goes on as the unbroken run, and
# the same file made hostile with sed and awk is refused: every header key
# and value (unknown, given twice, missing, out of range, not a number),
# the model's options, values and columns (unknown, twice, missing), and
# each column's values (text, empty, huge, not finite, fractional where the
# column holds whole numbers, beyond the column's range).  Each refusal is
# one line "psim: FILE:LINE: ..." naming the line (and the column), exit
# status 1, and no output and no temporary file left.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# a scene every model runs: no overlaps, every centre inside the walls
gen "$tmp/s.in" -n 60 -L 40 -s 8 --place nonoverlap --seed 2 --vmin -1 --vmax 1

mapfile -t models < <("$PSIM" models | awk '/^[a-z]/ {print $1}')
((${#models[@]} >= 2)) || fail "psim models lists ${#models[@]} models"

# the first option each model lists (none: empty)
first_option() {
    "$PSIM" models | awk -v m="$1" '/^[a-z]/ {cur = $1; next}
        cur == m && match($0, /--option [a-z_]+=/) {
            print substr($0, RSTART + 9, RLENGTH - 10); exit }'
}

# refused LINE WANT FILE [ARGS...]: psim refuses FILE: exit 1, one line
# "psim: FILE:LINE: ..." holding WANT, and none of the outputs asked for,
# nor a temporary file, left.
refused() {
    local line=$1 want=$2 file=$3
    shift 3
    expect_fail --rc 1 "$want" "$PSIM" -q --final "$tmp/never.final" \
        --restart "$tmp/never.rs" --out "$tmp/never.out" "$@" "$file"
    [[ $FAIL_LINE == "psim: $file:$line: "* ]] ||
        fail "$(basename "$file"): the error should name $file:$line: $FAIL_LINE"
    local left
    left=$(cd "$tmp" && ls -- never.* *.tmp* 2>/dev/null || true)
    [[ -z $left ]] || fail "$(basename "$file"): files left after a refusal: $left"
}

# header NAME MODEL SED: the model's restart file with its first line
# edited by the sed expression, as $tmp/NAME.rs
header() {
    sed "1{$3}" "$tmp/$2.rs" >"$tmp/$1.rs"
    cmp -s "$tmp/$1.rs" "$tmp/$2.rs" && fail "$1: the edit '$3' changed nothing"
    return 0
}

# field NAME MODEL LINE K VALUE: the model's restart file with field K of
# line LINE set to VALUE (the empty string drops the field)
field() {
    awk -v L="$3" -v K="$4" -v V="$5" 'NR == L {
            s = ""; for (i = 1; i <= NF; i++) if (i != K || V != "") s = s (s == "" ? "" : " ") (i == K ? V : $i)
            $0 = s }
        {print}' "$tmp/$2.rs" >"$tmp/$1.rs"
}

# --- psim's own restart files go on as the unbroken run ----------------------
for m in "${models[@]}"; do
    run_ok "$PSIM" -q --model "$m" --steps 8 --final "$tmp/$m.full" --restart "$tmp/$m.full.rs" \
        --out "$tmp/$m.full.out" "$tmp/s.in"
    run_ok "$PSIM" -q --model "$m" --steps 4 --restart "$tmp/$m.rs" --out "$tmp/$m.half.out" \
        "$tmp/s.in"
    head -1 "$tmp/$m.rs" | grep -q "^#psim restart 1 model=$m step=4 " ||
        fail "$m: restart header: $(head -1 "$tmp/$m.rs" | cut -c1-200)"
    run_ok "$PSIM" -q --final "$tmp/$m.two" --restart "$tmp/$m.two.rs" --out "$tmp/$m.two.out" \
        "$tmp/$m.rs"
    same_file "$tmp/$m.full" "$tmp/$m.two" "$m: 8 steps against 4, a restart and 4 more"
    same_file <(sed 5d "$tmp/$m.full.rs") <(sed 5d "$tmp/$m.two.rs") \
        "$m: the restart files after 8 steps"
done

# the longest first line psim writes, 513 cuts an axis of up to 5 digits
# (6 KB), is read (the cuts, which do not fit this grid, are left out);
# a longer one is refused at line 1
m=${models[0]}
cuts=$(seq 0 90 46080 | paste -sd,)
header long "$m" "s/ cuts=[^ ]*//; s/\$/ cuts=$cuts,$cuts/"
(($(head -1 "$tmp/long.rs" | wc -c) > 6000)) || fail "the long header is too short"
run_ok "$PSIM" -q --steps 1 --final "$tmp/long.final" "$tmp/long.rs"
cuts=$(seq 1000000000 1000 1000512000 | paste -sd,)
header longer "$m" "s/ cuts=[^ ]*//; s/\$/ cuts=0,$cuts,0,$cuts/"
refused 1 "line longer than 8192 bytes" "$tmp/longer.rs"

# --- the header ---------------------------------------------------------------
for m in "${models[@]}"; do
    header "$m.key" "$m" 's/$/ colour=red/'
    refused 1 "unknown key 'colour'" "$tmp/$m.key.rs"
    header "$m.twice" "$m" 's/$/ step=4/'
    refused 1 "key given twice: 'step'" "$tmp/$m.twice.rs"
    header "$m.nomodel" "$m" "s/ model=$m//"
    refused 1 "missing 'model=NAME'" "$tmp/$m.nomodel.rs"
    header "$m.nostep" "$m" 's/ step=4//'
    refused 1 "missing 'step=K'" "$tmp/$m.nostep.rs"
    header "$m.model" "$m" "s/ model=$m/ model=${m}x/"
    refused 1 "unknown model '${m}x'" "$tmp/$m.model.rs"
    for v in -1 1000000001 2.5 4e0 +4 x ''; do
        header "$m.step" "$m" "s/ step=4/ step=$v/"
        refused 1 "step must be an integer in 0..10^9, got '$v'" "$tmp/$m.step.rs"
    done
    for v in 2025 ''; do
        header "$m.format" "$m" "s/ format=[a-z0-9]*/ format=$v/"
        refused 1 "format must be 2024, 2019 or cs267" "$tmp/$m.format.rs"
    done
    header "$m.print" "$m" 's/ print=0/ print=2/'
    refused 1 "print must be 0 or 1, got '2'" "$tmp/$m.print.rs"
    header "$m.print1" "$m" 's/ format=[a-z0-9]*/ format=2024/; s/ print=0/ print=1/'
    refused 1 "print=1 is for format=2019" "$tmp/$m.print1.rs"
    # grids no model asks for: the engine would plan from them
    for v in 0,0,0 -1,0,0 1e999,0,0 1,0.5,0 1,-1,0 1,0,3 1,0,2.5 1,0,2097152 1,0 "1,0,0," \
        1,0,0,5,0,4,9 1,0,0,0,5,9,4 1,0,0,1,2,3 x,0,0; do
        header "$m.grid" "$m" "s/ grid=[^ ]*//; s/\$/ grid=$v/"
        refused 1 "grid must be REACH,OCC,TILE" "$tmp/$m.grid.rs"
    done
    # cuts: each axis 0 < ... < G, the same G, as many on each
    for v in 0,x,58 0,2,1,0,1,2 1,2,1,2 0,2,0,3 0,1,2 "0,1,0,1," 0,4294967296,0,4294967296; do
        header "$m.cuts" "$m" "s/ cuts=[^ ]*//; s/\$/ cuts=$v/"
        refused 1 "cuts must be" "$tmp/$m.cuts.rs"
    done
    # options: the model's own, each once, each in its range
    header "$m.opt" "$m" 's/ options=[^ ]*//; s/$/ options=nosuch=1/'
    refused 1 "restart header: the $m model has no option 'nosuch'" "$tmp/$m.opt.rs"
    header "$m.optnone" "$m" 's/ options=[^ ]*//; s/$/ options=/'
    refused 1 "options must be NAME=VALUE" "$tmp/$m.optnone.rs"
    o=$(first_option "$m")
    if [[ -n $o ]]; then
        header "$m.opttwice" "$m" "s/ options=[^ ]*//; s/\$/ options=$o=1,$o=1/"
        refused 1 "option $o given twice" "$tmp/$m.opttwice.rs"
        header "$m.optrange" "$m" "s/ options=[^ ]*//; s/\$/ options=$o=1e999/"
        refused 1 "restart header: option $o: '1e999' is too large for a double" "$tmp/$m.optrange.rs"
        header "$m.optcomma" "$m" "s/ options=[^ ]*//; s/\$/ options=$o=1,/"
        refused 1 "option '': expected NAME=VALUE" "$tmp/$m.optcomma.rs"
        # read by another model too: the file's model's options are checked
        for other in "${models[@]}"; do
            refused 1 "option $o given twice" "$tmp/$m.opttwice.rs" --model "$other"
        done
    fi
    # values: the model's own measured ones, each once, each finite
    header "$m.val" "$m" 's/ values=[^ ]*//; s/$/ values=nosuch:1/'
    refused 1 "unknown value 'nosuch' (the $m model's values:" "$tmp/$m.val.rs"
    val=$(head -1 "$tmp/$m.rs" | sed -n 's/.* values=\([a-z_0-9]*\):.*/\1/p')
    if [[ -n $val ]]; then
        header "$m.valtwice" "$m" "s/ values=/ values=$val:1,/"
        refused 1 "value given twice: '$val'" "$tmp/$m.valtwice.rs"
        for v in 1e999 x ''; do
            header "$m.valnum" "$m" "s/ values=$val:[^,]*/ values=$val:$v/"
            refused 1 "values must be NAME:NUMBER" "$tmp/$m.valnum.rs"
        done
    fi
    # the step count S (line 5): as a scene's
    for v in -1 1000000001 2.5 x; do
        field "$m.S" "$m" 5 1 "$v"
        refused 5 "step count S" "$tmp/$m.S.rs"
    done
done

# --- the model's columns ------------------------------------------------------
for m in "${models[@]}"; do
    cols=$(head -1 "$tmp/$m.rs" | sed -n 's/.* columns=\([^ ]*\).*/\1/p')
    if [[ -z $cols ]]; then
        # a model without columns takes none
        header "$m.col" "$m" 's/$/ columns=extra/'
        refused 1 "unknown column 'extra' (the $m model's columns: none)" "$tmp/$m.col.rs"
        continue
    fi
    IFS=, read -r -a col <<<"$cols"
    n=${#col[@]}
    header "$m.colname" "$m" "s/ columns=${col[0]}/ columns=${col[0]}x/"
    refused 1 "unknown column '${col[0]}x' (the $m model's columns: $cols)" "$tmp/$m.colname.rs"
    header "$m.coltwice" "$m" "s/ columns=${col[0]}/ columns=${col[0]},${col[0]}/"
    refused 1 "restart header: column" "$tmp/$m.coltwice.rs"
    # the last column gone from the header and from every line; the whole list gone
    sed "1s/,${col[n - 1]}//" "$tmp/$m.rs" | awk 'NR > 5 {NF--} {print}' >"$tmp/$m.colgone.rs"
    refused 1 "missing column '${col[n - 1]}'" "$tmp/$m.colgone.rs"
    header "$m.colsgone" "$m" 's/ columns=[^ ]*//'
    refused 1 "missing column '${col[0]}'" "$tmp/$m.colsgone.rs"
    # a field too many
    awk 'NR == 8 {$0 = $0 " 7"} {print}' "$tmp/$m.rs" >"$tmp/$m.extra.rs"
    refused 8 "unexpected text after ${col[n - 1]}" "$tmp/$m.extra.rs"

    for ((k = 0; k < n; k++)); do
        c=${col[k]} f=$((6 + k))
        # what no column takes, whatever its kind
        for v in x 0x10 nan inf -inf 1e999 -1e999 1,5 ''; do
            field "$m.bad" "$m" 8 "$f" "$v"
            refused 8 "" "$tmp/$m.bad.rs"
            # (an empty field moves the next ones: the error may name another)
            [[ -z $v || $FAIL_LINE == *"$c (field $f)"* ]] ||
                fail "$m: $c='$v': the error should name the column: $FAIL_LINE"
        done
        # the column's kind and range, as the refusal of text gives them
        field "$m.bad" "$m" 8 "$f" x
        refused 8 "$c (field $f) must be" "$tmp/$m.bad.rs"
        if [[ $FAIL_LINE =~ "must be a whole number in "(-?[0-9]+)\.\.([0-9]+) ]]; then
            lo=${BASH_REMATCH[1]} hi=${BASH_REMATCH[2]}
            ((hi <= 9007199254740992)) || fail "$m: $c: whole numbers up to $hi are not doubles"
            for v in 2.5 1.0 1e2 1e23 -9223372036854775809 9223372036854775808 \
                9007199254740993 $((lo - 1)) $((hi + 1)) "$hi.5"; do
                field "$m.int" "$m" 8 "$f" "$v"
                refused 8 "$c (field $f) must be a whole number in $lo..$hi, got '$v'" \
                    "$tmp/$m.int.rs"
            done
            # a count of its own (from 0, past 32 bits) goes on exactly
            if ((lo == 0 && hi >= 1 << 40)); then
                field "$m.big" "$m" 8 "$f" 123456789012
                run_ok "$PSIM" -q --steps 2 --restart "$tmp/$m.big2.rs" --out "$tmp/$m.big.out" \
                    "$tmp/$m.big.rs"
                id=$(sed -n 8p "$tmp/$m.rs" | cut -d' ' -f1)
                got=$(awk -v i="$id" -v f="$f" 'NR > 5 && $1 == i {print $f}' "$tmp/$m.big2.rs")
                [[ $got =~ ^[0-9]+$ ]] && ((got >= 123456789012 && got < 123456789012 + 100)) ||
                    fail "$m: $c of 123456789012 came back as '$got'"
            fi
        elif [[ $FAIL_LINE =~ "must be a number in ["([-0-9.e+]+)", "([-0-9.e+]+)"]" ]]; then
            lo=${BASH_REMATCH[1]} hi=${BASH_REMATCH[2]}
            for v in "$(awk -v x="$lo" 'BEGIN {printf "%.17g", x - 1 - x / 2}')" \
                "$(awk -v x="$hi" 'BEGIN {printf "%.17g", x + 1 + x / 2}')"; do
                field "$m.range" "$m" 8 "$f" "$v"
                refused 8 "$c (field $f) must be a number in [$lo, $hi], got '$v'" \
                    "$tmp/$m.range.rs"
            done
        else
            [[ $FAIL_LINE == *"must be a finite number"* ]] || fail "$m: $c: $FAIL_LINE"
            lo='' hi=''
        fi
        # the ends of its range: taken, or refused by the model at the line
        # (a value that depends on the scene), never used blindly
        for v in "$lo" "$hi"; do
            [[ -n $v ]] || continue
            field "$m.end" "$m" 8 "$f" "$v"
            rc=0
            "$PSIM" -q --check --steps 2 --final "$tmp/$m.end.final" "$tmp/$m.end.rs" \
                >/dev/null 2>"$tmp/end.err" || rc=$?
            if ((rc == 0)); then
                [[ -s $tmp/$m.end.final ]] || fail "$m: $c=$v: no final state"
            else
                ((rc == 1)) && [[ $(wc -l <"$tmp/end.err") == 1 ]] &&
                    grep -q "^psim: $tmp/$m.end.rs:8: .*$c" "$tmp/end.err" ||
                    fail "$m: $c=$v: exit $rc: $(cat "$tmp/end.err")"
                [[ ! -e $tmp/$m.end.final ]] || fail "$m: $c=$v: refused, but left its output"
            fi
            rm -f "$tmp/$m.end.final"
        done
        # checked whichever model reads the file, from standard input too
        field "$m.bad" "$m" 8 "$f" x
        for other in "${models[@]}"; do
            refused 8 "$c (field $f)" "$tmp/$m.bad.rs" --model "$other"
        done
        rc=0
        "$PSIM" -q --final "$tmp/never.final" - <"$tmp/$m.bad.rs" >/dev/null 2>"$tmp/stdin.err" ||
            rc=$?
        ((rc == 1)) || fail "$m: a bad restart from stdin: exit $rc"
        [[ $(wc -l <"$tmp/stdin.err") == 1 && $(cat "$tmp/stdin.err") == "psim: <stdin>:8: particle "*"$c (field $f)"* ]] ||
            fail "$m: a bad restart from stdin: $(cat "$tmp/stdin.err")"
        [[ ! -e $tmp/never.final ]] || fail "$m: a refused restart from stdin left its output"
    done
done

# --- what only the model can check, for the columns that depend on the scene
# (by the column's name, in whichever model has it) -------------------------
# model_refuses MODEL COLUMN VALUE WANT: line 8's COLUMN set to VALUE is refused
model_refuses() {
    local k
    k=$(head -1 "$tmp/$1.rs" | sed -n 's/.* columns=\([^ ]*\).*/\1/p' | tr , '\n' |
        grep -nx "$2" | cut -d: -f1) || return 0
    field "$1.model" "$1" 8 $((5 + k)) "$3"
    refused 8 "$4" "$tmp/$1.model.rs"
}
for m in "${models[@]}"; do
    id=$(sed -n 8p "$tmp/$m.rs" | cut -d' ' -f1)
    model_refuses "$m" t_own 4.5 "t_own 4.5 is after the file's step=4"
    model_refuses "$m" last "$id" "last $id is not another disk"
    model_refuses "$m" last 60 "last 60 is not another disk (0..59"
    model_refuses "$m" cell_x 100000 "cell_x, cell_y (100000, "
    model_refuses "$m" cell_y 100000 "cell_x, cell_y ("
    for c in cell_x cell_y; do
        k=$(head -1 "$tmp/$m.rs" | sed -n 's/.* columns=\([^ ]*\).*/\1/p' | tr , '\n' |
            grep -nx "$c" | cut -d: -f1) || continue
        v=$(sed -n 8p "$tmp/$m.rs" | cut -d' ' -f$((5 + k)))
        model_refuses "$m" "$c" $((v >= 2 ? v - 2 : v + 2)) "is not the cell of its position"
    done
done

echo "restart_hostile: ok (${models[*]})"
