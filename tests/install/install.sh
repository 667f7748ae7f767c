#!/usr/bin/env bash
# The installed package (docs/install.md, docs/api.md), run by ctest as
# install.WHAT:
#   tree                cmake --install the build tree into a staging prefix;
#                       every file is there, none of the text files names the
#                       staging prefix or the build or source tree; then the
#                       prefix is moved to PSIM_INSTALL_PREFIX (the fixture of
#                       the others: the package must work where it was moved)
#   version             the installed psim runs: --version, gen, a short run;
#                       psim-plot and psim-animate answer under those names
#   library             libpsim.so: its SONAME and links; it needs no
#                       jemalloc; it exports exactly the functions the
#                       installed headers declare (PSIM_API), all psim_*
#   cmake_consumer      tests/install/consumer built with find_package(psim)
#                       and psim::psim, then with the other of
#                       psim::psim_shared and psim::psim_static, and with
#                       pkg_check_modules(IMPORTED_TARGET psim); each run:
#                       its final state is the installed psim's; a version
#                       the package does not satisfy fails
#   pkgconfig_consumer  the same program built with pkg-config psim (the
#                       shared library), with --static and libpsim.a, and
#                       linked with jemalloc too, whose malloc the library
#                       then uses
#   example_cmake       examples/c built with CMake (psim::psim_shared) and
#   example_pkgconfig   with cc $(pkg-config --cflags --libs psim): run on a
#                       scene, its output is psim --final's, byte for byte
#   python              examples/python/run_scene.py loads the installed
#                       libpsim.so.0 with ctypes: its states (read from a
#                       file, made from numpy arrays) are psim --final's, and
#                       Python's process keeps its own malloc; a wrong
#                       reference makes it fail
#   man                 share/man/man1/psim.1 names every long option of
#                       every --help, every subcommand and model, every
#                       variable psim reads from the environment, and the
#                       documents' folder; it and the completion are what
#                       cmake/psim_docs.py makes from the installed psim's
#                       help, byte for byte
#   completion          the bash completion, sourced, offers the subcommands,
#                       each command's options (exactly its --help's), the
#                       models, the model options (after --model, exactly
#                       that model's), the values of --pin,
#                       --mem and --place, and file names
# ctest gives the build's settings in PSIM_INSTALL_* (tests/CMakeLists.txt).
# usage: install.sh WHAT
set -euo pipefail
what=${1:?usage: install.sh tree|version|library|cmake_consumer|pkgconfig_consumer|example_cmake|example_pkgconfig|python|man|completion}
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

for v in BUILD SOURCE PREFIX VERSION SOVERSION SHARED DESCRIPTION CC CMAKE GENERATOR MAKE \
         PKG_CONFIG PYTHON NM READELF ALLOCATOR BINDIR LIBDIR INCLUDEDIR MANDIR DATADIR DOCDIR; do
    var=PSIM_INSTALL_$v
    [[ -n ${!var:-} ]] || { echo "FAIL: $var is not set (ctest sets it: tests/CMakeLists.txt)" >&2; exit 1; }
done
prefix=$PSIM_INSTALL_PREFIX
man=$prefix/$PSIM_INSTALL_MANDIR/man1/psim.1
completion=$prefix/$PSIM_INSTALL_DATADIR/bash-completion/completions/psim
libdir=$prefix/$PSIM_INSTALL_LIBDIR
soname=libpsim.so.$PSIM_INSTALL_SOVERSION

if [[ $what == tree ]]; then
    stage=$prefix.stage
    rm -rf "$stage" "$prefix"
    if ! "$PSIM_INSTALL_CMAKE" --install "$PSIM_INSTALL_BUILD" --prefix "$stage" >"$tmp/install.log" 2>&1; then
        sed 's/^/  | /' "$tmp/install.log" >&2
        echo "FAIL: cmake --install $PSIM_INSTALL_BUILD --prefix $stage failed" >&2
        exit 1
    fi
    missing=()
    for f in "$PSIM_INSTALL_BINDIR/psim" "$PSIM_INSTALL_LIBDIR/libpsim.a" \
             "$PSIM_INSTALL_LIBDIR/libpsim.so.$PSIM_INSTALL_VERSION" \
             "$PSIM_INSTALL_LIBDIR/cmake/psim/psimConfig.cmake" \
             "$PSIM_INSTALL_LIBDIR/cmake/psim/psimConfigVersion.cmake" \
             "$PSIM_INSTALL_LIBDIR/cmake/psim/psimTargets.cmake" \
             "$PSIM_INSTALL_LIBDIR/pkgconfig/psim.pc" \
             "$PSIM_INSTALL_MANDIR/man1/psim.1" \
             "$PSIM_INSTALL_DATADIR/bash-completion/completions/psim"; do
        [[ -s $stage/$f ]] || missing+=("$f")
    done
    # every public header, and only those
    for h in "$PSIM_INSTALL_SOURCE"/include/psim/*.h; do
        cmp -s "$h" "$stage/$PSIM_INSTALL_INCLUDEDIR/psim/${h##*/}" ||
            missing+=("$PSIM_INSTALL_INCLUDEDIR/psim/${h##*/} (as include/psim/${h##*/})")
    done
    # the scripts, and the documents: every page of docs/ and README.md (its
    # links made local)
    for b in psim-plot psim-animate; do
        [[ -x $stage/$PSIM_INSTALL_BINDIR/$b ]] || missing+=("$PSIM_INSTALL_BINDIR/$b (executable)")
    done
    for d in "$PSIM_INSTALL_SOURCE"/docs/*.md; do
        cmp -s "$d" "$stage/$PSIM_INSTALL_DOCDIR/${d##*/}" ||
            missing+=("$PSIM_INSTALL_DOCDIR/${d##*/} (as docs/${d##*/})")
    done
    [[ -s $stage/$PSIM_INSTALL_DOCDIR/README.md ]] || missing+=("$PSIM_INSTALL_DOCDIR/README.md")
    if grep -q '](docs/' "$stage/$PSIM_INSTALL_DOCDIR/README.md" 2>/dev/null; then
        missing+=("$PSIM_INSTALL_DOCDIR/README.md with links to its own folder (it links to docs/)")
    fi
    if ((${#missing[@]})); then
        echo "FAIL: cmake --install did not install:" >&2
        printf '  %s\n' "${missing[@]}" >&2
        exit 1
    fi
    [[ -x $stage/$PSIM_INSTALL_BINDIR/psim ]] || { echo "FAIL: the installed psim is not executable" >&2; exit 1; }
    # the shared library's links: SONAME -> the file, libpsim.so -> SONAME
    for link in "libpsim.so.$PSIM_INSTALL_SOVERSION:libpsim.so.$PSIM_INSTALL_VERSION" \
                "libpsim.so:libpsim.so.$PSIM_INSTALL_SOVERSION"; do
        f=$stage/$PSIM_INSTALL_LIBDIR/${link%%:*}
        [[ -L $f && $(readlink "$f") == "${link#*:}" ]] ||
            { echo "FAIL: $PSIM_INSTALL_LIBDIR/${link%%:*} is not a link to ${link#*:}" >&2; exit 1; }
    done
    extra=$(cd "$stage/$PSIM_INSTALL_INCLUDEDIR" && find . -type f ! -name '*.h' | head -5)
    [[ -z $extra ]] || { echo "FAIL: installed under include/ besides headers: $extra" >&2; exit 1; }
    # The text files hold no absolute path of the build: the package can move.
    texts=("$stage/$PSIM_INSTALL_LIBDIR/cmake/psim"/*.cmake "$stage/$PSIM_INSTALL_LIBDIR/pkgconfig/psim.pc"
           "$stage/$PSIM_INSTALL_MANDIR/man1/psim.1"
           "$stage/$PSIM_INSTALL_DATADIR/bash-completion/completions/psim")
    for p in "$stage" "$PSIM_INSTALL_BUILD" "$PSIM_INSTALL_SOURCE"; do
        if hits=$(grep -lF -- "$p" "${texts[@]}"); then
            echo "FAIL: installed files name $p (they must not, to be relocatable):" >&2
            printf '  %s\n' "$hits" >&2
            exit 1
        fi
    done
    mv "$stage" "$prefix"
    echo "install: $(find "$prefix" -type f | wc -l) files installed, moved to $prefix"
    exit 0
fi

[[ -d $prefix ]] || { echo "FAIL: no installed tree at $prefix (the fixture install.tree makes it)" >&2; exit 1; }
# the e2e helpers (fail, run_ok, same_file, gen) with the installed psim
# shellcheck source-path=SCRIPTDIR source=../e2e/lib.sh
source "$here/../e2e/lib.sh" "$prefix/$PSIM_INSTALL_BINDIR/psim"
version=$PSIM_INSTALL_VERSION
help_texts=("--help" "gen --help" "plan --help" "topo --help" "models --help")

# A scene and the installed psim's final state of it, for the consumers.
scene_and_reference()
{
    gen "$tmp/scene.in" -n 600 --density 0.4 --steps 5 --seed 11
    run_ok "$PSIM" -q --threads 2 --final "$tmp/ref.txt" "$tmp/scene.in"
    [[ -s $tmp/ref.txt ]] || fail "the installed psim wrote no --final file"
}

# run_consumer BIN HOW [ALLOCATOR]: the consumer's final state must be the
# installed psim's, and the library's allocator ALLOCATOR (default libc:
# a program that does not link jemalloc keeps the C library's malloc).
run_consumer()
{
    local bin=$1 how=$2 allocator=${3:-libc}
    [[ -x $bin ]] || fail "$how: no consumer program was built"
    run_ok "$bin" "$tmp/scene.in" "$tmp/$how.txt" "$version" "$allocator"
    same_file "$tmp/$how.txt" "$tmp/ref.txt" "$how: the consumer's final state and psim --final's"
}

# needs BIN yes|no HOW: whether the program BIN loads libpsim.so (its
# DT_NEEDED names the SONAME) is as HOW says it was linked.
needs()
{
    local dyn
    dyn=$("$PSIM_INSTALL_READELF" -d "$1") || fail "readelf -d $1 failed"
    if [[ $2 == yes ]]; then
        grep -qF "[$soname]" <<<"$dyn" || fail "$3: the program does not load $soname"
    else
        ! grep -qF "[libpsim.so" <<<"$dyn" || fail "$3: the program loads libpsim.so, not libpsim.a"
    fi
}

# A python3 with numpy (Debian's, where the one on PATH lacks it).
numpy_python()
{
    local py
    for py in python3 /usr/bin/python3; do
        if "$py" -c 'import numpy' 2>/dev/null; then
            echo "$py"
            return 0
        fi
    done
    fail "no python3 with numpy (run scripts/install-test-deps.sh)"
}

# The long options a help text lists: "  -m, --model NAME", "      --steps S",
# and those its first usage line names ("[--pin POLICY]").
help_options()
{
    local text
    # shellcheck disable=SC2086 # "gen --help": two words
    text=$("$PSIM" $1) || fail "psim $1 failed"
    {
        grep -oE '^ {1,7}(-[A-Za-z0-9], )?--[A-Za-z0-9][A-Za-z0-9-]*' <<<"$text" |
            grep -oE -- '--[A-Za-z0-9][A-Za-z0-9-]*$' || true
        head -1 <<<"$text" | grep -oE '\[--[A-Za-z0-9][A-Za-z0-9-]*' | tr -d '[' || true
    } | sort -u
}

# The subcommands psim --help names in its usage lines ("psim gen [OPTIONS]").
subcommands()
{
    "$PSIM" --help | sed -n '1,/^$/p' | sed -nE 's/^(usage:)? *psim ([a-z]+)( .*)?$/\2/p'
}

models()
{
    "$PSIM" models | sed -nE 's/^([a-z0-9_-]+) .*/\1/p'
}

case $what in
version)
    out=$("$PSIM" --version) || fail "psim --version failed"
    [[ $(head -1 <<<"$out") == "psim $version "* ]] ||
        fail "psim --version does not start with 'psim $version': $(head -1 <<<"$out")"
    grep -q "allocator $PSIM_INSTALL_ALLOCATOR" <<<"$out" ||
        fail "psim --version does not name the allocator $PSIM_INSTALL_ALLOCATOR: $out"
    gen "$tmp/s.in" -n 300 --density 0.3 --steps 3
    run_ok "$PSIM" -q --threads 2 --out "$tmp/out.txt" "$tmp/s.in"
    (($(wc -l <"$tmp/out.txt") == 300)) || fail "the installed psim's --out has not 300 lines"
    # the scripts run where installed, under their installed names
    for b in psim-plot psim-animate; do
        run_ok "$prefix/$PSIM_INSTALL_BINDIR/$b" --help
        expect_fail --rc 2 "$b: " "$prefix/$PSIM_INSTALL_BINDIR/$b" --no-such-option
    done
    echo "install: $(head -1 <<<"$out") runs"
    ;;

library)
    so=$libdir/libpsim.so.$version
    dyn=$("$PSIM_INSTALL_READELF" -d "$so") || fail "readelf -d $so failed"
    got=$(sed -n 's/.*(SONAME).*\[\(.*\)\]$/\1/p' <<<"$dyn")
    [[ $got == "$soname" ]] || fail "$so's SONAME is '$got', not $soname"
    # the allocator is the program's: the library links none
    if grep -i 'NEEDED.*jemalloc' <<<"$dyn"; then
        fail "$so needs jemalloc: a program loading it would get jemalloc's malloc"
    fi
    # its exported symbols: exactly the functions the installed headers
    # declare with PSIM_API, each named psim_*
    "$PSIM_INSTALL_NM" -D --defined-only "$so" >"$tmp/nm.txt" || fail "nm -D $so failed"
    awk '{print $NF}' "$tmp/nm.txt" | sort -u >"$tmp/exported.txt"
    # (the declarations without comments and preprocessor lines: the name
    # before the first parenthesis of each PSIM_API ...;)
    "$PSIM_INSTALL_PYTHON" - "$prefix/$PSIM_INSTALL_INCLUDEDIR"/psim/*.h >"$tmp/names.txt" <<'PY' ||
import re, sys
names = set()
for path in sys.argv[1:]:
    text = re.sub(r"/\*.*?\*/", " ", open(path).read(), flags=re.S)
    text = "\n".join(l for l in text.split("\n") if not l.lstrip().startswith("#"))
    names.update(re.findall(r"\bPSIM_API\b[^;(]*?\b([A-Za-z_]\w*)\s*\(", text))
print("\n".join(sorted(names)))
PY
        fail "cannot list the functions of the installed headers"
    sort -u "$tmp/names.txt" >"$tmp/declared.txt"
    (($(wc -l <"$tmp/declared.txt") > 50)) ||
        fail "the headers declare only $(wc -l <"$tmp/declared.txt") functions with PSIM_API"
    others=$(grep -v '^psim_' "$tmp/exported.txt" || true)
    [[ -z $others ]] || fail "$so exports symbols outside the API: $(paste -sd' ' <<<"$others")"
    extra=$(comm -23 "$tmp/exported.txt" "$tmp/declared.txt")
    [[ -z $extra ]] || fail "$so exports functions no installed header declares: $(paste -sd' ' <<<"$extra")"
    absent=$(comm -13 "$tmp/exported.txt" "$tmp/declared.txt")
    [[ -z $absent ]] || fail "$so does not export functions the headers declare: $(paste -sd' ' <<<"$absent")"
    echo "install: $soname exports the $(wc -l <"$tmp/exported.txt") functions psim/*.h declares, nothing else; needs $(grep -c NEEDED <<<"$dyn") libraries, no jemalloc"
    ;;

cmake_consumer)
    scene_and_reference
    args=(-G "$PSIM_INSTALL_GENERATOR" -DCMAKE_MAKE_PROGRAM="$PSIM_INSTALL_MAKE"
          -DCMAKE_C_COMPILER="$PSIM_INSTALL_CC" -DCMAKE_PREFIX_PATH="$prefix"
          -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON)
    # consumer_build DIR WHAT ARGS...: configure and build the consumer
    consumer_build()
    {
        local dir=$1 what=$2
        shift 2
        if ! "$PSIM_INSTALL_CMAKE" -S "$here/consumer" -B "$dir" "${args[@]}" "$@" \
                >"$tmp/configure.log" 2>&1; then
            sed 's/^/  | /' "$tmp/configure.log" >&2
            fail "the consumer's configure with $what failed"
        fi
        if ! "$PSIM_INSTALL_CMAKE" --build "$dir" >"$tmp/build.log" 2>&1; then
            sed 's/^/  | /' "$tmp/build.log" >&2
            fail "the consumer linking $what did not build"
        fi
    }
    consumer_build "$tmp/b" "find_package(psim $version) and psim::psim" -DPSIM_WANT_VERSION="$version"
    want=$prefix/$PSIM_INSTALL_LIBDIR/cmake/psim
    [[ $(cat "$tmp/b/psim_dir.txt") -ef $want ]] ||
        fail "find_package(psim) found $(cat "$tmp/b/psim_dir.txt"), not $want"
    # psim::psim is the library BUILD_SHARED_LIBS chose; then the other one
    if [[ $PSIM_INSTALL_SHARED == ON ]]; then default=yes other=psim::psim_static; else default=no other=psim::psim_shared; fi
    needs "$tmp/b/consumer" "$default" "psim::psim"
    run_consumer "$tmp/b/consumer" cmake
    consumer_build "$tmp/b_other" "$other" -DPSIM_LINK="$other"
    needs "$tmp/b_other/consumer" "$([[ $other == psim::psim_shared ]] && echo yes || echo no)" "$other"
    run_consumer "$tmp/b_other/consumer" cmake_other
    # pkg-config's psim.pc from CMake: libpsim.so, its path found by CMake
    consumer_build "$tmp/b_pc" "pkg_check_modules(IMPORTED_TARGET psim)" -DPSIM_FIND=pkgconfig \
        -DCMAKE_PREFIX_PATH="$prefix"
    needs "$tmp/b_pc/consumer" yes "pkg_check_modules(IMPORTED_TARGET psim)"
    run_consumer "$tmp/b_pc/consumer" cmake_pkgconfig
    # a version this one does not satisfy: 0.x, a later minor version
    IFS=. read -r major minor _ <<<"$version"
    newer=$major.$((minor + 1))
    if "$PSIM_INSTALL_CMAKE" -S "$here/consumer" -B "$tmp/b2" "${args[@]}" \
            -DPSIM_WANT_VERSION="$newer" >"$tmp/configure2.log" 2>&1; then
        fail "find_package(psim $newer) accepted psim $version"
    fi
    grep -q "psimConfigVersion.cmake\|version: $version" "$tmp/configure2.log" ||
        fail "find_package(psim $newer) failed, but not for the version: $(cat "$tmp/configure2.log")"
    echo "install: find_package(psim $version) with psim::psim and $other, and pkg_check_modules(psim): each consumer's final state is psim's"
    ;;

pkgconfig_consumer)
    scene_and_reference
    export PKG_CONFIG_PATH=$libdir/pkgconfig
    pc=$PSIM_INSTALL_PKG_CONFIG
    command -v "$pc" >/dev/null || fail "no pkg-config ($pc; a build dependency, scripts/install-deps.sh)"
    run_ok "$pc" --exists psim
    got=$("$pc" --modversion psim)
    [[ $got == "$version" ]] || fail "pkg-config --modversion psim is '$got', not $version"
    got=$("$pc" --variable=prefix psim)
    [[ $got -ef $prefix ]] || fail "psim.pc's prefix is $got, not $prefix"
    # cc_consumer OUT HOW FLAGS...: build the consumer, strict C11
    cc_consumer()
    {
        local out=$1 how=$2
        shift 2
        if ! "$PSIM_INSTALL_CC" -std=c11 -Wall -Wextra -Wpedantic -Werror "$here/consumer/consumer.c" \
                "$@" -o "$out" >"$tmp/cc.log" 2>&1; then
            sed 's/^/  | /' "$tmp/cc.log" >&2
            fail "cc consumer.c $how failed; flags: $*"
        fi
    }
    # as a user types it: the shared library, found at run time through
    # LD_LIBRARY_PATH (the prefix is not the system's)
    flags=$("$pc" --cflags --libs psim) || fail "pkg-config --cflags --libs psim failed"
    [[ " $flags " == *" -lpsim "* ]] || fail "pkg-config --libs psim lacks -lpsim: $flags"
    # shellcheck disable=SC2086 # the flags are words
    cc_consumer "$tmp/consumer" "\$(pkg-config --cflags --libs psim)" $flags
    needs "$tmp/consumer" yes "pkg-config --libs psim"
    LD_LIBRARY_PATH=$libdir run_consumer "$tmp/consumer" pkgconfig
    # the static library: its own dependencies come from --static
    sflags=$("$pc" --cflags --libs --static psim) || fail "pkg-config --cflags --libs --static psim failed"
    [[ " $sflags " == *" -lm "* ]] || fail "pkg-config --libs --static psim lacks -lm: $sflags"
    sflags=" $sflags "
    [[ $sflags == *" -lpsim "* ]] || fail "pkg-config --libs --static psim lacks -lpsim: $sflags"
    # shellcheck disable=SC2086
    cc_consumer "$tmp/consumer_static" "with libpsim.a" ${sflags/ -lpsim / -l:libpsim.a }
    needs "$tmp/consumer_static" no "pkg-config --static, -l:libpsim.a"
    run_consumer "$tmp/consumer_static" pkgconfig_static
    # a program whose malloc is jemalloc: the library allocates through it
    if [[ $PSIM_INSTALL_ALLOCATOR == jemalloc ]]; then
        # shellcheck disable=SC2086
        cc_consumer "$tmp/consumer_jemalloc" "with jemalloc" $flags -Wl,--no-as-needed -ljemalloc
        LD_LIBRARY_PATH=$libdir run_consumer "$tmp/consumer_jemalloc" pkgconfig_jemalloc jemalloc
    fi
    echo "install: cc consumer.c $flags (and --static with libpsim.a): the consumer's final state is psim's"
    ;;

example_cmake)
    scene_and_reference
    if ! "$PSIM_INSTALL_CMAKE" -S "$PSIM_INSTALL_SOURCE/examples/c" -B "$tmp/b" \
            -G "$PSIM_INSTALL_GENERATOR" -DCMAKE_MAKE_PROGRAM="$PSIM_INSTALL_MAKE" \
            -DCMAKE_C_COMPILER="$PSIM_INSTALL_CC" -DCMAKE_PREFIX_PATH="$prefix" \
            -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON >"$tmp/configure.log" 2>&1 ||
        ! "$PSIM_INSTALL_CMAKE" --build "$tmp/b" >"$tmp/build.log" 2>&1; then
        sed 's/^/  | /' "$tmp/configure.log" "$tmp/build.log" 2>/dev/null >&2
        fail "examples/c did not build with CMake against $prefix"
    fi
    needs "$tmp/b/run_scene" yes "examples/c (psim::psim_shared)"
    run_ok "$tmp/b/run_scene" "$tmp/scene.in" 2 >"$tmp/out.txt"
    same_file "$tmp/out.txt" "$tmp/ref.txt" "examples/c's run_scene (CMake) and psim --final"
    grep -q "run_scene: psim $version, discrete model, 600 disks, 5 steps on 2 threads" "$tmp/.run_ok.err" ||
        fail "run_scene's summary is not the run's: $(head -1 "$tmp/.run_ok.err")"
    echo "install: examples/c built with CMake: run_scene's state is psim --final's"
    ;;

example_pkgconfig)
    scene_and_reference
    export PKG_CONFIG_PATH=$libdir/pkgconfig
    # as docs/api.md gives it
    # shellcheck disable=SC2046 # the flags are words
    if ! (cd "$tmp" && "$PSIM_INSTALL_CC" "$PSIM_INSTALL_SOURCE/examples/c/run_scene.c" \
            $("$PSIM_INSTALL_PKG_CONFIG" --cflags --libs psim) -o run_scene) >"$tmp/cc.log" 2>&1; then
        sed 's/^/  | /' "$tmp/cc.log" >&2
        fail "cc run_scene.c \$(pkg-config --cflags --libs psim) failed"
    fi
    needs "$tmp/run_scene" yes "examples/c (pkg-config)"
    LD_LIBRARY_PATH=$libdir run_ok "$tmp/run_scene" "$tmp/scene.in" >"$tmp/out.txt"
    same_file "$tmp/out.txt" "$tmp/ref.txt" "examples/c's run_scene (pkg-config) and psim --final"
    # a scene it cannot read: one line naming the file, exit 1
    printf '3\n10\n1\n2\n0 1 1 0 0\n' >"$tmp/short.in"
    LD_LIBRARY_PATH=$libdir expect_fail --rc 1 "short.in:6: unexpected end of file" \
        "$tmp/run_scene" "$tmp/short.in"
    # the program docs/api.md shows is this one
    awk '/^## A complete program/ { f = 1 } f && /^```c$/ { p = 1; next } p && /^```$/ { exit } p' \
        "$PSIM_INSTALL_SOURCE/docs/api.md" >"$tmp/doc.c"
    same_file "$tmp/doc.c" "$PSIM_INSTALL_SOURCE/examples/c/run_scene.c" \
        "the program in docs/api.md and examples/c/run_scene.c"
    echo "install: examples/c built with pkg-config: run_scene's state is psim --final's"
    ;;

python)
    scene_and_reference
    py=$(numpy_python)
    lib=$libdir/$soname
    example=$PSIM_INSTALL_SOURCE/examples/python/run_scene.py
    run_ok "$py" "$example" --lib "$lib" --threads 2 --final "$tmp/ref.txt" "$tmp/scene.in" >"$tmp/out.txt"
    grep -q "discrete model, 600 disks, 5 steps, allocator libc;.* the state is psim's" "$tmp/out.txt" ||
        fail "run_scene.py did not say what it ran: $(cat "$tmp/out.txt")"
    # Python keeps its own malloc: loading the library brings no jemalloc
    maps=$("$py" -c 'import ctypes, sys; ctypes.CDLL(sys.argv[1]); print(open("/proc/self/maps").read())' "$lib") ||
        fail "python3 could not load $lib"
    grep -qF "$(basename "$(readlink -f "$lib")")" <<<"$maps" || fail "python3's maps do not show $lib loaded"
    ! grep -q jemalloc <<<"$maps" || fail "loading $lib brought jemalloc into python3"
    # a reference one disk off: the check must see it
    awk 'NR == 7 { $3 = sprintf("%.17g", $3 + 1) } { print }' "$tmp/ref.txt" >"$tmp/wrong.txt"
    rc=0
    "$py" "$example" --lib "$lib" --final "$tmp/wrong.txt" "$tmp/scene.in" >/dev/null 2>"$tmp/err.txt" || rc=$?
    if ((rc != 1)) || ! grep -q "disk 6: x is" "$tmp/err.txt"; then
        fail "run_scene.py against a wrong reference: exit $rc, $(cat "$tmp/err.txt")"
    fi
    echo "install: ctypes and numpy ($py): $(cat "$tmp/out.txt")"
    ;;

man)
    [[ -s $man ]] || fail "no man page at $man"
    grep -m1 '^\.TH' "$man" | grep -q "^\.TH PSIM 1 .*\"psim $version\"" ||
        fail "the man page's .TH line does not name psim $version: $(grep -m1 '^\.TH' "$man")"
    # the page as text: roff's \- \fB \fI \fR \& \e undone
    sed -e 's/\\-/-/g' -e 's/\\f[BIRP]//g' -e 's/\\&//g' -e 's/\\e/\\/g' "$man" >"$tmp/man.txt"
    missing=()
    for h in "${help_texts[@]}"; do
        # shellcheck disable=SC2086
        for o in $("$PSIM" $h | grep -oE -- '--[A-Za-z0-9][A-Za-z0-9-]*' | sort -u); do
            grep -qE -- "(^|[^A-Za-z0-9-])$o([^A-Za-z0-9-]|$)" "$tmp/man.txt" ||
                missing+=("$o (psim $h)")
        done
    done
    for c in $(subcommands); do
        grep -q "^\.SS \"psim $c" "$tmp/man.txt" || missing+=("a section for psim $c")
    done
    for m in $(models); do
        grep -qx "$m" "$tmp/man.txt" || missing+=("the model $m")
    done
    # every variable psim reads from the environment, in ENVIRONMENT; the
    # installed documents in SEE ALSO
    sed -n '/^\.SH ENVIRONMENT/,/^\.SH /p' "$tmp/man.txt" >"$tmp/env.txt"
    for v in $(grep -rhoE '(getenv\(|env_value\([a-z]+, )"[A-Z_]+"' "$PSIM_INSTALL_SOURCE/src" | grep -oE '"[A-Z_]{2,}"' | tr -d '"' | sort -u); do
        grep -qE "^(.*, )?$v(,.*)?$" "$tmp/env.txt" || missing+=("$v in ENVIRONMENT")
    done
    for s in "EXIT STATUS" EXAMPLES "SEE ALSO"; do
        grep -q "^\.SH $s" "$tmp/man.txt" || missing+=("a section $s")
    done
    grep -qF "$PSIM_INSTALL_DOCDIR" <(sed -n '/^\.SH SEE ALSO/,$p' "$tmp/man.txt") ||
        missing+=("$PSIM_INSTALL_DOCDIR in SEE ALSO")
    if ((${#missing[@]})); then
        fail "the man page $man lacks: ${missing[*]}"
    fi
    # the page the installed program's help makes, byte for byte
    run_ok "$PSIM_INSTALL_PYTHON" "$PSIM_INSTALL_SOURCE/cmake/psim_docs.py" --psim "$PSIM" \
        --version "$version" --description "$PSIM_INSTALL_DESCRIPTION" --man "$tmp/psim.1" \
        --man-template "$PSIM_INSTALL_SOURCE/cmake/psim-man.in" --docdir "$PSIM_INSTALL_DOCDIR" \
        --completion-template "$PSIM_INSTALL_SOURCE/cmake/psim-completion.bash.in" \
        --completion "$tmp/psim.bash"
    same_file "$tmp/psim.1" "$man" "the installed man page and the one the installed psim's help makes"
    same_file "$tmp/psim.bash" "$completion" "the installed completion and the one the installed psim's help makes"
    echo "install: the man page names every option of ${#help_texts[@]} help texts, $(subcommands | wc -l) subcommands, $(models | wc -l) models"
    ;;

completion)
    [[ -s $completion ]] || fail "no bash completion at $completion"
    # shellcheck disable=SC1090
    source "$completion"
    complete -p psim | grep -q -- "-F _psim" || fail "sourcing $completion does not register _psim for psim"
    mkdir "$tmp/cwd" "$tmp/cwd/subdir"
    : >"$tmp/cwd/scene.in"
    cd "$tmp/cwd"
    # offers WORD...: what _psim offers for the command line WORD... (the
    # last word is the one completed), sorted, one a line
    offers()
    {
        offers_at $(($# - 1)) "$@"
    }
    # offers_at K WORD...: the same, completing the word K (0 is psim)
    offers_at()
    {
        local at=$1
        shift
        COMP_WORDS=("$@")
        COMP_CWORD=$at
        COMP_LINE="$*"
        COMP_POINT=${#COMP_LINE}
        COMPREPLY=()
        _psim psim "${COMP_WORDS[COMP_CWORD]}" "${COMP_WORDS[COMP_CWORD - 1]}"
        ((${#COMPREPLY[@]} == 0)) || printf '%s\n' "${COMPREPLY[@]}" | sort -u
    }
    # same WHAT EXPECTED GOT: two sorted lists are equal
    same()
    {
        [[ $2 == "$3" ]] || fail "completion of $1: expected
$(diff <(echo "$2") <(echo "$3") | sed -n 's/^[<>]/  &/p')
  (< expected, > offered)"
    }
    # has WHAT GOT WORD...: each WORD is in the list
    has()
    {
        local what=$1 got=$2 w
        shift 2
        for w in "$@"; do
            grep -qxF -- "$w" <<<"$got" || fail "completion of $what does not offer '$w': $(tr '\n' ' ' <<<"$got")"
        done
    }
    subs=$(subcommands | sort -u)
    [[ -n $subs ]] || fail "psim --help names no subcommands"
    # shellcheck disable=SC2086
    has "'psim '" "$(offers psim '')" $subs scene.in subdir
    got=$(offers psim g)
    has "'psim g'" "$got" gen
    ! grep -qx plan <<<"$got" || fail "completion of 'psim g' offers plan"
    has "'psim sc' (the scene)" "$(offers psim sc)" scene.in
    has "'psim -q sc' (the scene)" "$(offers psim -q sc)" scene.in
    # each command's long options: exactly its help's
    same "'psim --'" "$(help_options --help)" "$(offers psim --)"
    same "'psim run --'" "$(help_options --help)" "$(offers psim run --)"
    for c in $subs; do
        same "'psim $c --'" "$(help_options "$c --help")" "$(offers psim "$c" --)"
    done
    # values
    same "'psim --model '" "$(models | sort -u)" "$(offers psim --model '')"
    same "'psim --model='" "$(models | sort -u)" "$(offers psim --model =)"
    same "'psim -m c'" "$(models | grep '^c' | sort -u)" "$(offers psim -m c)"
    same "'psim --option '" "$("$PSIM" models | grep -oE -- '--option [a-z0-9_]+=' | cut -c10- | sort -u)" \
        "$(offers psim --option '')"
    # --option after a model: that model's options only, wherever --model is
    for m in $(models); do
        own=$("$PSIM" models | sed -n "/^$m /,/^[^ ]/p" | grep -oE -- '--option [a-z0-9_]+=' | cut -c10- | sort -u)
        [[ -n $own ]] || fail "psim models lists no options for $m"
        same "'psim --model $m -O '" "$own" "$(offers psim --model "$m" -O '')"
        same "'psim -O  -m $m' (the model after)" "$own" "$(offers_at 2 psim -O '' -m "$m")"
        same "'psim --model=$m --option='" "$own" "$(offers psim --model = "$m" --option =)"
        same "'psim -m$m run -O '" "$own" "$(offers psim run "-m$m" -O '')"
    done
    [[ -z $(offers psim --model no_such_model -O '') ]] ||
        fail "completion of 'psim --model no_such_model -O ' offers words"
    has "'psim --out sc'" "$(offers psim --out sc)" scene.in
    has "'psim --final=sc'" "$(offers psim --final = sc)" scene.in
    has "'psim gen -o sc'" "$(offers psim gen -o sc)" scene.in
    has "'psim topo --topology sc'" "$(offers psim topo --topology sc)" scene.in
    [[ -z $(offers psim --steps '') ]] || fail "completion of 'psim --steps ' offers words: $(offers psim --steps '')"
    [[ -z $(offers psim models '') ]] || fail "completion of 'psim models ' offers words"
    # the values the completion names itself must be the help's
    run_help=$("$PSIM" --help) gen_help=$("$PSIM" gen --help)
    for v in $(offers psim --pin ''); do
        grep -qE "(^|[ ,])${v}[K,. )]" <<<"$run_help" || fail "completion offers --pin $v, which psim --help does not name"
    done
    for v in $(offers psim --mem ''); do
        grep -qw "$v" <<<"$run_help" || fail "completion offers --mem $v, which psim --help does not name"
    done
    for v in $(offers psim gen --place ''); do
        grep -qw "$v" <<<"$gen_help" || fail "completion offers gen --place $v, which psim gen --help does not name"
    done
    [[ -n $(offers psim --pin '') && -n $(offers psim --mem '') && -n $(offers psim gen --place '') ]] ||
        fail "completion offers no values for --pin, --mem or gen --place"
    echo "install: the completion offers $(paste -sd' ' <<<"$subs"), each command's options, $(models | wc -l) models and file names"
    ;;

*)
    fail "unknown check '$what'"
    ;;
esac
