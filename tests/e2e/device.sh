#!/usr/bin/env bash
# --device: bad values exit 2 with one line; --device cpu is the default's
# bytes; every model `psim models` does not list as running on a CUDA
# device is refused one (exit 2, one line); a model that does is refused
# where psim was built without CUDA or sees no device (exit 2, one line
# saying which), and runs where there is one (the bytes: tests/gpu);
# psim topo says which CUDA devices it sees in one line or more.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

for bad in "" tpu GPU gpu: gpu:x gpu:-1 gpu:1x "gpu: 1" gpu:1024 gpu:99999999999999999999 cpu:0; do
    expect_fail --rc 2 "--device" "$PSIM" -q -n 100 -s 1 --device "$bad"
done
expect_fail --rc 2 "--device" "$PSIM" -q -n 100 -s 1 --device

# --device cpu: the default, byte for byte
run_ok "$PSIM" -q -n 500 -s 20 -o "$tmp/default.out"
run_ok "$PSIM" -q -n 500 -s 20 --device cpu -o "$tmp/cpu.out"
cmp "$tmp/default.out" "$tmp/cpu.out" || fail "--device cpu changed the output"

# which build and machine this is
built=1
"$PSIM" --version | grep -q "CUDA on" || built=0
"$PSIM" --version | grep -Eq "CUDA (on|off)" || fail "psim --version names no CUDA on/off"
"$PSIM" topo >"$tmp/topo.txt" || fail "psim topo failed"
devices=$(grep -c "^CUDA devices: " "$tmp/topo.txt" || true)
((devices == 1)) || fail "psim topo: expected one 'CUDA devices:' line, got $devices"
seen=1
grep -q "^CUDA devices: none (.\+)$" "$tmp/topo.txt" && seen=0
if ((built == 0)); then
    grep -q "^CUDA devices: none (psim was built without CUDA)$" "$tmp/topo.txt" ||
        fail "psim topo in a build without CUDA: $(grep '^CUDA' "$tmp/topo.txt")"
fi

run_ok "$PSIM" gen --n 200 --density 0.3 --r 1 --steps 5 --out "$tmp/s.in"
"$PSIM" models | awk '/^[a-z]/ { m = $1; print m, 0 } /runs on a CUDA device/ { print m, 1 }' |
    awk '{ g[$1] += $2 } END { for (m in g) print m, g[m] }' >"$tmp/models.txt"
[[ -s $tmp/models.txt ]] || fail "psim models listed no model"
gpu_models=0
while read -r model gpu; do
    if ((built == 0)); then
        expect_fail --rc 2 "psim was built without CUDA" "$PSIM" -q --model "$model" --device gpu "$tmp/s.in"
    elif ((gpu == 0)); then
        expect_fail --rc 2 "--device cpu runs it" "$PSIM" -q --model "$model" --device gpu "$tmp/s.in"
        [[ $FAIL_LINE == *"the $model model"* ]] || fail "$model: the refusal names no model: $FAIL_LINE"
    elif ((seen == 0)); then
        expect_fail --rc 2 "no CUDA device" "$PSIM" -q --model "$model" --device gpu "$tmp/s.in"
        expect_fail --rc 2 "no CUDA device" "$PSIM" -q --model "$model" --device gpu:3 "$tmp/s.in"
    else
        expect_fail --rc 2 "no such CUDA device" "$PSIM" -q --model "$model" --device gpu:1023 "$tmp/s.in"
    fi
    gpu_models=$((gpu_models + gpu))
done <"$tmp/models.txt"
((gpu_models >= 1)) || fail "psim models lists no model that runs on a CUDA device"
