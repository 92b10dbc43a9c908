#!/usr/bin/env bash
# An install that stands alone (docs/install.md, "A prefix that moves"): installed into one
# folder and moved to another, with the build tree's OpenImageIO module taken away, the installed
# `deepsea` and a consumer built against the moved prefix read TIFF input (which needs that
# module) and load it, and nothing else, from the moved prefix; `deepsea demo` runs on the
# installed example config. The build tree's module is restored on exit (the test runs alone:
# RUN_SERIAL; if it is killed, the next build relinks the module).
set -euo pipefail
cmake=$1 cxx=$2 build=$3 plugin=$4 consumer=$5 work=$6
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
"$cmake" --install "$build" --prefix "$work/installed" >/dev/null
mv "$work/installed" "$work/moved"
prefix=$(cd "$work/moved" && pwd -P)
build_abs=$(cd "$build" && pwd -P)
work_abs=$(cd "$work" && pwd -P)

# The example configs, where `deepsea demo` and `bake-library` users look for them.
share=$prefix/share/deepsea
for f in demo.yaml library.yaml cameras/authors-800.yaml cameras/small-320.yaml \
         rigs/authors-testset.yaml rigs/paper-eval.yaml rigs/single-down.yaml \
         waters/jerlov-IB.yaml waters/deep-clear.yaml; do
  [[ -f $share/$f ]] || fail "no share/deepsea/$f"
done
installed_module=$(find "$prefix" -name libdeepsea_oiio.so | head -1)
[[ -n $installed_module ]] || fail "no libdeepsea_oiio.so in $prefix"
echo "ok moved prefix: $prefix, configs in $share, module $installed_module"

# The build tree's module out of the way: whatever loads now must find the prefix's.
[[ -f $plugin ]] || fail "no module in the build tree ($plugin): build first"
mv "$plugin" "$plugin.away"
trap 'mv -f "$plugin.away" "$plugin"' EXIT

# $1: a name for the log; the rest: a command that must load the moved prefix's module and
# nothing from the build tree.
loads_from_prefix() {
  local name=$1; shift
  rm -f "$work/ld.$name".*
  LD_DEBUG=libs LD_DEBUG_OUTPUT="$work/ld.$name" "$@" >"$work/$name.txt" 2>&1 \
    || { cat "$work/$name.txt"; fail "$name failed"; }
  local module
  module=$(grep -h -o "calling init: .*libdeepsea_oiio.so" "$work/ld.$name".* | head -1 | sed 's/calling init: //')
  [[ -n $module && $module -ef $installed_module ]] \
    || fail "$name loaded '${module:-no module}', not $installed_module"
  # (The scratch folder, and so the moved prefix, lies in the build tree: left out.)
  if grep -h "calling init: $build_abs/" "$work/ld.$name".* | grep -v "calling init: $work_abs/"; then
    fail "$name loaded the above from the build tree"
  fi
  echo "ok $name: OpenImageIO module $module"
}

# A consumer built against the moved prefix only (static libraries: the package gives it a run
# path to the prefix's module folder).
"$cmake" -S "$consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/configure.txt" 2>&1 \
  || { cat "$work/configure.txt"; fail "consumer configure"; }
"$cmake" --build "$work/consumer" >"$work/build.txt" 2>&1 || { cat "$work/build.txt"; fail "consumer build"; }
run=$work/run
mkdir -p "$run"
"$work/consumer/consumer" "$run" >/dev/null  # bakes tiny.vdb, writes depth.exr
# A 16-bit TIFF colour frame (sRGB codes): no fast path reads it, only OpenImageIO.
/usr/bin/python3 - "$run/colour.tif" <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio
h, w = 36, 48
v, u = np.mgrid[0:h, 0:w]
rgb = np.stack([u * 1300, v * 1800, (u + v) * 700], axis=-1).astype(np.uint16)
out = oiio.ImageOutput.create(sys.argv[1])
assert out.open(sys.argv[1], oiio.ImageSpec(w, h, 3, "uint16")), oiio.geterror()
assert out.write_image(rgb) and out.close(), out.geterror()
PY
cd "$work"  # nothing below may depend on the build or source tree as working folder
loads_from_prefix consumer "$work/consumer/consumer" "$run" "$run/colour.tif" "$run/depth.exr"
loads_from_prefix deepsea_render "$prefix/bin/deepsea" render --asset "$run/tiny.vdb" \
  --rgb "$run/colour.tif" --depth "$run/depth.exr" --layers "$run/cli_layers.exr"
/usr/bin/python3 - "$run/files_layers.exr" "$run/cli_layers.exr" <<'PY'
import sys
import OpenImageIO as oiio
a, b = (oiio.ImageBuf(p) for p in sys.argv[1:3])
assert a.spec().channelnames == b.spec().channelnames, "channels differ"
pa, pb = a.get_pixels(oiio.FLOAT), b.get_pixels(oiio.FLOAT)
same = (pa == pb) | ((pa != pa) & (pb != pb))
assert same.all(), f"{(~same).sum()} values differ from deepsea render"
assert (pa[..., 0] > 0).any(), "the TIFF frame rendered black"
print(f"ok TIFF frame: consumer's layers = installed deepsea render's ({pa.size} values)")
PY

mv -f "$plugin.away" "$plugin"; trap - EXIT  # the demo reads no TIFF

# `deepsea demo`: its default config is the moved prefix's, shown by --help, and it runs (with
# the paper's single scattering: the demo's multiple-scattering bake takes 4 minutes on two
# cores, 30 s this way).
"$prefix/bin/deepsea" demo --help >"$work/demo_help.txt"
grep -q -- "$share/demo.yaml" "$work/demo_help.txt" \
  || { cat "$work/demo_help.txt"; fail "demo --help does not show $share/demo.yaml"; }
src_dir=$(cd "$consumer/../../.." && pwd -P)
! grep -q -- "$src_dir/volumes" "$work/demo_help.txt" || fail "demo --help names the source tree's config"
"$prefix/bin/deepsea" demo --out "$work/demo" --frames 1 --scattering single >"$work/demo.txt" 2>&1 \
  || { cat "$work/demo.txt"; fail "deepsea demo from the moved prefix"; }
[[ -s $work/demo/contact_sheet.png && -s $work/demo/frames/frame_0001.png ]] || fail "demo output"
echo "ok demo: $share/demo.yaml -> $work/demo"
# The installed library manifest finds the cameras, rigs and waters installed beside it.
"$prefix/bin/deepsea" bake-library "$share/library.yaml" --out "$work/library" --dry-run \
  >"$work/library.txt" 2>&1 || { cat "$work/library.txt"; fail "bake-library --dry-run"; }
grep -q "27 of 27 assets" "$work/library.txt" || { cat "$work/library.txt"; fail "library"; }
echo "ok library: $share/library.yaml, $(tail -1 "$work/library.txt")"
echo "package relocated: OK"
