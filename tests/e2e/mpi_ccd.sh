#!/usr/bin/env bash
# The ccd model over MPI ranks (mpirun): every rank holds every disk and
# detects its share; the same bytes as one process for 1-4 ranks x 1-2
# threads on scenes shaped as the course's hand-made ones, on the
# course's generator's scenes, on rows of disks whose conflicts chain
# across the whole box (a Newton's cradle spanning it, a crowded row
# where many candidates share disks), on clustered scenes (big and small
# cells together); over TCP alone; across restarts on other rank counts;
# the summary's counters are one process's and each candidate is found
# on one rank; --check passes over ranks; a bad scene is said once.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

# mpirun -np R PSIM ARGS...
mpi() { local r=$1; shift; mpirun -q --oversubscribe --bind-to none -np "$r" "$PSIM" "$@"; }

if ! mpi_setup; then
    expect_fail --rc 2 "built without MPI" env OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 \
        "$PSIM" --model ccd "$tmp/none.in" -q
    echo "ok: a build without MPI refuses ranks"
    exit 0
fi

# scene NAME L r S MODE LINES...: a 2019 scene
scene()
{
    local name=$1 L=$2 r=$3 S=$4 mode=$5
    shift 5
    { echo "$#"; echo "$L"; echo "$r"; echo "$S"; echo "$mode"; printf '%s\n' "$@"; } >"$tmp/$name.in"
}

# awk_scene NAME N L r S AWK-BODY: a 2019 scene whose N particle lines
# the awk program prints (i from 0 to N - 1; rand() seeded)
awk_scene()
{
    local name=$1 n=$2 L=$3 r=$4 S=$5 body=$6
    { printf '%s\n%s\n%s\n%s\nprint\n' "$n" "$L" "$r" "$S"
      awk -v n="$n" -v L="$L" -v r="$r" "BEGIN { srand(7); for (i = 0; i < n; i++) { $body } }"
    } >"$tmp/$name.in"
}

# same NAME: the output of every rank count and thread count is that of
# one process (the initial state, every step, the final counts)
same()
{
    local r t
    run_ok "$PSIM" --model ccd --threads 1 -q --out "$tmp/$1.one" "$tmp/$1.in"
    [[ -s $tmp/$1.one ]] || fail "$1: no output"
    for r in 1 2 3 4; do
        for t in 1 2; do
            run_ok mpi "$r" --model ccd --threads "$t" -q --out "$tmp/$1.r" "$tmp/$1.in"
            same_file "$tmp/$1.one" "$tmp/$1.r" "$1: $r ranks x $t threads"
        done
    done
}

# The shapes of the course's hand-made scenes, in other sizes.
scene cradle 40 1 30 print "0 3 20 -1.5 0" "1 5.05 20 0 0" "2 7.1 20 0 0" "3 9.15 20 0 0" \
    "4 11.2 20 0 0" "5 30 20 -2 0" "6 36 20 0.5 0"
scene cross 30 1.5 30 print "0 2 2 1 1" "1 15 15 1 -1" "2 28 2 -1 1" "3 2 28 1.2 -1"
scene diagonal 30 1 30 print "0 2 2 -1 0" "1 9 9 -1 0" "2 16 16 -1 0" "3 23 23 -1 0" \
    "4 28 28 -1 -1"
scene square 40 1 30 print "0 21 1 0 2" "1 39 21 -2 0" "2 19 39 0 -2" "3 1 19 2 0"
scene triangle 6 0.5 30 print "0 3 4.5 0 -1" "1 2.5 3.63397459622 -0.5 0.866025403784" \
    "2 3.5 3.63397459622 0.5 0.866025403784"
for s in cradle cross diagonal square triangle; do
    same "$s"
done
echo "ok: the hand-made shapes, 1-4 ranks x 1-2 threads"

# The course's generator (a scene with no particle lines): every disk
# crosses 1/8..1/4 of the box a step, one big cell cut into bands.
printf '3000\n30000\n1\n15\nprint\n' >"$tmp/gen.in"
same gen
echo "ok: generated scenes"

# A Newton's cradle spanning the box: a row of disks 2.02r apart from
# wall to wall, both ends moving in; the momentum runs along the whole
# row across every rank's share.
awk_scene row 2000 4120 1 30 'v = (i == 0) ? 2 : (i == n - 1) ? -2 : 0;
    printf "%d %.6f 2000 %.6f 0\n", i, 40 + 2.02 * i, v'
same row
# A crowded row: disks 2.1r apart with random speeds along it, so that
# many disks have two candidates and acceptance chains along the row,
# through the shares of every rank (its detection is 8 tasks).
awk_scene crowd 2000 4300 1 20 'printf "%d %.6f %.6f %.6f %.6f\n", i, 30 + 2.1 * i,
    2000 + (rand() - 0.5) * 0.2, (rand() - 0.5) * 1.6, (rand() - 0.5) * 0.05'
same crowd
echo "ok: conflicts chained across the ranks' shares"

# Clustered: a dense slow crowd (big cells cut into bands, with
# neighbours) and a sparse one (small cells) in one box.
awk_scene cluster 2500 400 1 25 'if (i < 1500) { x = 20 + rand() * 120; y = 20 + rand() * 120 }
    else { x = 2 + rand() * 396; y = 2 + rand() * 396 }
    printf "%d %.6f %.6f %.6f %.6f\n", i, x, y, (rand() - 0.5) * 3, (rand() - 0.5) * 3'
same cluster
echo "ok: big and small cells together"

# Counters: the summary's are one process's (per-rank work summed, the
# rest counted once), and each candidate is found on one rank alone:
# every rank sends its own to each of the others, 24 bytes each.
run_ok "$PSIM" --model ccd --threads 2 -q --stats "$tmp/one.json" --out "$tmp/c.one" "$tmp/cluster.in"
run_ok mpi 3 --model ccd --threads 2 -q --stats "$tmp/three.json" --out "$tmp/c.r" "$tmp/cluster.in"
/usr/bin/python3 - "$tmp/one.json" "$tmp/three.json" <<'PY' || fail "counters over 3 ranks"
import json, sys
one, three = (json.load(open(p)) for p in sys.argv[1:])
keys = ["pair_tests", "pair_candidates", "wall_candidates", "pair_collisions",
        "wall_collisions", "accept_rounds", "tasks", "regrids"]
for k in keys:
    assert one[k] == three[k], (k, one[k], three[k])
assert one["pair_collisions"] > 100 and one["tasks"] > 0, one
assert three["ranks"] == 3 and len(three["per_rank"]) == 3, three
sent = sum(r["bytes_sent"] for r in three["per_rank"])
found = one["pair_candidates"] + one["wall_candidates"]
assert sent == 24 * 2 * found, (sent, found)
assert all(r["bytes_sent"] > 0 for r in three["per_rank"]), three["per_rank"]
PY
echo "ok: counters of one process, each candidate found once"

# The transport that crosses machines.
run_ok mpirun -q --oversubscribe --bind-to none --mca btl tcp,self -np 3 "$PSIM" --model ccd \
    --threads 2 -q --out "$tmp/tcp.out" "$tmp/gen.in"
same_file "$tmp/gen.one" "$tmp/tcp.out" "over TCP"
echo "ok: the same over TCP alone"

# --check over ranks.
for s in cluster crowd; do
    run_ok mpi 3 --model ccd --check --threads 2 -q --out "$tmp/chk.out" "$tmp/$s.in"
    same_file "$tmp/$s.one" "$tmp/chk.out" "$s under --check over 3 ranks"
done
echo "ok: --check over ranks"

# Restarts across rank counts: 2 ranks write one after 10 steps, 3 ranks
# and one process run the next 10 from it, as the unbroken run of 20 (the
# final state, the output's last step with its collision counts).
run_ok "$PSIM" --model ccd --threads 1 --steps 20 -q --final "$tmp/whole.fin" \
    --out "$tmp/whole.out" "$tmp/cluster.in"
run_ok mpi 2 --model ccd "$tmp/cluster.in" --steps 10 -q --restart "$tmp/half.rst" \
    --out /dev/null
for r in 3 1; do
    if ((r == 1)); then
        run_ok "$PSIM" --model ccd "$tmp/half.rst" -q --final "$tmp/r.fin" --out "$tmp/r.out"
    else
        run_ok mpi "$r" --model ccd "$tmp/half.rst" -q --final "$tmp/r.fin" --out "$tmp/r.out"
    fi
    same_file "$tmp/whole.fin" "$tmp/r.fin" "restart written by 2 ranks, run on $r"
    same_file <(tail -n 2500 "$tmp/whole.out") <(tail -n 2500 "$tmp/r.out") \
        "restart written by 2 ranks, run on $r: the last step"
done
echo "ok: restarts move across rank counts"

# Failures: one line from one rank, exit 1, no output.
mpi_fail() {   # RC SUBSTRING ARGS...: mpirun -np 2 fails with psim's one line
    local want=$1 what=$2 rc=0; shift 2
    mpi 2 "$@" 2>"$tmp/err" || rc=$?
    ((rc == want)) || fail "expected exit $want, got $rc from mpirun -np 2 psim $*"
    (($(wc -l <"$tmp/err") == 1)) || fail "not one line: $(cat "$tmp/err")"
    grep -q -- "$what" "$tmp/err" || fail "stderr lacks '$what': $(cat "$tmp/err")"
}
scene bad 10 1 5 print "0 2 2 1 1" "1 5 zz 1 1"
mpi_fail 1 "bad.in:7" --model ccd "$tmp/bad.in" -q --out "$tmp/out.txt"
[[ ! -e $tmp/out.txt ]] || fail "a bad scene left an output"
scene wall 10 1 5 print "0 2 2 1 1" "1 0.5 5 1 1"
mpi_fail 1 "overlaps a wall" --model ccd "$tmp/wall.in" -q --out "$tmp/out.txt"
[[ ! -e $tmp/out.txt ]] || fail "a refused scene left an output"
echo "ok: failures over ranks"
