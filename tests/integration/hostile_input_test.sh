#!/usr/bin/env bash
# Hostile and careless inputs of a user with thousands of frames (issue 29): paths that resolve
# onto the inputs, links, devices, non-finite colour, files cut short, exit codes, limits. Each
# case drives the real binary: the documented exit code, one line on stderr naming the file or
# option, and no input ever changed or output half-written.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
py=/usr/bin/python3
v=$src/volumes
cases=0
# code NAME CODE NEEDLE CMD...: exits CODE with one line on stderr that contains NEEDLE.
code() {
  local name=$1 want=$2 needle=$3; shift 3
  expect_fail "$name" "$@"
  set +e; "$@" >/dev/null 2>&1; local rc=$?; set -e
  [[ $rc -eq $want ]] || { echo "FAIL $name: exit $rc, expected $want"; exit 1; }
  grep -qF -- "$needle" "$work/err.txt" || { echo "FAIL $name: no '$needle' in the line"; exit 1; }
  cases=$((cases + 1))
}
# unchanged NAME: the input frames are byte for byte as made.
unchanged() {
  (cd "$work/in" && sha256sum -c --quiet "$work/in.sha") ||
    { echo "FAIL $1: an input frame was changed"; exit 1; }
}

rig=$v/rigs/authors-testset.yaml
echo "camera: {width: 32, height: 24, fx: 24.0, fy: 24.0, cx: 15.5, cy: 11.5}" >"$work/cam.yaml"
"$ds" bake --camera "$work/cam.yaml" --rig "$rig" --water jerlov:IB --xy-step 8 \
  --depth-samples 8 -o "$work/a.vdb" >/dev/null
"$ds" scene --out "$work/in" --frames 2 --camera "$work/cam.yaml" >/dev/null
(cd "$work/in" && sha256sum frame_* >"$work/in.sha")
seq=(render --asset "$work/a.vdb" --rgb "$work/in/frame_*[0-9].png" --depth "$work/in/*_depth.exr")
one=(render --asset "$work/a.vdb" --rgb "$work/in/frame_0001.png" --depth "$work/in/frame_0001_depth.exr")

# --- outputs that resolve onto the inputs: refused before anything is written ---
for o in "in/nosuch/.." "in/a/b/../.." "./in/x/../" "in/"; do
  code "sequence -o $o" 2 "is the folder of the input" bash -c \
    "cd '$work' && '$ds' ${seq[*]@Q} -o '$o'"
  unchanged "sequence -o $o"
done
code "sequence --layers in/nosuch/.." 2 "is the folder of the input" \
  "$ds" "${seq[@]}" --layers "$work/in/nosuch/.."
ln -s "$work/in" "$work/in-link"
code "sequence -o a link to the input folder" 2 "is the folder of the input" \
  "$ds" "${seq[@]}" -o "$work/in-link"
code "one frame -o in/nosuch/../frame_0001.png" 2 "also the colour input" \
  "$ds" "${one[@]}" -o "$work/in/nosuch/../frame_0001.png"
mkdir -p "$work/out"
ln -s "$work/in/frame_0001.png" "$work/out/frame_0001.png"
code "sequence: an output is a link to an input" 2 "is one of this render's input files" \
  "$ds" "${seq[@]}" -o "$work/out"
unchanged "links"
rm -rf "$work/out" "$work/in/nosuch" "$work/in/a" "$work/in/x"
[[ ! -e $work/in/nosuch && $(ls "$work/in" | wc -l) -eq 5 ]] || { echo "FAIL: in/ changed"; exit 1; }

# --- -o through links: a link to a file is written through, anything else is refused ---
their "[1.2]" "[0.4, 0.071, 0.06]" 4 >"$work/theirs.yaml"
theirs=$work/theirs.yaml
(cd "$work" && "$ds" import-config "$theirs" -o - >"$work/stdout.yaml")
grep -q "^camera:" "$work/stdout.yaml" || { echo "FAIL: -o - wrote no YAML to stdout"; exit 1; }
ls -a "$work" | grep -q '^-$' && { echo "FAIL: -o - wrote a file named -"; exit 1; }
echo "# shared" >"$work/shared.yaml"
ln -s "$work/shared.yaml" "$work/setup.yaml"
"$ds" import-config "$theirs" -o "$work/setup.yaml" >/dev/null
[[ -L $work/setup.yaml ]] || { echo "FAIL: the link was replaced by a file"; exit 1; }
grep -q "^camera:" "$work/shared.yaml" || { echo "FAIL: not written through the link"; exit 1; }
ln -s /dev/null "$work/devnull.yaml"
code "import-config -o a link to /dev/null" 4 "not a regular file" \
  "$ds" import-config "$theirs" -o "$work/devnull.yaml"
[[ -L $work/devnull.yaml && -c /dev/null ]] || { echo "FAIL: /dev/null or its link replaced"; exit 1; }
ln -s "$work/nowhere.yaml" "$work/dangling.yaml"
code "import-config -o a dangling link" 4 "leads nowhere" \
  "$ds" import-config "$theirs" -o "$work/dangling.yaml"
mkfifo "$work/pipe.png"
code "render -o a named pipe" 4 "not a regular file" "$ds" "${one[@]}" -o "$work/pipe.png"
[[ -p $work/pipe.png ]] || { echo "FAIL: the pipe was replaced"; exit 1; }

# --- inputs that never end, or are no file ---
code "render --rgb /dev/zero" 4 "/dev/zero: is not a regular file" timeout 10 \
  "$ds" render --asset "$work/a.vdb" --rgb /dev/zero --depth "$work/in/frame_0001_depth.exr" \
  -o "$work/res.png"
code "import-config /dev/zero" 4 "/dev/zero: is not a regular file" timeout 10 \
  "$ds" import-config /dev/zero
code "bake --config a folder" 4 "is a folder" "$ds" bake --config "$work/in" -o "$work/res.vdb"
code "info a pipe" 4 "not a regular file" timeout 10 "$ds" info "$work/pipe.png"
code "render --rgb ''" 2 "--rgb: an empty value" "$ds" render --asset "$work/a.vdb" --rgb '' \
  --depth "$work/in/frame_0001_depth.exr" -o "$work/res.png"
code "--asset=" 2 "--asset: an empty value" "$ds" render --asset= --rgb "$work/in/frame_0001.png" \
  --depth "$work/in/frame_0001_depth.exr" -o "$work/res.png"
long=$(printf 'x%.0s' {1..300})
code "a file name too long" 4 "File name too long" "$ds" "${one[@]}" -o "$work/$long.png"

# --- a legal 250-character output name gets a temporary ---
name=$(printf 'n%.0s' {1..246}).png
"$ds" "${one[@]}" -o "$work/$name" >/dev/null
[[ -s $work/$name ]] || { echo "FAIL: the 250-character output was not written"; exit 1; }

# --- one frame: the exit code of what failed, as reference gives ---
code "one frame: missing depth" 4 "nosuch_depth.exr" "$ds" render --asset "$work/a.vdb" \
  --rgb "$work/in/frame_0001.png" --depth "$work/nosuch_depth.exr" -o "$work/res.png"
"$ds" scene --out "$work/big" --frames 1 --width 48 --height 36 >/dev/null
code "one frame: sizes differ" 3 "sizes differ" "$ds" render --asset "$work/a.vdb" \
  --rgb "$work/big/frame_0001.png" --depth "$work/in/frame_0001_depth.exr" -o "$work/res.png"

# --- float colour with one NaN: an input error naming the pixel ---
"$py" - "$work" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
w = sys.argv[1]
rgb = np.full((24, 32, 3), 0.3, np.float32)
rgb[5, 7, 1] = np.nan
out = oiio.ImageOutput.create(w + "/nan.exr")
out.open(w + "/nan.exr", oiio.ImageSpec(32, 24, 3, "float"))
out.write_image(rgb)
out.close()
two = np.full((24, 32, 2), 0.3, np.float32)
spec = oiio.ImageSpec(32, 24, 2, "float")
spec.channelnames = ("R", "G")
out = oiio.ImageOutput.create(w + "/two.exr")
out.open(w + "/two.exr", spec)
out.write_image(two)
out.close()
PY
code "colour EXR with a NaN" 3 "nan.exr: pixel (7, 5) G is NaN" "$ds" render --asset "$work/a.vdb" \
  --rgb "$work/nan.exr" --depth "$work/in/frame_0001_depth.exr" -o "$work/res.png"
code "2-channel EXR as colour" 3 "are not a colour image" "$ds" render --asset "$work/a.vdb" \
  --rgb "$work/two.exr" --depth "$work/in/frame_0001_depth.exr" -o "$work/res.png"

# --- a JPEG that says it is upside down ---
"$ds" "${one[@]}" -o "$work/up.jpg" >/dev/null
"$py" - "$work/up.jpg" "$work/turned.jpg" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
# APP1 "Exif": a little-endian TIFF with one IFD0 entry, orientation (0x0112, SHORT) = 3
tiff = b"II*\x00" + struct.pack("<I", 8) + struct.pack("<H", 1) + \
    struct.pack("<HHIHH", 0x0112, 3, 1, 3, 0) + struct.pack("<I", 0)
app1 = b"Exif\x00\x00" + tiff
open(sys.argv[2], "wb").write(data[:2] + b"\xff\xe1" + struct.pack(">H", len(app1) + 2) + app1 + data[2:])
PY
code "JPEG with EXIF orientation 3" 3 "EXIF orientation 3 (rotated 180 degrees)" \
  "$ds" render --asset "$work/a.vdb" --rgb "$work/turned.jpg" \
  --depth "$work/in/frame_0001_depth.exr" -o "$work/res.png"

# --- --resume: a PNG that lost its last bytes is rendered again ---
"$ds" "${seq[@]}" -o "$work/seq" >/dev/null
cp "$work/seq/frame_0002.png" "$work/whole.png"
head -c -12 "$work/whole.png" >"$work/seq/frame_0002.png"
"$ds" "${seq[@]}" -o "$work/seq" --resume >"$work/out.txt"
grep -q "rendered 1 frame(s), skipped 1" "$work/out.txt" || { echo "FAIL resume:"; cat "$work/out.txt"; exit 1; }
cmp "$work/seq/frame_0002.png" "$work/whole.png" || { echo "FAIL: the cut frame was not redone"; exit 1; }

# --- scene: values it used to replace by its defaults, limits, a folder of other frames ---
for fx in -5 0 nan inf; do
  code "scene --fx $fx" 2 "--fx" "$ds" scene --out "$work/s" --fx "$fx"
done
code "scene --cx nan" 2 "--cx" "$ds" scene --out "$work/s" --cx nan
code "scene --width 10000" 2 "--width" "$ds" scene --out "$work/s" --width 10000 --height 10000
code "scene --frames 100000000" 2 "--frames" "$ds" scene --out "$work/s" --frames 100000000
code "scene --out a folder of other frames" 4 "holds the frames of another camera" \
  "$ds" scene --out "$work/big" --frames 1 --camera "$work/cam.yaml"
code "scene --out with frames beyond this flight" 4 "numbered beyond" \
  "$ds" scene --out "$work/in" --frames 1 --camera "$work/cam.yaml"
expect_absent "$work/s"

# --- threads ---
code "--threads 1000000" 2 "--threads" "$ds" "${one[@]}" -o "$work/res.png" --threads 1000000
"$ds" "${one[@]}" -o "$work/t.png" --threads 64 >/dev/null 2>"$work/err.txt"
[[ ! -s $work/err.txt ]] || { echo "FAIL: --threads 64 printed:"; cat "$work/err.txt"; exit 1; }

expect_absent "$work"/res.*
if ls -a "$work" "$work/in" | grep -q '\.tmp-'; then echo "FAIL: temporary left"; exit 1; fi
unchanged "the end"
echo "$cases passed, 0 failed"
