#!/usr/bin/env bash
# The library as a program outside the tree sees it: installs the build into a
# temporary prefix (cmake --install BUILD --prefix TMP), checks what is there (files,
# umbrella header, headers compiling on their own, exported symbols, version), then
# builds examples/c against it with pkg-config (shared; static with --static) and with
# find_package (hairkit::hairkit, hairkit::hairkit_static), runs each build on the
# default scene at 4 hairs per cm^2 and checks its picture: the same bytes from all of
# them and from `hairkit run`. A build without the shared library (HK_SHARED=OFF, as
# CI's sanitizer build) is checked in its static half: the .a, pkg-config --static and
# hairkit::hairkit_static. Exits 77 (skipped) when a tool it needs is missing.
#
# usage: install.sh BUILD_DIR SOURCE_DIR HAIRKIT CMAKE CC LIBDIR SHARED SANITIZE
set -u
build=$1 src=$2 hk=$3 cmake=$4 cc=$5 libdir=$6 shared=$7 sanitize=$8

skip() { echo "SKIP: $*"; exit 77; }
for tool in pkg-config readelf nm "$cc"; do
    command -v "$tool" >/dev/null 2>&1 || skip "'$tool' is not installed"
done
pkg-config --exists libpng || skip "pkg-config does not know libpng (hairkit.pc requires it)"
case "$libdir" in
/*) skip "CMAKE_INSTALL_LIBDIR is absolute ($libdir): the build cannot be installed elsewhere" ;;
esac

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
prefix=$tmp/prefix
lib=$prefix/$libdir
export PKG_CONFIG_PATH=$lib/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}
warn=(-std=c11 -Wall -Wextra -Wpedantic -Werror)

if ! "$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1; then
    cat "$tmp/install.log" >&2
    echo "install: cmake --install failed" >&2
    exit 1
fi

# ---- what is installed ----
installed=("$lib/libhairkit.a")
[ "$shared" = ON ] && installed+=("$lib/libhairkit.so")
for f in "${installed[@]}" "$lib/pkgconfig/hairkit.pc" \
    "$lib/cmake/hairkit/hairkitConfig.cmake" "$lib/cmake/hairkit/hairkitConfigVersion.cmake" \
    "$prefix/include/hairkit/hairkit.h" "$prefix/include/hairkit/version.h" "$prefix/bin/hairkit"; do
    [ -e "$f" ] || fail "not installed: ${f#"$prefix"/}"
done
version=$("$hk" --version | sed 's/^hairkit //')
[ "$(pkg-config --modversion hairkit)" = "$version" ] ||
    fail "hairkit.pc says $(pkg-config --modversion hairkit), hairkit --version $version"
if [ "$shared" = ON ]; then
    soname=$(readelf -d "$lib/libhairkit.so" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
    major=${version%%.*} rest=${version#*.}
    if [ "$major" = 0 ]; then want=libhairkit.so.0.${rest%%.*}; else want=libhairkit.so.$major; fi
    [ "$soname" = "$want" ] || fail "soname '$soname', wanted $want"
    [ -e "$lib/$soname" ] || fail "not installed: $libdir/$soname"
fi

# Every public header is in the umbrella header and compiles on its own, with no feature
# macro and no other include path.
for h in "$prefix"/include/hairkit/*.h; do
    name=$(basename "$h")
    [ "$name" = hairkit.h ] && continue
    grep -q "^#include \"hairkit/$name\"" "$prefix/include/hairkit/hairkit.h" ||
        fail "hairkit/hairkit.h does not include hairkit/$name"
    printf '#include <hairkit/%s>\ntypedef int not_empty;\n' "$name" >"$tmp/one.c"
    "$cc" "${warn[@]}" -fsyntax-only -I"$prefix/include" "$tmp/one.c" 2>"$tmp/cc.err" ||
        fail "hairkit/$name does not compile on its own: $(head -c 400 "$tmp/cc.err")"
done

# The public headers declare the API only: every function declared there has HK_API
# (internal functions are declared in headers under src/, which are not installed).
if grep -n '^[A-Za-z].*\bhk_[a-z0-9_]*(' "$prefix"/include/hairkit/*.h | grep -v 'HK_API\|typedef\|static inline' >"$tmp/internal"; then
    fail "functions declared without HK_API in the public headers: $(head -5 "$tmp/internal")"
fi

if [ "$shared" = ON ]; then
    # The shared library exports exactly the functions declared with HK_API.
    grep -ho '^HK_API [^(]*(' "$prefix"/include/hairkit/*.h | sed -E 's/.*[ *](hk_[A-Za-z0-9_]+) *\($/\1/' |
        sort -u >"$tmp/declared"
    nm -D --defined-only "$lib/libhairkit.so" | awk '{print $NF}' | sort -u >"$tmp/exported"
    if [ "$sanitize" = ON ]; then # no version script with the sanitizers: hk_ names only
        grep '^hk_' "$tmp/exported" >"$tmp/exported.hk"
        mv "$tmp/exported.hk" "$tmp/exported"
    fi
    if ! cmp -s "$tmp/declared" "$tmp/exported"; then
        fail "exported symbols differ from the HK_API declarations (< declared only, > exported only):
    $(diff "$tmp/declared" "$tmp/exported" | grep '^[<>]' | head -20)"
    fi
    echo "install: $(wc -l <"$tmp/exported") functions exported by $soname"
fi

# ---- examples/c built four ways ----
example=$src/examples/c/grow_and_render.c
# docs/library.md shows the program in full: the same text.
sed -n '/^```c$/,/^```$/p' "$src/docs/library.md" | sed '1d;$d' >"$tmp/doc.c"
cmp -s "$tmp/doc.c" "$example" || fail "docs/library.md does not show examples/c/grow_and_render.c as it is"
setup=$src/examples/default/setup.txt
# run NAME PROGRAM: runs the program on the scene, checks its output and picture.
run() {
    local name=$1 prog=$2
    if ! LD_LIBRARY_PATH=$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} "$prog" "$setup" "$tmp/$name.png" 4 \
        >"$tmp/$name.out" 2>"$tmp/$name.err"; then
        fail "$name: the program failed: $(head -c 400 "$tmp/$name.err")"
        return
    fi
    grep -qx "hairkit $version" "$tmp/$name.out" || fail "$name: hk_version() is not '$version': $(head -1 "$tmp/$name.out")"
    grep -q "guides and [1-9][0-9]* strands" "$tmp/$name.out" || fail "$name: no strands: $(cat "$tmp/$name.out")"
    [ "$(head -c 4 "$tmp/$name.png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e47 ] ||
        fail "$name: $name.png is not a PNG"
}
needed() { readelf -d "$1" | grep -c "NEEDED.*libhairkit"; }

if [ "$shared" = ON ]; then
    # pkg-config, shared library
    if "$cc" "${warn[@]}" -o "$tmp/pc-shared" "$example" $(pkg-config --cflags --libs hairkit) 2>"$tmp/cc.err"; then
        [ "$(needed "$tmp/pc-shared")" = 1 ] || fail "pc-shared: does not use libhairkit.so"
        run pc-shared "$tmp/pc-shared"
    else
        fail "pc-shared: cc \$(pkg-config --cflags --libs hairkit) failed: $(head -c 600 "$tmp/cc.err")"
    fi
fi
# pkg-config --static, static library: a copy of the prefix without the .so, so that
# -lhairkit finds libhairkit.a and only pkg-config's private flags complete the link.
cp -a "$prefix" "$tmp/static-prefix"
rm -f "$tmp/static-prefix/$libdir"/libhairkit.so*
if "$cc" "${warn[@]}" -o "$tmp/pc-static" "$example" \
    $(PKG_CONFIG_PATH=$tmp/static-prefix/$libdir/pkgconfig pkg-config --static --cflags --libs hairkit) \
    2>"$tmp/cc.err"; then
    [ "$(needed "$tmp/pc-static")" = 0 ] || fail "pc-static: uses libhairkit.so"
    run pc-static "$tmp/pc-static"
else
    fail "pc-static: cc \$(pkg-config --static --cflags --libs hairkit) failed: $(head -c 600 "$tmp/cc.err")"
fi
# find_package(hairkit), hairkit::hairkit and hairkit::hairkit_static
kinds=static
[ "$shared" = ON ] && kinds="shared static"
for kind in $kinds; do
    static=OFF
    [ $kind = static ] && static=ON
    if "$cmake" -S "$src/examples/c" -B "$tmp/cm-$kind" -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_C_COMPILER="$cc" -DCMAKE_BUILD_TYPE=Release -DHAIRKIT_STATIC=$static >"$tmp/cm.log" 2>&1 &&
        "$cmake" --build "$tmp/cm-$kind" >>"$tmp/cm.log" 2>&1; then
        [ "$(needed "$tmp/cm-$kind/grow_and_render")" = "$([ $kind = shared ] && echo 1 || echo 0)" ] ||
            fail "cmake-$kind: linked the wrong library"
        run cmake-$kind "$tmp/cm-$kind/grow_and_render"
    else
        fail "cmake-$kind: find_package(hairkit) build failed: $(tail -c 1500 "$tmp/cm.log")"
    fi
done

# The same picture from the four builds and from `hairkit run` on that scene.
mkdir -p "$tmp/scene"
sed 's/^HairDensity .*/HairDensity 4/' "$src/examples/default/hairstyle.txt" >"$tmp/scene/hairstyle.txt"
{
    echo "HairstyleInfo hairstyle.txt"
    echo "CollisionInfo \"$src/examples/default/collision.txt\""
    echo "VisualityInfo \"$src/examples/default/visuality.txt\""
    echo "HeadModel \"$src/assets/head.obj\""
    echo "WickModel \"$src/assets/wick.obj\""
} >"$tmp/scene/setup.txt"
if "$hk" run "$tmp/scene/setup.txt" -o "$tmp/cli.png" --width 800 --height 600 --quiet 2>"$tmp/cli.err"; then
    for name in pc-shared pc-static cmake-shared cmake-static; do
        [ -e "$tmp/$name.png" ] || continue
        cmp -s "$tmp/cli.png" "$tmp/$name.png" || fail "$name: not the picture of hairkit run"
    done
else
    fail "hairkit run failed: $(head -c 400 "$tmp/cli.err")"
fi

[ "$fails" -eq 0 ] || { echo "install: $fails failure(s)" >&2; exit 1; }
echo "install: all checks passed"
