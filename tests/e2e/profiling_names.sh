#!/usr/bin/env bash
# docs/profiling.md names, for each phase, the functions that hold its time
# in a profile.  Every function its tables name must be a symbol of the
# built psim, so that a renamed or removed function fails here, not in a
# reader's perf report.
#
# The tables are those between <!-- profile-names:begin --> and
# <!-- profile-names:end -->; in each, the column headed "function" holds
# the names, each in backticks (and nothing else in backticks).  A name matches a symbol of that name, or
# one GCC made from it by specialising it (NAME.constprop.0, NAME.isra.0,
# NAME.part.0, NAME.cold); an OpenMP outlined body is named in full
# (NAME._omp_fn.N).  Static functions are local symbols that nm lists as
# long as the binary is not stripped.
#
# The names are GCC's (the default build's compiler; clang names its
# outlined bodies otherwise and inlines other static functions).  So
# every name must be a function defined in src/, in any build, and a
# symbol of psim where psim --version says GCC built it.
set -euo pipefail
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/lib.sh" "$@"

doc="$(dirname "$0")/../../docs/profiling.md"
[[ -r $doc ]] || fail "cannot read $doc"
command -v nm >/dev/null || fail "nm (binutils) is not installed"

src="$(dirname "$0")/../../src"
[[ -d $src ]] || fail "cannot find the source folder $src"
compiler=$("$PSIM" --version | sed -n 's/^built: [^,]*, \([A-Za-z]*\) .*/\1/p')
[[ -n $compiler ]] || fail "psim --version names no compiler on its built: line"

nm "$PSIM" 2>"$tmp/nm.err" | awk 'NF >= 3 && $2 ~ /^[TtWw]$/ {print $3}' | sort -u >"$tmp/symbols" ||
    fail "nm failed on $PSIM: $(cat "$tmp/nm.err")"
[[ -s $tmp/symbols ]] || fail "nm lists no function symbols in $PSIM (a stripped binary?)"
# the test's own control: a function every build has
grep -qx 'main' "$tmp/symbols" || fail "nm's list of $PSIM lacks main: cannot check the names"

# The names: backticked words in the "function" column of the marked tables.
awk -v doc="$doc" '
    /<!-- profile-names:begin -->/ { inside = 1; begins++; next }
    /<!-- profile-names:end -->/   { inside = 0; ends++; next }
    !inside { next }
    !/^\|/ { col = 0; next }            # a line outside a table ends it
    {
        n = split($0, cell, "|")
        if (!col) {                     # the header row of a table
            for (k = 2; k < n; k++) {
                h = cell[k]; gsub(/^ +| +$/, "", h)
                if (h == "function") col = k
            }
            if (!col) { printf "BADTABLE %d\n", NR; exit }
            tables++; header = NR; next
        }
        if (NR == header + 1) next      # the |---| row
        c = cell[col]
        while (match(c, /`[^`]*`/)) {
            print substr(c, RSTART + 1, RLENGTH - 2)
            c = substr(c, RSTART + RLENGTH)
        }
    }
    END {
        if (begins != 1 || ends != 1) printf "BADMARKERS %d %d\n", begins, ends
        printf "TABLES %d\n", tables
    }' "$doc" >"$tmp/names"

grep -q '^BADMARKERS' "$tmp/names" &&
    fail "$doc must have one <!-- profile-names:begin --> and one <!-- profile-names:end --> marker"
grep -q '^BADTABLE' "$tmp/names" &&
    fail "$doc: the table at line $(awk '/^BADTABLE/ {print $2}' "$tmp/names") has no \"function\" column"
tables=$(awk '/^TABLES/ {print $2}' "$tmp/names")
((tables >= 4)) || fail "$doc: expected a table a model between the markers, found $tables"
sed -i '/^TABLES /d' "$tmp/names"
count=$(wc -l <"$tmp/names")
((count >= 20)) || fail "$doc: only $count function names found in its profile tables"

missing=0
while IFS= read -r name; do
    [[ $name =~ ^[A-Za-z_][A-Za-z0-9_]*(\._omp_fn\.[0-9]+)?$ ]] ||
        { echo "FAIL: $doc names \`$name\`, which is not a function name" >&2; missing=$((missing + 1)); continue; }
    base=${name%%._omp_fn.*}
    # defined at file scope in a .c file of src/ (a definition's line is
    # not indented, has the name before its parenthesis and no semicolon)
    if ! grep -rqE --include='*.c' "^([A-Za-z_].*[^A-Za-z0-9_])?${base}\\([^;]*$" "$src"; then
        echo "FAIL: $doc names \`$name\`, but no function ${base} is defined in src/" >&2
        missing=$((missing + 1))
        continue
    fi
    [[ $compiler == GNU ]] || continue   # the symbols are GCC's
    if grep -qxF -- "$name" "$tmp/symbols"; then
        continue
    fi
    # GCC's clones of NAME (not of NAME._omp_fn.N, which is named in full)
    if [[ $name != *._omp_fn.* ]] &&
        grep -qE "^${name}(\.(constprop|isra|part|cold|localalias)(\.[0-9]+)?)+$" "$tmp/symbols"; then
        continue
    fi
    echo "FAIL: $doc names \`$name\`, which is not a symbol of $PSIM" >&2
    missing=$((missing + 1))
done <"$tmp/names"
((missing == 0)) || fail "$missing function name(s) of docs/profiling.md's profile tables are not in the build"

echo "profiling_names: ok ($count names in $tables tables; symbols checked: $([[ $compiler == GNU ]] && echo yes || echo "no, built by $compiler"))"
