#!/usr/bin/env bash
# A consumer project (tests/package/consumer) configured with find_package(deepsea) against
# the installed prefix only, built and run: it bakes, writes, reloads and renders a frame from
# its own buffers with only <deepsea/deepsea.h>, the same bits as the installed `deepsea render`.
set -euo pipefail
cmake=$1 cxx=$2 prefix=$3 consumer=$4 work=$5
rm -rf "$work"; mkdir -p "$work/run"
# Only the prefix: no package registry, so the build tree cannot stand in for the install.
"$cmake" -S "$consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/configure.txt" 2>&1 \
  || { cat "$work/configure.txt"; exit 1; }
prefix_abs=$(cd "$prefix" && pwd -P)
grep -q "deepsea .* from $prefix_abs/" "$work/configure.txt" \
  || { echo "FAIL: deepsea not found in $prefix_abs"; grep deepsea "$work/configure.txt"; exit 1; }
"$cmake" --build "$work/build" >"$work/build.txt" 2>&1 || { cat "$work/build.txt"; exit 1; }
"$work/build/consumer" "$work/run"
[[ -s $work/run/final.png && -s $work/run/tiny.vdb ]]
# The same frame through the installed command: every layer the same bits.
"$prefix/bin/deepsea" render --asset "$work/run/tiny.vdb" --rgb "$work/run/colour.exr" \
  --depth "$work/run/depth.exr" --layers "$work/run/cli.exr" >/dev/null
/usr/bin/python3 - "$work/run/layers.exr" "$work/run/cli.exr" <<'PY'
import sys
import OpenImageIO as oiio
a, b = (oiio.ImageBuf(p) for p in sys.argv[1:3])
assert a.spec().channelnames == b.spec().channelnames, "channels differ"
pa, pb = a.get_pixels(oiio.FLOAT), b.get_pixels(oiio.FLOAT)
same = (pa == pb) | ((pa != pa) & (pb != pb))
assert same.all(), f"{(~same).sum()} values differ from deepsea render"
print(f"consumer's layers = deepsea render's: {pa.size} values")
PY
echo "package cmake consumer: OK"
