#!/usr/bin/env bash
# OpenImageIO is a module loaded on first use (src/io/oiio_plugin.h): a PNG + EXR job never
# loads it; a TIFF does, and reads as before; a module that cannot be loaded is one line naming
# it, a non-zero exit and no output, and only for the frames that need it.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$src/tests/integration/cli_lib.sh"
cam=$src/volumes/cameras/small-320.yaml

"$ds" scene --out "$work/in" --frames 2 --camera "$cam" >/dev/null
"$ds" bake --camera "$cam" --rig "$src/volumes/rigs/authors-testset.yaml" --water jerlov:IB \
  -o "$work/a.vdb" >/dev/null
f1=$work/in/frame_0001.png d1=$work/in/frame_0001_depth.exr

# The libraries the dynamic loader maps (LD_DEBUG=files names each one it opens).
loaded() { LD_DEBUG=files LD_DEBUG_OUTPUT="$work/ld" "$@" >/dev/null; cat "$work"/ld.*; rm -f "$work"/ld.*; }

for out in seq.png seq.jpg seq.exr; do
  loaded "$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
    -o "$work/${out%.*}" --format "${out#*.}" >"$work/libs.txt"
  if grep -q -E "OpenImageIO|deepsea_oiio" "$work/libs.txt"; then
    echo "FAIL: a PNG + EXR -> ${out#*.} sequence loaded OpenImageIO:"
    grep -E "OpenImageIO|deepsea_oiio" "$work/libs.txt" | head -3
    exit 1
  fi
  [[ $(ls "$work/${out%.*}" | grep -c "\.${out#*.}$") -eq 2 ]]
done
echo "ok PNG + EXR in, PNG, JPEG and EXR out: OpenImageIO never loaded"

# The same frame as TIFF (written by Python's OpenImageIO): the module is loaded, and the
# render is the PNG frame's (8-bit codes, the same decode table).
/usr/bin/python3 - "$f1" "$work/frame.tif" <<'PY'
import sys
import OpenImageIO as oiio
buf = oiio.ImageBuf(sys.argv[1])
assert buf.write(sys.argv[2], "uint8"), oiio.geterror()
PY
loaded "$ds" render --asset "$work/a.vdb" --rgb "$work/frame.tif" --depth "$d1" \
  -o "$work/tif.png" --exposure 2 >"$work/libs.txt"
grep -q "deepsea_oiio" "$work/libs.txt" || { echo "FAIL: the TIFF did not load the module"; exit 1; }
"$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$d1" -o "$work/png.png" --exposure 2 \
  >/dev/null
/usr/bin/python3 - "$work/tif.png" "$work/png.png" <<'PY'
import sys
import OpenImageIO as oiio
a, b = (oiio.ImageBuf(p).get_pixels(oiio.UINT8) for p in sys.argv[1:3])
assert (a == b).all(), "a TIFF frame renders differently from the same frame as PNG"
PY
echo "ok TIFF in: module loaded, the same image as from the PNG"

# A module that cannot be loaded: one line naming it, for the TIFF only.
export DEEPSEA_OIIO_PLUGIN=$work/missing/libdeepsea_oiio.so
expect_fail missing-module "$ds" render --asset "$work/a.vdb" --rgb "$work/frame.tif" \
  --depth "$d1" -o "$work/none.png"
grep -q "libdeepsea_oiio.so could not be loaded\|module (libdeepsea_oiio.so) could not be loaded" \
  "$work/err.txt"
grep -q "$work/missing/libdeepsea_oiio.so" "$work/err.txt"
expect_absent "$work/none.png"
printf 'not an ELF file\n' >"$work/bogus.so"
expect_fail bogus-module env DEEPSEA_OIIO_PLUGIN="$work/bogus.so" "$ds" render \
  --asset "$work/a.vdb" --rgb "$work/frame.tif" --depth "$d1" -o "$work/none.png"
expect_absent "$work/none.png"
"$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$d1" -o "$work/fine.png" >/dev/null
[[ -s $work/fine.png ]]
echo "ok without the module: PNG still renders"
echo "oiio module: OK"
