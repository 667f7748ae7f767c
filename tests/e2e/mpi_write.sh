#!/usr/bin/env bash
# Outputs over MPI ranks, written in parallel: every output of states
# (-o, --trace, --final, --restart, --dump) is the bytes of one process
# for 2-4 ranks x 1-2 threads, also written in many rounds, with fewer
# particles than ranks, to standard output, a FIFO and over a checkpoint;
# a write that fails on one rank leaves no file and no temporary file,
# and every rank exits non-zero.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

if ! mpi_setup; then
    echo "ok: psim built without MPI: no ranks to write (tests/e2e/mpi_force.sh checks the refusal)"
    exit 0
fi

# mpi R ARGS...: psim over R ranks (PSIM_PART_LINES passed on when set:
# a rank's part of a round of the writes, in lines; PSIM_TMPFILE=0: the
# outputs through named temporary files, as where ranks run on several
# machines)
mpi() {
    local r=$1
    shift
    mpirun -q --oversubscribe -x PSIM_PART_LINES -x PSIM_TMPFILE -np "$r" "$PSIM" "$@"
}
export PSIM_PART_LINES= PSIM_TMPFILE=

kinds=(txt tr fin rs xyz)
# outs PREFIX: every output of states, to PREFIX.KIND
outs() { echo -o "$1.txt" --trace "$1.tr" --final "$1.fin" --restart "$1.rs" --dump "$1.xyz"; }

# Scenes: 1000 disks (not a multiple of 3), and 1, 2, 3 and 5 disks in a
# large box (fewer disks than ranks: empty parts).
gen "$tmp/s1000.in" -n 1000 -L 40 -r 0.5 -s 12 --seed 4
for n in 1 2 3 5; do
    gen "$tmp/s$n.in" -n "$n" -L 100 -r 1 -s 4 --seed "$n"
done
for s in 1000 1 2 3 5; do
    for t in 1 2; do
        # (the restart file's grid plan follows the thread count)
        # shellcheck disable=SC2046
        run_ok "$PSIM" --model force "$tmp/s$s.in" --threads "$t" -q $(outs "$tmp/one")
        [[ $s != 1000 ]] || (($(wc -l <"$tmp/one.tr") == 12 * 1000)) ||
            fail "the trace of one process has $(wc -l <"$tmp/one.tr") lines"
        for r in 2 3 4; do
            # (1000 disks also in many rounds: parts of 7 lines)
            rounds=("")
            [[ $s != 1000 ]] || rounds+=(7)
            for parts in "${rounds[@]}"; do
                export PSIM_PART_LINES=$parts
                rm -f "$tmp"/r.*
                # shellcheck disable=SC2046
                run_ok mpi "$r" --model force "$tmp/s$s.in" --threads "$t" -q $(outs "$tmp/r")
                for k in "${kinds[@]}"; do
                    same_file "$tmp/one.$k" "$tmp/r.$k" \
                        "$s disks, $r ranks x $t threads${parts:+, parts of $parts lines}: .$k"
                done
            done
        done
    done
done
export PSIM_PART_LINES=
echo "ok: every output over 2-4 ranks x 1-2 threads has the bytes of one process"

# Through named temporary files.
# shellcheck disable=SC2046
run_ok "$PSIM" --model force "$tmp/s1000.in" --threads 2 -q $(outs "$tmp/one")
for r in 2 3; do
    rm -f "$tmp"/r.*
    # shellcheck disable=SC2046
    PSIM_TMPFILE=0 PSIM_PART_LINES=100 run_ok mpi "$r" --model force "$tmp/s1000.in" \
        --threads 2 -q $(outs "$tmp/r")
    for k in "${kinds[@]}"; do
        same_file "$tmp/one.$k" "$tmp/r.$k" "$r ranks, named temporary files: .$k"
    done
done
compgen -G "$tmp/.psim-*" >/dev/null && fail "a temporary file was left"
echo "ok: the same through named temporary files"

# Outputs that are not regular files, which rank 0 writes alone: standard
# output and a FIFO.
args=(--model force "$tmp/s1000.in" --threads 1 -q)
run_ok "$PSIM" "${args[@]}" -o - --trace "$tmp/one.tr" >"$tmp/one.out"
[[ -s $tmp/one.out ]] || fail "no output on standard output"
mkfifo "$tmp/fifo"
for r in 2 3; do
    cat "$tmp/fifo" >"$tmp/r.tr" &
    reader=$!
    PSIM_PART_LINES=50 run_ok mpi "$r" "${args[@]}" -o - --trace "$tmp/fifo" >"$tmp/r.out"
    wait "$reader"
    same_file "$tmp/one.out" "$tmp/r.out" "$r ranks: -o on standard output"
    same_file "$tmp/one.tr" "$tmp/r.tr" "$r ranks: --trace to a FIFO"
done
echo "ok: standard output and a FIFO over ranks"

# Checkpoints (--restart-every): the last one, and the file over an old one.
run_ok "$PSIM" "${args[@]}" --restart "$tmp/one.rs" --restart-every 5 --final "$tmp/one.fin"
echo old >"$tmp/r.fin"
for r in 2 4; do
    rm -f "$tmp/r.rs"
    PSIM_PART_LINES=100 run_ok mpi "$r" "${args[@]}" --restart "$tmp/r.rs" --restart-every 5 \
        --final "$tmp/r.fin"
    same_file "$tmp/one.rs" "$tmp/r.rs" "$r ranks: --restart-every"
    same_file "$tmp/one.fin" "$tmp/r.fin" "$r ranks: --final over an old file"
done
echo "ok: checkpoints over ranks"

# Failures.  A write that fails on rank 1 alone: its file size limit (1
# KB blocks) lies below its first part, written by itself (ompio's
# individual writes; SIGXFSZ ignored, so that the write fails with EFBIG).
# Each rank's exit status is kept (mpirun does not end the others first).
# (ThreadSanitizer's runtime, with LLVM's libomp, faults under a file
# size limit before psim runs)
wrap='trap "" XFSZ; [[ $OMPI_COMM_WORLD_RANK == 1 ]] && ulimit -f 8
"$0" "$@"; echo $? >"$RCDIR/rc.$OMPI_COMM_WORLD_RANK"'
fsize_outs=(--final --trace --dump --restart -o)
if "$PSIM" --version | grep -q "sanitizers[^,]*thread"; then
    echo "mpi_write: a file size limit needs a build without ThreadSanitizer"
    fsize_outs=()
fi
for out in "${fsize_outs[@]}"; do
    for r in 2 3; do
        rm -rf "$tmp/rc" && mkdir "$tmp/rc"
        # (named temporary files with 3 ranks)
        PSIM_TMPFILE=$((r == 3 ? 0 : 1)) RCDIR=$tmp/rc mpirun -q --oversubscribe -x RCDIR \
            -x PSIM_TMPFILE --mca io ompio --mca fcoll individual \
            --mca orte_abort_on_non_zero_status 0 -np "$r" bash -c "$wrap" "$PSIM" \
            --model force "$tmp/s1000.in" --threads 1 -q "$out" "$tmp/full.txt" \
            2>"$tmp/full.err" || true
        grep -q "full.txt: write failed" "$tmp/full.err" ||
            fail "$out, $r ranks, a full disk on rank 1: $(cat "$tmp/full.err")"
        [[ ! -e $tmp/full.txt ]] || fail "$out, $r ranks: a failed write left its file"
        compgen -G "$tmp/.psim-*" >/dev/null && fail "$out, $r ranks: a temporary file was left"
        for ((q = 0; q < r; q++)); do
            [[ -s $tmp/rc/rc.$q ]] || fail "$out, $r ranks: rank $q did not end by itself"
            (($(cat "$tmp/rc/rc.$q") != 0)) || fail "$out, $r ranks: rank $q exited 0"
        done
    done
done
((${#fsize_outs[@]} == 0)) ||
    echo "ok: a write that fails on one rank fails every rank and leaves no file"

# Rank 0's own stream fails (a device: rank 0 writes it alone), and a
# folder that is a file: one line, exit 1.
for r in 2 3; do
    expect_fail --rc 1 "/dev/full: write failed: No space left on device" \
        mpi "$r" "${args[@]}" --final /dev/full
    touch "$tmp/afile"
    expect_fail --rc 1 "afile/x: cannot write" mpi "$r" "${args[@]}" --trace "$tmp/afile/x" \
        --final "$tmp/fin.txt"
    [[ ! -e $tmp/fin.txt ]] || fail "$r ranks: an output left after another could not be opened"
done
compgen -G "$tmp/.psim-*" >/dev/null && fail "a temporary file was left"
echo "ok: an output rank 0 cannot write fails every rank"
