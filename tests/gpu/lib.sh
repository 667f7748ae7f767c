# The GPU tests' helpers, over tests/e2e/lib.sh (which this sources with
# the test's arguments): same NAME ARGS... runs psim ARGS at one thread
# and on the GPU and compares their -o and --final byte for byte.
# shellcheck source=../e2e/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/../e2e/lib.sh" "$@"

same()
{
    local name=$1
    shift
    run_ok "$PSIM" -q "$@" --threads 1 -o "$tmp/$name.cpu.out" --final "$tmp/$name.cpu.fin"
    run_ok "$PSIM" -q "$@" --device gpu -o "$tmp/$name.gpu.out" --final "$tmp/$name.gpu.fin"
    [[ -s $tmp/$name.cpu.out && -s $tmp/$name.cpu.fin ]] || fail "$name: no CPU output"
    cmp "$tmp/$name.cpu.out" "$tmp/$name.gpu.out" || fail "$name: -o differs: psim $* --device gpu"
    cmp "$tmp/$name.cpu.fin" "$tmp/$name.gpu.fin" || fail "$name: --final differs: psim $* --device gpu"
}
