# Shared helpers of the bench scripts (sourced: . "$(dirname "$0")/lib.sh").

# median [X ...]: the median of the numbers given, or else of those on
# standard input (one per line); of an even count, the mean of the two in
# the middle.  Printed with 6 decimals; nothing (status 1) for no numbers.
median() {
    if (($#)); then printf '%s\n' "$@"; else cat; fi | sort -g |
        awk '{v[NR] = $1}
             END {if (NR == 0) exit 1
                  printf "%.6f\n", (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'
}

# mpi_ready PSIM: PSIM built and mpirun at hand (else a line and exit 1),
# and Open MPI allowed to run as root (the CI machines' user).
mpi_ready() {
    [[ -x $1 ]] || { echo "$0: no $1 (build first)" >&2; exit 1; }
    command -v mpirun >/dev/null || { echo "$0: mpirun not found (openmpi-bin)" >&2; exit 1; }
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
}
