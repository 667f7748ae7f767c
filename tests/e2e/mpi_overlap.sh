#!/usr/bin/env bash
# The force model over MPI ranks with small tiles (--tile), so that each
# rank has tiles that read no ghost and run while the ghosts' positions
# travel: the same bytes as one process for 2-4 ranks x 1-2 threads and
# every way of running a step's rounds on threads.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

mpi() { local r=$1; shift; mpirun -q --oversubscribe -np "$r" "$PSIM" "$@"; }

if ! mpi_setup; then
    echo "ok: built without MPI (nothing runs over ranks)"
    exit 0
fi

args=(--model force -n 12000 -s 4 --steps 120)
run_ok "$PSIM" "${args[@]}" --threads 1 -q -o "$tmp/one.txt" --final "$tmp/one.fin"
for tile in 4 8; do
    for r in 2 3 4; do
        for t in 1 2; do
            for rounds in 0 1 2; do
                ((t > 1 || rounds == 0)) || continue
                what="--tile $tile, $r ranks x $t threads, rounds=$rounds"
                run_ok mpi "$r" "${args[@]}" --tile "$tile" --threads "$t" \
                    --option rounds="$rounds" -q -o "$tmp/r.txt" --final "$tmp/r.fin"
                same_file "$tmp/one.txt" "$tmp/r.txt" "$what, -o"
                same_file "$tmp/one.fin" "$tmp/r.fin" "$what, --final"
            done
        done
    done
done
echo "ok: ranks whose tiles run while the ghosts travel write the bytes of one process"
