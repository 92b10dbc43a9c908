#!/usr/bin/env bash
# The bad-input matrix (issue 10): hostile inputs for bake, info, reference, import-config,
# bake-library and the image/depth readers, each driven through the real binary. Every case
# must exit non-zero with exactly one line on stderr naming the file or setting, and leave no
# output (nor a temporary) behind. Prints the count at the end.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
v=$src/volumes
edit=$(dirname "$0")/edit_asset.py
cases=0
# bad NAME NEEDLE CMD...: expect_fail, the line contains NEEDLE, no res.* or temporary left.
bad() {
  local name=$1 needle=$2; shift 2
  expect_fail "$name" "$@"
  grep -qF -- "$needle" "$work/err.txt" || { echo "FAIL $name: no '$needle' in the line"; exit 1; }
  expect_absent "$work"/res.*
  if ls -a "$work" | grep -q '\.tmp-'; then echo "FAIL $name: temporary left"; exit 1; fi
  cases=$((cases + 1))
}
cam=$v/cameras/small-320.yaml rig=$v/rigs/authors-testset.yaml
small=(--camera "$cam" --rig "$rig" --water jerlov:IB --xy-step 32 --depth-samples 8)

# inputs: one good asset and frame, and files derived from them
"$ds" bake "${small[@]}" -o "$work/a.vdb" >/dev/null
echo "camera: {width: 32, height: 24, fx: 24.0, fy: 24.0, cx: 15.5, cy: 11.5}" > "$work/cam.yaml"
"$ds" scene --out "$work/f" --frames 1 --camera "$work/cam.yaml" >/dev/null
rgb=$work/f/frame_0001.png depth=$work/f/frame_0001_depth.exr
ref=(reference --camera "$work/cam.yaml" --rig "$rig" --water jerlov:IB)

# --- assets (info, and render reads them the same way) ---
bad "asset: missing" "none.vdb" "$ds" info "$work/none.vdb"
: > "$work/empty.vdb"
bad "asset: empty" "empty.vdb: not an OpenVDB file" "$ds" info "$work/empty.vdb"
echo "not a vdb" > "$work/text.vdb"
bad "asset: text renamed .vdb" "text.vdb: not an OpenVDB file" "$ds" info "$work/text.vdb"
cp "$rgb" "$work/png.vdb"
bad "asset: PNG renamed .vdb" "png.vdb: not an OpenVDB file" "$ds" info "$work/png.vdb"
size=$(stat -c %s "$work/a.vdb")
for n in 8 2000 $((size / 2)) $((size - 1)); do
  head -c "$n" "$work/a.vdb" > "$work/cut.vdb"
  bad "asset: truncated to $n bytes" "cut.vdb: " "$ds" info "$work/cut.vdb"
done
# one flipped byte: in the header, the metadata, the grid descriptors, the data, the end
for off in 3 40 700 1400 3000 $((size / 3)) $((size / 2)) $((size - 200)) $((size - 1)); do
  python3 "$edit" "$work/a.vdb" "$work/flip.vdb" "flip:$off"
  bad "asset: byte $off changed" "flip.vdb: " "$ds" info "$work/flip.vdb"
done
python3 "$edit" "$work/a.vdb" "$work/legacy.vdb" legacy
bad "asset: no integrity record (older deepsea)" "re-bake" "$ds" info "$work/legacy.vdb"
# edited and re-sealed: what the edit broke is found after the hash
python3 "$edit" "$work/a.vdb" "$work/same.vdb" reseal
"$ds" info "$work/same.vdb" >/dev/null  # the re-sealing itself is harmless
for e in no-backscatter:"no backscatter grid" bad-json:"not valid JSON" \
         negative-attenuation:"water.attenuation" zero-lamps:"rig.lights"; do
  python3 "$edit" "$work/a.vdb" "$work/ed.vdb" "${e%%:*}"
  bad "asset: ${e%%:*}, re-sealed" "${e#*:}" "$ds" info "$work/ed.vdb"
done

# --- bake: settings, outputs ---
bad "bake: xy step 1000000" "xy_step must be in [1, 4096]" "$ds" bake "${small[@]}" \
  --xy-step 1000000 -o "$work/res.vdb"
bad "bake: depth samples 2e9" "depth_samples must be in [2, 4096]" "$ds" bake "${small[@]}" \
  --depth-samples 2000000000 -o "$work/res.vdb"
bad "bake: lattice too large" "larger than the limit of 50 million" "$ds" bake "${small[@]}" \
  --xy-step 1 --depth-samples 1000 -o "$work/res.vdb"
bad "bake: -o x.exr" "must end in .vdb" "$ds" bake "${small[@]}" -o "$work/res.exr"
bad "bake: -o without extension" "must end in .vdb" "$ds" bake "${small[@]}" -o "$work/out"
bad "bake: -o missing folder" "does not exist" "$ds" bake "${small[@]}" -o "$work/no/out.vdb"
mkdir -p "$work/dir.vdb"
bad "bake: -o is a folder" "dir.vdb: it is a directory" "$ds" bake "${small[@]}" -o "$work/dir.vdb"
cp "$cam" "$work/setup.vdb"
bad "bake: -o equal to --camera" "is the same file as the input --camera" "$ds" bake \
  --camera "$work/setup.vdb" --rig "$rig" --water jerlov:IB -o "$work/setup.vdb"
cmp -s "$cam" "$work/setup.vdb" || { echo "FAIL: the input was changed"; exit 1; }
printf 'camera:\n  width: 32\n  heigth: 24\n' > "$work/typo.yaml"
bad "bake: misspelt key" "typo.yaml:3" "$ds" bake --camera "$work/typo.yaml" --rig "$rig" \
  --water jerlov:IB -o "$work/res.vdb"
printf 'camera: {width: wide, height: 24, fx: 1, fy: 1, cx: 0, cy: 0}\n' > "$work/type.yaml"
bad "bake: wrong type" "type.yaml:1" "$ds" bake --camera "$work/type.yaml" --rig "$rig" \
  --water jerlov:IB -o "$work/res.vdb"
printf 'camera: {width: 200000, height: 200000, fx: 1, fy: 1, cx: 0, cy: 0}\n' > "$work/huge.yaml"
bad "bake: 200000^2 camera" "megapixels" "$ds" bake --camera "$work/huge.yaml" --rig "$rig" \
  --water jerlov:IB -o "$work/res.vdb"
printf 'water: {name: w, attenuation: [-1, 0.2, 0.2], scattering: [0.1, 0.1, 0.1], phase: isotropic}\n' \
  > "$work/negwater.yaml"
bad "bake: negative attenuation" "negwater.yaml" "$ds" bake --camera "$cam" --rig "$rig" \
  --water "$work/negwater.yaml" -o "$work/res.vdb"
printf 'rig:\n  lights: []\n' > "$work/nolamps.yaml"
bad "bake: zero lamps" "nolamps.yaml" "$ds" bake --camera "$cam" --rig "$work/nolamps.yaml" \
  --water jerlov:IB -o "$work/res.vdb"
# Stated limits, checked before any work (issue 29): each used to run for minutes, take
# gigabytes, bake NaN into an asset or end in OpenVDB's raw ArithmeticError with exit 1.
for c in "fx: 1.0e-4, fy: 1.0e-4, cx: 159.5, cy: 119.5" "fx: 5.0e-324, fy: 240, cx: 159.5, cy: 119.5" \
         "fx: 240, fy: 240, cx: 1.0e6, cy: 119.5" "fx: 240, fy: 1.0, cx: 159.5, cy: 119.5"; do
  printf 'camera: {width: 320, height: 240, %s}\n' "$c" > "$work/wide.yaml"
  t0=$SECONDS
  bad "bake: camera beyond 80 degrees ($c)" "limit is 80 degrees per axis" "$ds" bake \
    --camera "$work/wide.yaml" --rig "$rig" --water jerlov:IB -o "$work/res.vdb"
  (( SECONDS - t0 < 5 )) || { echo "FAIL: the wide camera took $((SECONDS - t0)) s"; exit 1; }
done
lamp() {  # lamp FILE POSITION INTENSITY
  printf 'rig:\n  lights:\n    - position: %s\n      direction: [0, 0, 1]\n      intensity: %s\n' \
    "$2" "$3" > "$1"
}
for i in "[1.0e39, 1, 1]" "[1, 1.0e308, 1]" "[1, 1, 1.0e10]"; do
  lamp "$work/bright.yaml" "[0.5, 0, 0]" "$i"
  bad "bake: lamp intensity $i" "bright.yaml:5: rig.lights[0].intensity: must be at most 1e+09 W/sr" \
    "$ds" bake --camera "$cam" --rig "$work/bright.yaml" --water jerlov:IB -o "$work/res.vdb"
done
for p in "[1.0e300, 0, 0]" "[0, 0, 100.5]" "[1.0e308, 1.0e308, 0]"; do
  lamp "$work/far.yaml" "$p" "[1, 1, 1]"
  bad "bake: lamp at $p" "beyond the limit of 100 m" "$ds" bake --camera "$cam" \
    --rig "$work/far.yaml" --water jerlov:IB -o "$work/res.vdb"
done
for z in 1e6 1e-300 0.001 1001; do
  bad "bake: --z-max $z" "--z-max: must be in [0.01, 1000] metres" "$ds" bake "${small[@]}" \
    --z-max "$z" -o "$work/res.vdb"
done
bad "bake: --paths 2147483647" "paths must be in [1, 4194304]" "$ds" bake "${small[@]}" \
  --scattering multiple --paths 2147483647 -o "$work/res.vdb"
# A narrow camera, 1 cm deep, 4096 samples: cells OpenVDB cannot transform, before any column.
printf 'camera: {width: 64, height: 48, fx: 1.0e5, fy: 1.0e5, cx: 31.5, cy: 23.5}\n' > "$work/tele.yaml"
bad "bake: lattice below OpenVDB's smallest transform" "too small for an OpenVDB transform" \
  "$ds" bake --camera "$work/tele.yaml" --rig "$rig" --water jerlov:IB --z-max 0.01 \
  --depth-samples 4096 --xy-step 8 -o "$work/res.vdb"
! grep -q ArithmeticError "$work/err.txt" || { echo "FAIL: OpenVDB's message reached the user"; exit 1; }
mkdir -p "$work/ro" && chmod 555 "$work/ro"
if [[ ! -w "$work/ro" ]] || [[ $(id -u) -ne 0 ]]; then
  bad "bake: unwritable folder" "ro/out.vdb" "$ds" bake "${small[@]}" -o "$work/ro/out.vdb"
fi

# --- reference: quadrature, outputs, images and depths ---
bad "reference: --rel-tol 1e-300" "rel_tol must be in" "$ds" "${ref[@]}" --rgb "$rgb" \
  --depth "$depth" --rel-tol 1e-300 -o "$work/res.png"
cp "$rgb" "$work/in.png"
bad "reference: -o equal to --rgb" "is the same file as the input --rgb" "$ds" "${ref[@]}" \
  --rgb "$work/in.png" --depth "$depth" -o "$work/in.png"
cmp -s "$rgb" "$work/in.png" || { echo "FAIL: --rgb was changed"; exit 1; }
bad "reference: -o equal to --layers" "is the same file as the -o output" "$ds" "${ref[@]}" \
  --rgb "$rgb" --depth "$depth" -o "$work/res.exr" --layers "$work/res.exr"
bad "reference: -o unknown extension" "cannot write '.xyz'" "$ds" "${ref[@]}" --rgb "$rgb" \
  --depth "$depth" -o "$work/res.xyz"
bad "reference: --layers not .exr" "res.png" "$ds" "${ref[@]}" --rgb "$rgb" --depth "$depth" \
  --layers "$work/res.png"
: > "$work/empty.png"
bad "image: empty" "empty.png" "$ds" "${ref[@]}" --rgb "$work/empty.png" --depth "$depth" \
  -o "$work/res.png"
head -c 300 "$rgb" > "$work/cut.png"
bad "image: truncated PNG" "cut.png" "$ds" "${ref[@]}" --rgb "$work/cut.png" --depth "$depth" \
  -o "$work/res.png"
# JPEG colour and EXR depth are decoded by libjpeg-turbo and OpenEXR directly: a cut file is
# still one line (libjpeg would fill the missing rows with grey and only warn).
"$ds" "${ref[@]}" --rgb "$rgb" --depth "$depth" -o "$work/ok.jpg" >/dev/null
head -c 400 "$work/ok.jpg" > "$work/cut.jpg"
bad "image: truncated JPEG" "cut.jpg" "$ds" "${ref[@]}" --rgb "$work/cut.jpg" --depth "$depth" \
  -o "$work/res.png"
# A PNG never reaches OpenImageIO, whose libpng printed a line of its own before deepsea's: a
# cut PNG as depth, and one named .tif, are read by libspng and fail with one line.
head -c 30 "$rgb" > "$work/cut30.png"
bad "depth: PNG cut in its header" "cut30.png" "$ds" "${ref[@]}" --rgb "$rgb" \
  --depth "$work/cut30.png" -o "$work/res.png"
cp "$work/cut30.png" "$work/cut30.tif"
bad "image: cut PNG named .tif" "cut30.tif" "$ds" "${ref[@]}" --rgb "$work/cut30.tif" \
  --depth "$depth" -o "$work/res.png"
head -c $(($(stat -c %s "$depth") / 2)) "$depth" > "$work/cut.exr"
bad "depth: truncated EXR" "cut.exr" "$ds" "${ref[@]}" --rgb "$rgb" --depth "$work/cut.exr" \
  -o "$work/res.png"
cp "$rgb" "$work/png.exr"
bad "depth: PNG renamed .exr" "png.exr" "$ds" "${ref[@]}" --rgb "$rgb" --depth "$work/png.exr" \
  -o "$work/res.png"
bad "image: missing" "none.png" "$ds" "${ref[@]}" --rgb "$work/none.png" --depth "$depth" \
  -o "$work/res.png"
# headers claiming 20000^2 and 100000^2 pixels: refused from the header, at once
python3 - "$work" <<'PY'
import struct, sys, zlib
w = sys.argv[1]
def png(path, width, height, data=b""):
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
                           chunk(b"IDAT", zlib.compress(data)) + chunk(b"IEND", b""))
def npy(path, h, wd):
    hdr = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }" % (h, wd)
    hdr += " " * (63 - len(hdr) % 64) + "\n"
    open(path, "wb").write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(hdr)) + hdr.encode())
for side in (20000, 100000):
    png(f"{w}/big{side}.png", side, side)
    npy(f"{w}/big{side}.npy", side, side)
    open(f"{w}/big{side}.pfm", "wb").write(b"Pf\n%d %d\n-1.0\n" % (side, side))
png(f"{w}/one.png", 1, 1, b"\0\x80\x80\x80")  # a valid 1x1 grey image
PY
for side in 20000 100000; do
  for f in png npy pfm; do
    if [[ $f == png ]]; then args=(--rgb "$work/big$side.png" --depth "$depth")
    else args=(--rgb "$rgb" --depth "$work/big$side.$f"); fi
    t0=$SECONDS
    bad "header claiming ${side}x$side ($f)" "big$side.$f: image size ${side}x$side" \
      "$ds" "${ref[@]}" "${args[@]}" -o "$work/res.png"
    (( SECONDS - t0 < 5 )) || { echo "FAIL: ${side}^2 $f took $((SECONDS - t0)) s"; exit 1; }
  done
done
bad "image: 1x1 against a 32x24 depth" "sizes differ" "$ds" "${ref[@]}" --rgb "$work/one.png" \
  --depth "$depth" -o "$work/res.png"
printf 'Pf\n32 24\n-1.0\n' > "$work/short.pfm"
bad "depth: PFM without raster" "short.pfm: truncated PFM raster" "$ds" "${ref[@]}" \
  --rgb "$rgb" --depth "$work/short.pfm" -o "$work/res.png"
bad "depth: 8-bit PNG" "8 bits" "$ds" "${ref[@]}" --rgb "$rgb" --depth "$rgb" --depth-channel R -o "$work/res.png"

# --- import-config ---
printf 'bogus: 1\n' > "$work/dsr.yaml"
bad "import-config: unknown key" "dsr.yaml" "$ds" import-config "$work/dsr.yaml" \
  -o "$work/res.yaml"
bad "import-config: missing" "none.yaml" "$ds" import-config "$work/none.yaml" -o "$work/res.yaml"
cfg="$src/../shared/data/rgbd/seafloor-descent/deepsearenderer_config.yaml"
if [[ -f $cfg ]]; then
  cp "$cfg" "$work/dsr-good.yaml"
  cp "$cfg" "$work/keep.yaml"
  bad "import-config: -o equal to its input" "is the same file as the input" "$ds" \
    import-config "$work/dsr-good.yaml" -o "$work/dsr-good.yaml"
  cmp -s "$work/keep.yaml" "$work/dsr-good.yaml" || { echo "FAIL: input changed"; exit 1; }
fi

# --- bake-library ---
printf 'cameras: [%s]\nrigs: [%s]\nwaters: [jerlov:IB]\nbake: {xy_step: 1000000}\n' \
  "$cam" "$rig" > "$work/lib.yaml"
bad "bake-library: xy_step out of range" "lib.yaml: bake: xy_step" "$ds" bake-library \
  "$work/lib.yaml" --out "$work/res.lib"
printf 'cameras: [%s]\nrigs: [%s]\nwaters: [jerlov:IB]\nbake: {xy_stepp: 8}\n' \
  "$cam" "$rig" > "$work/lib2.yaml"
bad "bake-library: misspelt key" "lib2.yaml:4" "$ds" bake-library "$work/lib2.yaml" \
  --out "$work/res.lib"
printf 'cameras: [%s]\nrigs: [%s]\nwaters: [jerlov:IB]\nbake: {xy_step: 32, depth_samples: 8}\n' \
  "$cam" "$rig" > "$work/lib3.yaml"
# --shard "$UNSET": it used to bake the whole library on every task of an array job.
for sh in "" "1" "a/b" "1/2/3" " 0/2" "0/0" "2/2" "99999999999/2"; do
  bad "bake-library: --shard '$sh'" "shard" "$ds" bake-library "$work/lib3.yaml" \
    --out "$work/res.lib" --shard "$sh"
  rc=$(set +e; "$ds" bake-library "$work/lib3.yaml" --out "$work/res.lib" --shard "$sh" \
    >/dev/null 2>&1; echo $?)
  [[ $rc -eq 2 ]] || { echo "FAIL: --shard '$sh' exit $rc, expected 2"; exit 1; }
done

# --- a full disk: a 128 KB tmpfs (root only; the small asset is about 360 KB) ---
full=$work/full
mkdir -p "$full"
if mount -t tmpfs -o size=128k tmpfs "$full" 2>/dev/null; then
  trap 'umount "$full" 2>/dev/null || true' EXIT
  set +e
  "$ds" bake "${small[@]}" -o "$full/a.vdb" >"$work/out.txt" 2>"$work/err.txt"
  rc=$?
  set -e
  [[ $rc -ne 0 && $(wc -l <"$work/err.txt") -eq 1 ]] || { echo "FAIL full disk: rc $rc"; cat "$work/err.txt"; exit 1; }
  grep -q "No space left on device" "$work/err.txt" || { echo "FAIL full disk"; cat "$work/err.txt"; exit 1; }
  [[ -z $(ls -A "$full") ]] || { echo "FAIL full disk: left $(ls -A "$full")"; exit 1; }
  echo "ok full disk (exit $rc): $(cat "$work/err.txt")"
  cases=$((cases + 1))
  umount "$full"; trap - EXIT
else
  echo "note: cannot mount a tmpfs here (not root?): the full-disk case is skipped"
fi
echo "bad input: $cases hostile inputs, each one clean line, no output left"
