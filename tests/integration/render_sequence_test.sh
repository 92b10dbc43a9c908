#!/usr/bin/env bash
# deepsea render on sequences (docs/sequences.md): frames pair by name or number, outputs are
# checked before any work, the manifest keeps the exposure for --resume and refuses other
# settings, outputs carry their exposure and asset hash, a locked folder is refused. Every
# refusal: one line on stderr, a non-zero exit, no output left behind.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
cam=$src/volumes/cameras/small-320.yaml
"$ds" scene --out "$work/in" --frames 3 --camera "$cam" >/dev/null
rm "$work/in/camera.yaml"
"$ds" bake --camera "$cam" --rig "$src/volumes/rigs/authors-testset.yaml" --water jerlov:IB \
  --xy-step 16 --depth-samples 16 -o "$work/a.vdb" >/dev/null
"$ds" bake --camera "$cam" --rig "$src/volumes/rigs/single-down.yaml" --water jerlov:IB \
  --xy-step 16 --depth-samples 16 -o "$work/b.vdb" >/dev/null
render() { "$ds" render --asset "$work/a.vdb" "$@"; }
rgb=$work/in/'*.png' depth=$work/in/'*_depth.exr'

# 1. Pairing by frame identity. One depth file missing: an error listing the lone colour
# file, before anything is rendered (formerly frame 2 got frame 3's depth, exit 0).
mkdir "$work/gap"
cp "$work/in/frame_0001.png" "$work/in/frame_0002.png" "$work/in/frame_0003.png" "$work/gap/"
cp "$work/in/frame_0001_depth.exr" "$work/in/frame_0003_depth.exr" "$work/gap/"
expect_fail "depth missing" render --rgb "$work/gap/*.png" --depth "$work/gap/*_depth.exr" \
  -o "$work/gap_out"
grep -q "unpaired frames.*1 colour file(s) without depth.*gap/frame_0002.png" "$work/err.txt"
expect_absent "$work/gap_out"
cp "$work/in/frame_0002_depth.exr" "$work/gap/frame_0009_depth.exr"
expect_fail "depth of another frame" render --rgb "$work/gap/*.png" \
  --depth "$work/gap/*_depth.exr" -o "$work/gap_out"
grep -q "frame_0002.png.*depth file(s) without colour.*frame_0009_depth.exr" "$work/err.txt"
expect_absent "$work/gap_out"
# Names that differ but numbers that match pair by number (rgb/0001.png, depth/d_1.exr).
mkdir "$work/num" "$work/num/rgb" "$work/num/depth"
for i in 1 2 3; do
  cp "$work/in/frame_000$i.png" "$work/num/rgb/000$i.png"
  cp "$work/in/frame_000$i""_depth.exr" "$work/num/depth/d_$i.exr"
done
render --rgb "$work/num/rgb/*.png" --depth "$work/num/depth/*.exr" -o "$work/num/out" \
  --exposure 100 >/dev/null
render --rgb "$rgb" --depth "$depth" -o "$work/ref" --exposure 100 >/dev/null
for i in 1 2 3; do cmp "$work/num/out/000$i.png" "$work/ref/frame_000$i.png"; done
# Two input folders with the same frame names into one output: refused.
mkdir -p "$work/two/a" "$work/two/b"
for d in a b; do cp "$work/in/frame_0001.png" "$work/in/frame_0001_depth.exr" "$work/two/$d/"; done
expect_fail "same frame names from two folders" render --rgb "$work/two/*/*.png" \
  --depth "$work/two/*/*_depth.exr" -o "$work/two_out"
grep -q "are both frame" "$work/err.txt"
expect_absent "$work/two_out"

# 3. Outputs checked before work; outputs never overwrite inputs.
f1=$work/in/frame_0001.png d1=$work/in/frame_0001_depth.exr
sum_before=$(cat "$work"/in/* | md5sum)
expect_fail "-o is the colour input" render --rgb "$f1" --depth "$d1" -o "$f1"
expect_fail "--layers is the depth input" render --rgb "$f1" --depth "$d1" --layers "$d1"
expect_fail "-o and --layers the same file" render --rgb "$f1" --depth "$d1" \
  -o "$work/x.exr" --layers "$work/x.exr"
expect_fail "sequence into its input folder" render --rgb "$rgb" --depth "$depth" -o "$work/in"
grep -q "folder of the input" "$work/err.txt"
expect_fail "layers into the input folder" render --rgb "$rgb" --depth "$depth" \
  --layers "$work/in/"
[[ $(cat "$work"/in/* | md5sum) == "$sum_before" ]] || { echo "FAIL: an input changed"; exit 1; }
expect_fail "unknown extension" render --rgb "$f1" --depth "$d1" -o "$work/x.xyz"
grep -q "x.xyz" "$work/err.txt"
expect_fail "no extension" render --rgb "$f1" --depth "$d1" -o "$work/noext"
expect_fail "layers not EXR" render --rgb "$f1" --depth "$d1" --layers "$work/l.png"
expect_fail "missing output folder" render --rgb "$f1" --depth "$d1" -o "$work/nodir/x.png"
grep -q "nodir" "$work/err.txt"
expect_fail "sequence -o is an image name" render --rgb "$rgb" --depth "$depth" \
  -o "$work/seq.png"
expect_fail "sequence -o is a file" render --rgb "$rgb" --depth "$depth" -o "$work/a.vdb"
expect_fail "sequence folder under a file" render --rgb "$rgb" --depth "$depth" \
  -o "$f1/seq"
# A bad asset is found before any folder is made.
expect_fail "missing asset" "$ds" render --asset "$work/none.vdb" --rgb "$rgb" \
  --depth "$depth" -o "$work/noasset"
expect_absent "$work/x.xyz" "$work/noext" "$work/l.png" "$work/nodir" "$work/x.exr" \
  "$work/seq.png" "$f1/seq" "$work/noasset"
[[ $(find "$work/in" -type f | wc -l) -eq 6 ]] || { echo "FAIL: files appeared in in/"; exit 1; }

# 2. The manifest: written atomically beside the frames; outputs carry exposure and hash.
render --rgb "$rgb" --depth "$depth" -o "$work/seq" --layers "$work/lay" \
  | grep -q "rendered 3 frame(s), skipped 0, failed 0"
m=$work/seq/deepsea-sequence.json
/usr/bin/python3 - "$m" "$work/seq/frame_0002.png" "$work/lay/frame_0002.exr" <<'PY'
import json, sys
import OpenImageIO as oiio
m = json.load(open(sys.argv[1]))
assert m["format"] == 1 and m["frames"] == {"total": 3, "done": 3}, m
assert m["asset_hash"].startswith("fnv1a64:") and m["exposure"]["mode"] == "auto", m
assert m["exposure"]["factor"] > 0 and m["exposure"]["chosen_on"].endswith("frame_0001.png")
assert m["outputs"] == {"image": "png", "bits": 8, "layers": "all", "half": False}, m
assert m["camera"]["width"] == 320 and m["deepsea_version"], m
for f in sys.argv[2:]:
    spec = oiio.ImageInput.open(f).spec()
    assert float(spec.getattribute("deepsea:exposure")) == m["exposure"]["factor"], f
    assert spec.getattribute("deepsea:asset_hash") == m["asset_hash"], f
PY
cmp "$m" "$work/lay/deepsea-sequence.json"
# The whole manifest, byte for byte, as a write after every frame made it (the manifests are
# written from a thread of their own; the last write must still count every frame): every
# key's value, nlohmann's layout (sorted keys, two-space indent, doubles as Python's repr).
/usr/bin/python3 - "$m" "$work/seq/frame_0001.png" "$work/in" <<'PY'
import json, sys
import OpenImageIO as oiio
path, png, inputs = sys.argv[1:]
spec = oiio.ImageInput.open(png).spec()
expected = {
    "asset_hash": spec.getattribute("deepsea:asset_hash"),
    "camera": {"cx": 159.5, "cy": 119.5, "fx": 240.0, "fy": 240.0, "height": 240, "width": 320},
    "camera_stage": "none",
    "deepsea_version": spec.getattribute("deepsea:version"),
    "exposure": {"chosen_on": inputs + "/frame_0001.png",
                 "factor": float(spec.getattribute("deepsea:exposure")),
                 "max_clipped": 0.005, "mode": "auto", "percentile": 0.995, "target": 0.85},
    "format": 1,
    "frames": {"done": 3, "total": 3},
    "inputs": {"depth": inputs + "/*_depth.exr", "rgb": inputs + "/*.png"},
    "outputs": {"bits": 8, "half": False, "image": "png", "layers": "all"},
    "port": "none",
    "settings": {"depth_channel": "", "depth_kind": "z", "depth_scale": 0.001, "forward": True},
}
text = open(path).read()
want = json.dumps(expected, indent=2, sort_keys=True) + "\n"
assert text == want, "manifest differs:\n" + text + "\nexpected:\n" + want
PY
[[ -z $(find "$work/seq" "$work/lay" -name '.*') ]] || { echo "FAIL: hidden files left"; exit 1; }
# --resume: exact counts; a 0-byte image, a cut layer file and a missing one are redone,
# with the exposure of the manifest.
cp -r "$work/seq" "$work/seq_full"
: > "$work/seq/frame_0002.png"
head -c 4000 "$work/lay/frame_0003.exr" > "$work/cut.exr"; mv "$work/cut.exr" "$work/lay/frame_0003.exr"
render --rgb "$rgb" --depth "$depth" -o "$work/seq" --layers "$work/lay" --resume \
  | grep -q "rendered 2 frame(s), skipped 1, failed 0"
for f in "$work"/seq_full/*.png; do cmp "$f" "$work/seq/$(basename "$f")"; done
# A resumed sequence whose first frames are done keeps the manifest's exposure although the
# first frame it composites is another one (formerly re-chosen: +8 %, flicker).
rm "$work/seq/frame_0003.png"
render --rgb "$rgb" --depth "$depth" -o "$work/seq" --layers "$work/lay" --resume \
  | grep -q "rendered 1 frame(s), skipped 2, failed 0"
cmp "$work/seq_full/frame_0003.png" "$work/seq/frame_0003.png"
/usr/bin/python3 -c "import json,sys; assert json.load(open(sys.argv[1]))['frames']['done'] == 3" "$m"
# Another asset, other settings, other inputs: refused with one line, nothing changed.
sum_seq=$(cat "$work"/seq/* "$work"/lay/* | md5sum)
expect_fail "resume with another asset" "$ds" render --asset "$work/b.vdb" --rgb "$rgb" \
  --depth "$depth" -o "$work/seq" --layers "$work/lay" --resume
grep -q "deepsea-sequence.json: cannot resume: the asset was fnv1a64:" "$work/err.txt"
expect_fail "resume with another exposure" render --rgb "$rgb" --depth "$depth" \
  -o "$work/seq" --layers "$work/lay" --resume --exposure 3
expect_fail "resume without layers" render --rgb "$rgb" --depth "$depth" -o "$work/seq" --resume
expect_fail "resume with 16 bits" render --rgb "$rgb" --depth "$depth" -o "$work/seq" \
  --layers "$work/lay" --resume --bits 16
expect_fail "another sequence into this folder" render --rgb "$work/num/rgb/*.png" \
  --depth "$work/num/depth/*.exr" -o "$work/seq"
grep -q "holds the frames of" "$work/err.txt"
[[ $(cat "$work"/seq/* "$work"/lay/* | md5sum) == "$sum_seq" ]] || { echo "FAIL: outputs changed"; exit 1; }
# --shadow-step: a bad value is one line naming it, before any work; a sequence swept at one
# step refuses --resume at another.
for bad in 0 9 two; do
  expect_fail "--shadow-step $bad" render --rgb "$rgb" --depth "$depth" -o "$work/st" --shadows \
    --shadow-step "$bad"
  grep -q -- "--shadow-step" "$work/err.txt"
done
expect_fail "--shadow-step without --shadows" render --rgb "$rgb" --depth "$depth" -o "$work/st" \
  --shadow-step 3
expect_absent "$work/st"
render --rgb "$rgb" --depth "$depth" -o "$work/st" --shadows --shadow-step 3 >/dev/null
expect_fail "resume at another shadow step" render --rgb "$rgb" --depth "$depth" -o "$work/st" \
  --shadows --resume
grep -q -- "--shadow-step was 3, now 2" "$work/err.txt"
# Frames without a manifest cannot be resumed (their exposure is unknown).
mkdir "$work/old"; cp "$work/seq_full/frame_0001.png" "$work/old/"
expect_fail "resume without a manifest" render --rgb "$rgb" --depth "$depth" -o "$work/old" --resume
[[ $(ls -A "$work/old") == frame_0001.png ]] || { echo "FAIL: old/ changed"; exit 1; }

# --format: a JPEG sequence, the same frames as the PNG one up to JPEG's loss; recorded in the
# manifest and kept on --resume; 16 bits refused for JPEG; -o's extension must match it.
render --rgb "$rgb" --depth "$depth" -o "$work/jpg" --format jpg --exposure 100 \
  | grep -q "rendered 3 frame(s), skipped 0, failed 0"
[[ $(cd "$work/jpg" && echo *.jpg) == "frame_0001.jpg frame_0002.jpg frame_0003.jpg" ]] ||
  { echo "FAIL: JPEG sequence names"; ls "$work/jpg"; exit 1; }
/usr/bin/python3 - "$work/jpg" "$work/ref" <<'PY'
import json, sys
import numpy as np
import OpenImageIO as oiio
jpg, png = sys.argv[1:]
assert json.load(open(jpg + "/deepsea-sequence.json"))["outputs"]["image"] == "jpg"
for i in (1, 2, 3):
    a = oiio.ImageBuf(f"{jpg}/frame_000{i}.jpg").get_pixels(oiio.FLOAT) * 255
    b = oiio.ImageBuf(f"{png}/frame_000{i}.png").get_pixels(oiio.FLOAT) * 255
    assert a.shape == b.shape and np.abs(a - b).mean() < 2.0, (i, np.abs(a - b).mean())
PY
rm "$work/jpg/frame_0002.jpg"
render --rgb "$rgb" --depth "$depth" -o "$work/jpg" --format jpg --exposure 100 --resume \
  | grep -q "rendered 1 frame(s), skipped 2, failed 0"
expect_fail "resume as PNG" render --rgb "$rgb" --depth "$depth" -o "$work/jpg" \
  --exposure 100 --resume
grep -q "cannot resume: --format was jpg, now png" "$work/err.txt"
expect_fail "16-bit JPEG" render --rgb "$rgb" --depth "$depth" -o "$work/jpg16" --format jpg \
  --bits 16
grep -q "JPEG holds 8 bits" "$work/err.txt"
expect_fail "-o x.png --format jpg" render --rgb "$f1" --depth "$d1" -o "$work/x.png" \
  --format jpg
expect_absent "$work/jpg16" "$work/x.png"

# 7. A folder another process writes into is refused (its lock held here with flock(1)).
mkdir "$work/busy"
flock -o "$work/busy/.deepsea.lock" sleep 30 &
holder=$!
for _ in $(seq 50); do [[ -e $work/busy/.deepsea.lock ]] && break; sleep 0.1; done
expect_fail "folder locked" render --rgb "$rgb" --depth "$depth" -o "$work/busy"
grep -q "another deepsea process is writing into this folder" "$work/err.txt"
kill "$holder"; wait "$holder" 2>/dev/null || true
[[ -z $(ls "$work/busy") ]] || { echo "FAIL: frames written into a locked folder"; exit 1; }
render --rgb "$rgb" --depth "$depth" -o "$work/busy" | grep -q "rendered 3 frame(s)"
[[ ! -e $work/busy/.deepsea.lock ]] || { echo "FAIL: lock file left"; exit 1; }
echo "render sequences: OK"
