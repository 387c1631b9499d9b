#!/usr/bin/env bash
# The installed package from the outside (ctest api-install): installs the build into a temporary prefix, checks what
# is there (public headers only, libpenumbra with its SONAME exporting pn_* alone and without Embree, the CMake and
# pkg-config packages, the CLI, the Python module) and that every place reports one version, then builds examples/
# out of tree against the prefix alone (C++ through find_package, shared and static; C through pkg-config), runs
# them and the Python example, and checks each frame's visibility against the installed CLI's render of the same
# frame, bit for bit, and their stage outputs against each other; the engine-style example (its own OpenCL context,
# kernels, map and G-buffer, shaded by pn_shade) checks itself against the Renderer.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR SCRATCH VERSION EXR_CHANNEL_EQUAL PYTHON PYTHON_DIR
set -euo pipefail
build=$1 source=$2 scratch=$3 version=$4 exr_equal=$5 python=${6:-} python_dir=${7:-}
prefix=$scratch/prefix
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$scratch" && mkdir -p "$scratch"

echo "== cmake --install into $prefix"
cmake --install "$build" --prefix "$prefix" > "$scratch/install.log"
libdir=$(cd "$prefix" && dirname "$(find . -name 'libpenumbra.so' | head -n 1)")
[ -n "$libdir" ] || fail "no libpenumbra.so under $prefix"
lib=$prefix/$libdir
for f in include/penumbra/penumbra.h include/penumbra/penumbra.hpp include/penumbra/version.h "$libdir/libpenumbra.a" \
         "$libdir/libpenumbra.so.${version%%.*}" "$libdir/cmake/penumbra/penumbraConfig.cmake" \
         "$libdir/cmake/penumbra/penumbraConfigVersion.cmake" "$libdir/pkgconfig/penumbra.pc" bin/penumbra; do
  [ -e "$prefix/$f" ] || fail "$f is not installed"
done
internal=$(find "$prefix/include" -type f | grep -Ev '/include/penumbra/[a-z]+\.(h|hpp)$' || true)
[ -z "$internal" ] || fail "headers beyond include/penumbra/*.h(pp) are installed: $(echo "$internal" | head -n 3)"
readelf -d "$lib/libpenumbra.so" | grep -q "SONAME.*libpenumbra.so.${version%%.*}]" || fail "no SONAME libpenumbra.so.${version%%.*}"
! readelf -d "$lib/libpenumbra.so" | grep -qi embree || fail "libpenumbra.so needs Embree"
others=$(nm -D --defined-only "$lib/libpenumbra.so" | awk '{print $3}' | grep -v '^pn_' | grep -v '^$' || true)
[ -z "$others" ] || fail "libpenumbra.so exports more than pn_*: $(echo "$others" | head -n 3)"

echo "== one version: $version"
[ "$("$prefix/bin/penumbra" --version)" = "penumbra $version" ] || fail "penumbra --version"
export PKG_CONFIG_PATH=$lib/pkgconfig
[ "$(pkg-config --modversion penumbra)" = "$version" ] || fail "pkg-config --modversion penumbra"
grep -q "PN_VERSION_STRING \"$version\"" "$prefix/include/penumbra/version.h" || fail "version.h"
grep -q "set(PACKAGE_VERSION \"$version\")" "$prefix/$libdir/cmake/penumbra/penumbraConfigVersion.cmake" ||
  fail "penumbraConfigVersion.cmake"

echo "== the CLI's frame"
frame=(builtin:box 64x48 pcf)
"$prefix/bin/penumbra" render "${frame[0]}" --size "${frame[1]}" -t "${frame[2]}" -o "$scratch/cli.exr" --png none -q

echo "== examples/cpp through find_package (shared, then static)"
for kind in shared static; do
  cmake -S "$source/examples/cpp" -B "$scratch/cpp-$kind" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DPENUMBRA_EXAMPLE_STATIC=$([ $kind = static ] && echo ON || echo OFF) \
        > "$scratch/cpp-$kind.log"
  cmake --build "$scratch/cpp-$kind" >> "$scratch/cpp-$kind.log"
  "$scratch/cpp-$kind/render_frame" "${frame[@]}" "$scratch/cpp-$kind.exr" "$scratch/cpp-$kind.blur" |
    tee "$scratch/cpp-$kind.out"
done
! readelf -d "$scratch/cpp-static/render_frame" | grep -q libpenumbra || fail "the static example loads libpenumbra.so"

echo "== examples/c through pkg-config"
make -s -C "$scratch" -f "$source/examples/c/Makefile" SRC_DIR="$source/examples/c" > "$scratch/c.log"
"$scratch/render_frame_c" "${frame[@]}" "$scratch/c.exr" "$scratch/c.blur" | tee "$scratch/c.out"

echo "== examples/c/engine_shade.c: pcss and vssm on the program's own map and G-buffer, against the Renderer"
"$scratch/engine_shade_c" | tee "$scratch/engine.out" || fail "engine_shade_c: pn_shade disagrees with the Renderer"
[ "$(grep -c ': agrees$' "$scratch/engine.out")" = 2 ] || fail "engine_shade_c did not check both techniques"

outputs=(cpp-shared cpp-static c)
if [ -n "$python" ]; then
  echo "== examples/python"
  PYTHONPATH="$prefix/$python_dir" "$python" "$source/examples/python/render_frame.py" "${frame[@]}" \
    "$scratch/python.exr" "$scratch/python.blur" | tee "$scratch/python.out"
  outputs+=(python)
fi

echo "== bit for bit"
for out in "${outputs[@]}"; do
  grep -qx "penumbra $version" "$scratch/$out.out" || fail "$out reports another version"
  "$exr_equal" "$scratch/cli.exr" "$scratch/$out.exr" visibility.Y R G B || fail "$out's frame differs from the CLI's"
  cmp "$scratch/cpp-shared.blur" "$scratch/$out.blur" || fail "$out's stage output differs from the C++ example's"
done
echo "api-install: ${outputs[*]} equal the CLI's frame"
