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
