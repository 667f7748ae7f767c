#!/usr/bin/env bash
# The source layers include one way only.  From the top:
#   src/cli            the program
#   src/models         the models: one folder each, plus the registry and
#                      scene glue at src/models/ itself
#   src/engine         what every model runs on
#   src/io             files: scenes, restart files, number text
#   src/topology       hwloc topology and pinning (include/psim/topology.h),
#                      which only the program uses
#   src/base           what every layer uses (errors, the version)
#   include/psim       the public headers
# A file may include a header of its own layer or of one below, except
# the topology layer's (src/topology, include/psim/topology.h), which only
# src/cli and the topology layer may include; a model's folder includes no
# other model's folder.  The example models under examples/model/ are
# checked as the model folders they become under src/models/.  Every
# `#include "..."` of src/, include/ and examples/model/ is resolved as the
# compiler does (the including file's folder, then src/, then include/);
# one that resolves to no file of the tree fails too.  Last, a copy of the
# tree with a planted upward include must fail, naming its file and line.
set -euo pipefail
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

src=$(cd "$(dirname "$0")/../.." && pwd)

# rank PATH: the layer of a tree-relative path, as a number (higher is
# above), or nothing for a path in no layer
rank()
{
    case $1 in
        include/psim/topology.h | src/topology/*) echo 2 ;;
        include/psim/*) echo 0 ;;
        src/base/*) echo 1 ;;
        src/io/*) echo 3 ;;
        src/engine/*) echo 4 ;;
        src/models/*) echo 5 ;;
        src/cli/*) echo 6 ;;
    esac
}
name_of=([0]=include/psim [1]=src/base [2]=src/topology [3]=src/io [4]=src/engine
         [5]=src/models [6]=src/cli)

# model_folder PATH: the model folder a path under src/models/ is in, or
# nothing for the files at src/models/ itself
model_folder()
{
    local rest=${1#src/models/}
    [[ $1 == src/models/* && $rest == */* ]] && echo "${rest%%/*}"
    return 0
}

# check ROOT COUNT_FILE: print one line "FILE:LINE: why" per include
# against the layers; the number of includes checked goes to COUNT_FILE
check()
{
    local root=$1 count_file=$2 count=0 file real as dir lineno inc target t ra rb fa fb
    while IFS= read -r file; do
        real=${file#"$root"/}
        as=$real
        # an example model is checked where it goes: src/models/NAME/
        [[ $real == examples/model/* ]] && as=src/models/${real#examples/model/}
        ra=$(rank "$as")
        if [[ -z $ra ]]; then
            echo "$real:1: in no layer (${name_of[*]})"
            continue
        fi
        while IFS=: read -r lineno inc; do
            count=$((count + 1))
            inc=${inc#*\"}
            inc=${inc%%\"*}
            target=
            # the including file's folder: its own (an example's sources
            # beside it), then the one it is checked as
            for dir in "$(dirname "$real")" "$(dirname "$as")" src include; do
                t=$(realpath -m --relative-to="$root" "$root/$dir/$inc")
                if [[ -f $root/$t && $t != ../* ]]; then
                    target=$t
                    break
                fi
            done
            if [[ -z $target ]]; then
                echo "$real:$lineno: \"$inc\" is no file of the tree"
                continue
            fi
            [[ $target == examples/model/* ]] && target=src/models/${target#examples/model/}
            rb=$(rank "$target")
            if [[ -z $rb ]]; then
                echo "$real:$lineno: \"$inc\" ($target) is in no layer"
            elif ((rb == 2 && ra != 2 && ra != 6)); then
                echo "$real:$lineno: \"$inc\": ${name_of[ra]} includes the topology layer ($target), which only src/cli may"
            elif ((rb > ra)); then
                echo "$real:$lineno: \"$inc\": ${name_of[ra]} includes $target of ${name_of[rb]}, a layer above it"
            elif ((ra == 5 && rb == 5)); then
                fa=$(model_folder "$as")
                fb=$(model_folder "$target")
                if [[ -n $fa && -n $fb && $fa != "$fb" ]]; then
                    echo "$real:$lineno: \"$inc\": model folder src/models/$fa includes $target of another model's folder"
                fi
            fi
        done < <(grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$root/$real" || true)
    done < <(find "$root/src" "$root/include" "$root/examples/model" -type f \
                  \( -name '*.c' -o -name '*.h' \) 2>/dev/null | sort)
    echo "$count" >"$count_file"
}

check "$src" "$tmp/count" >"$tmp/violations"
if [[ -s $tmp/violations ]]; then
    sed 's/^/  /' "$tmp/violations" >&2
    fail "$(wc -l <"$tmp/violations") include(s) against the layers (above)"
fi
# a real check: the tree's includes were read, in every layer
(($(cat "$tmp/count") >= 50)) || fail "only $(cat "$tmp/count") includes found under $src"

# The checker finds what it should: a copy of the tree with an upward
# include in io, a topology include in engine, and one model folder
# including another's, each named by file and line.
copy=$tmp/tree
mkdir -p "$copy"
cp -r "$src/src" "$src/include" "$copy/"
if [[ -d $src/examples/model ]]; then
    mkdir -p "$copy/examples"
    cp -r "$src/examples/model" "$copy/examples/"
fi
models=()
for d in "$copy"/src/models/*/; do
    models+=("$(basename "$d")")
done
((${#models[@]} >= 2)) || fail "fewer than two model folders under src/models"
printf '#include "../engine/engine.h"\n' >"$copy/src/io/planted_up.c"
printf '/* a */\n#include "psim/topology.h"\n' >"$copy/src/engine/planted_topo.c"
printf '\n\n#include "../%s/planted.h"\n' "${models[1]}" >"$copy/src/models/${models[0]}/planted.c"
: >"$copy/src/models/${models[1]}/planted.h"
printf '#include "no/such/header.h"\n' >"$copy/src/base/planted_missing.c"
check "$copy" "$tmp/count" >"$tmp/planted"
for want in "src/io/planted_up.c:1: " "src/engine/planted_topo.c:2: " \
            "src/models/${models[0]}/planted.c:3: " "src/base/planted_missing.c:1: "; do
    grep -qF "$want" "$tmp/planted" || fail "a planted violation at $want was not found:
$(sed 's/^/  | /' "$tmp/planted")"
done
(($(wc -l <"$tmp/planted") == 4)) || fail "expected the 4 planted violations alone, got:
$(sed 's/^/  | /' "$tmp/planted")"
echo "layers: ok ($(find "$src/src" -name '*.[ch]' | wc -l) source files)"
