#!/usr/bin/env bash
# deepsea render with a camera stage (docs/camera.md, "In a render"): --camera's lens, sensor
# and processing record each frame; the image is the camera's display values; --layers holds
# its layers; outputs carry their exposure; the noise is keyed by the colour file's stem; the
# auto-exposure controller's journal lets --resume continue it with the same bits; bad settings
# get one line and leave nothing.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
cam=$src/volumes/cameras/small-320.yaml
"$ds" scene --out "$work/in" --frames 6 --camera "$cam" >/dev/null
rm "$work/in/camera.yaml"
"$ds" bake --camera "$cam" --rig "$src/volumes/rigs/authors-testset.yaml" --water jerlov:IB \
  --xy-step 16 --depth-samples 16 -o "$work/a.vdb" >/dev/null
render() { "$ds" render --asset "$work/a.vdb" "$@"; }
rgb=$work/in/'*.png' depth=$work/in/'*_depth.exr'
f1=$work/in/frame_0001.png d1=$work/in/frame_0001_depth.exr
# camera_yaml EXTRA...: small-320's pinhole plus the given camera-stage lines.
camera_yaml() {
  grep -v '^#' "$cam"
  printf '%s\n' "$@"
}
camera_yaml "  sensor: {preset: mvbluefox3-2051c, exposure_time_ms: 25, iso: 400}" >"$work/cam.yaml"
camera_yaml "  sensor: {preset: mvbluefox3-2051c, exposure_time_ms: 25, iso: 400, noise: false}" \
  "  processing: {curve: linear}" >"$work/clean.yaml"
camera_yaml "  sensor: {preset: mvbluefox3-2051c, exposure_time_ms: 0.5}" \
  "  auto_exposure: {target: 0.4, damping: 0.5}" >"$work/ae.yaml"

# 1. One frame: the image, the camera's layers, the metadata (no exposure factor).
render --rgb "$f1" --depth "$d1" --camera "$work/clean.yaml" -o "$work/one.png" \
  --layers "$work/one.exr" --layer-set final,raw,linear_dn,noise_free >/dev/null
/usr/bin/python3 - "$work" <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio
w = sys.argv[1]
png = oiio.ImageBuf(w + "/one.png")
spec = png.spec()
assert spec.getattribute("deepsea:exposure") is None, "a camera's image has no factor"
assert float(spec.getattribute("deepsea:exposure_time_ms")) == 25.0
assert float(spec.getattribute("deepsea:system_gain")) > 0
assert spec.getattribute("deepsea:white_balance") == "1 1 1"
assert len(spec.getattribute("deepsea:frame_key")) == 16
codes = png.get_pixels(oiio.UINT8).astype(np.int32)
exr = oiio.ImageBuf(w + "/one.exr")
names = list(exr.spec().channelnames)
for layer in ("final", "raw", "linear_dn", "noise_free"):
    assert layer + ".R" in names, names
px = exr.get_pixels(oiio.FLOAT)
def layer(n):
    i = names.index(n + ".R")
    return px[:, :, i:i + 3]
raw, noise_free = layer("raw"), layer("noise_free")
assert np.all(raw == np.round(raw)), "raw DN are whole numbers"
assert raw.max() <= 4095 and raw.min() >= 0
# Noise off, linear curve: the image's codes are the noise-free display values, quantised
# once (the DN quantisation moves a code by at most one).
diff = np.abs(codes - np.round(noise_free * 255))
assert diff.max() <= 1, diff.max()
assert codes.mean() > 5, codes.mean()
print("ok one frame: layers, metadata, image = noise-free display values within 1 code")
PY

# 2. The noise is keyed by the colour file's stem: a frame alone equals the same frame in a
# sequence; the same pixels under another name get other noise.
render --rgb "$rgb" --depth "$depth" --camera "$work/cam.yaml" -o "$work/seq" >/dev/null
render --rgb "$f1" --depth "$d1" --camera "$work/cam.yaml" -o "$work/alone.png" >/dev/null
cmp "$work/alone.png" "$work/seq/frame_0001.png"
grep -q '"mode": "camera"' "$work/seq/deepsea-sequence.json"
mkdir "$work/renamed"
cp "$f1" "$work/renamed/other.png"; cp "$d1" "$work/renamed/other_depth.exr"
render --rgb "$work/renamed/other.png" --depth "$work/renamed/other_depth.exr" \
  --camera "$work/cam.yaml" -o "$work/other.png" >/dev/null
if cmp -s "$work/other.png" "$work/alone.png"; then echo "FAIL: same noise under another name"; exit 1; fi
echo "ok noise keyed by the frame's stem"

# 3. The auto-exposure controller: its settings change from frame to frame within its
# limits, recorded per output and in the journal; --resume continues it with the same bits
# after frames were lost, and after a journal line was lost.
render --rgb "$rgb" --depth "$depth" --camera "$work/ae.yaml" -o "$work/ae_ref" >/dev/null
test "$(wc -l <"$work/ae_ref/deepsea-exposures.jsonl")" -eq 6
render --rgb "$rgb" --depth "$depth" --camera "$work/ae.yaml" -o "$work/ae" >/dev/null
rm "$work/ae/frame_0003.png" "$work/ae/frame_0006.png"
grep -v frame_0004 "$work/ae/deepsea-exposures.jsonl" >"$work/j" && mv "$work/j" "$work/ae/deepsea-exposures.jsonl"
render --rgb "$rgb" --depth "$depth" --camera "$work/ae.yaml" -o "$work/ae" --resume >"$work/out.txt"
grep -q "rendered 3 frame(s), skipped 3" "$work/out.txt"
for i in 1 2 3 4 5 6; do cmp "$work/ae/frame_000$i.png" "$work/ae_ref/frame_000$i.png"; done
/usr/bin/python3 - "$work" <<'PY'
import sys
import OpenImageIO as oiio
w = sys.argv[1]
t = [float(oiio.ImageBuf(f"{w}/ae_ref/frame_000{i}.png").spec().getattribute(
    "deepsea:exposure_time_ms")) for i in range(1, 7)]
assert t[0] == 0.5, t
assert len(set(t)) > 2, f"the controller did not move: {t}"
assert all(0.01 <= x <= 30.0 for x in t), t
print("ok auto exposure times", ["%.3g" % x for x in t])
PY
echo "ok --resume continues the controller with the same bits"

# 4. Refusals: one line, nothing written.
expect_fail "--exposure with a camera stage" render --rgb "$f1" --depth "$d1" \
  --camera "$work/cam.yaml" --exposure 2 -o "$work/x1.png"
grep -q "exposure_time_ms" "$work/err.txt"
expect_fail "a camera layer without a camera stage" render --rgb "$f1" --depth "$d1" \
  --layers "$work/x2.exr" --layer-set final,raw
grep -q "camera stage" "$work/err.txt"
camera_yaml "  lens: {f_number: 0}" >"$work/bad.yaml"
expect_fail "f-number 0" render --rgb "$f1" --depth "$d1" --camera "$work/bad.yaml" -o "$work/x3.png"
grep -q "bad.yaml:.*camera.lens.f_number" "$work/err.txt"
camera_yaml "  lens: {distortion: {k1: -3}}" >"$work/fold.yaml"
expect_fail "a lens that folds the image" render --rgb "$f1" --depth "$d1" \
  --camera "$work/fold.yaml" -o "$work/x4.png"
camera_yaml "  sensor: {preset: mvbluefox3-2051c, exposure_time_ms: 30, iso: 400}" >"$work/cam2.yaml"
expect_fail "resume with another camera" render --rgb "$rgb" --depth "$depth" \
  --camera "$work/cam2.yaml" -o "$work/seq" --resume
grep -q "cannot resume: the camera stage" "$work/err.txt"
expect_absent "$work/x1.png" "$work/x2.exr" "$work/x3.png" "$work/x4.png"
echo "ok refusals"
