#!/usr/bin/env bash
# deepsea render through a port (docs/ports.md, "Rendering through a port"): --camera whose
# camera section has a port renders along the water-side rays; the layer files gain mask.Y; the
# sequence manifest records the port, and --resume refuses another port or none; a port through
# which no pixel sees the frames is refused before any output.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
cam=$src/volumes/cameras/small-320.yaml
"$ds" scene --out "$work/in" --frames 3 --camera "$cam" >/dev/null
rm "$work/in/camera.yaml"
"$ds" bake --camera "$cam" --rig "$src/volumes/rigs/authors-testset.yaml" --water jerlov:IB \
  --xy-step 16 --depth-samples 16 -o "$work/a.vdb" >/dev/null
render() { "$ds" render --asset "$work/a.vdb" "$@"; }
rgb=$work/in/'*.png' depth=$work/in/'*_depth.exr'
# with_port LINES...: small-320's pinhole plus the given port lines.
with_port() {
  grep -v '^#' "$cam"
  printf '%s\n' "$@"
}
with_port "  port: {flat: {normal: [0, 0, 1], distance: 0.03, glass_thickness: 0.012}}" \
  >"$work/flat.yaml"
with_port "  port: {dome: {centre: [0, 0, 0], radius: 0.05, glass_thickness: 0.01}}" \
  >"$work/dome.yaml"
# 45 degrees off the axis behind a 2-degree camera: every water-side ray looks elsewhere
cat >"$work/blind.yaml" <<'YAML'
camera:
  width: 320
  height: 240
  fx: 5000.0
  fy: 5000.0
  cx: 159.5
  cy: 119.5
  port: {flat: {normal: [1, 0, 1], distance: 0.03, glass_thickness: 0.012}}
YAML

# 1. A sequence through the flat port: the images, the layers with the mask, the manifest.
render --rgb "$rgb" --depth "$depth" --camera "$work/flat.yaml" -o "$work/out" \
  --layers "$work/layers" >/dev/null
/usr/bin/python3 - "$work" <<'PY'
import json, sys
import OpenImageIO as oiio
w = sys.argv[1]
m = json.load(open(w + "/out/deepsea-sequence.json"))
assert "flat:" in m["port"] and "distance: 0.03" in m["port"], m["port"]
buf = oiio.ImageBuf(w + "/layers/frame_0001.exr")
names = buf.spec().channelnames
assert "mask.Y" in names, names
px = buf.get_pixels(oiio.FLOAT)
mask = px[:, :, names.index("mask.Y")]
assert mask.min() >= 0 and mask.max() == 1, (mask.min(), mask.max())
print("ok flat port: manifest records it, mask.Y in the layers (%.3f of the pixels see the input)"
      % mask.mean())
PY

# 2. --resume refuses another port, or none; the same port resumes.
expect_fail resume-other-port render --rgb "$rgb" --depth "$depth" --camera "$work/dome.yaml" \
  -o "$work/out" --layers "$work/layers" --resume
grep -q "cannot resume: the port was one port, now another port" "$work/err.txt"
expect_fail resume-no-port render --rgb "$rgb" --depth "$depth" -o "$work/out" \
  --layers "$work/layers" --resume
grep -q "cannot resume: the port was one port, now none" "$work/err.txt"
render --rgb "$rgb" --depth "$depth" --camera "$work/flat.yaml" -o "$work/out" \
  --layers "$work/layers" --resume | grep -q "skipped 3"
echo "ok resume: the same port skips the frames"

# 3. A port through which no pixel sees the frames: one line, nothing written.
expect_fail blind-port render --rgb "$work/in/frame_0001.png" \
  --depth "$work/in/frame_0001_depth.exr" --camera "$work/blind.yaml" -o "$work/blind.png"
grep -q "camera.port: no pixel's water-side ray sees" "$work/err.txt"
expect_absent "$work/blind.png"
# Lamp shadows work in the input's pinhole pixels: through a port they are refused.
expect_fail shadows-through-a-port render --rgb "$work/in/frame_0001.png" \
  --depth "$work/in/frame_0001_depth.exr" --camera "$work/flat.yaml" --shadows -o "$work/sh.png"
grep -q "lamp shadows through a port are not built yet" "$work/err.txt"
expect_absent "$work/sh.png"

# 4. An asset baked through the flat port (docs/port-bake.md, "Baking through a port"): info prints
# the port and the check along the refracted rays; it renders through that port only.
"$ds" bake --camera "$work/flat.yaml" --rig "$src/volumes/rigs/authors-testset.yaml" \
  --water jerlov:IB --xy-step 16 --depth-samples 16 -o "$work/p.vdb" >/dev/null
"$ds" info "$work/p.vdb" >"$work/info.txt"
grep -q "^port       flat port (normal \[0, 0, 1\], distance 0.03 m, glass 0.012 m" "$work/info.txt"
grep -q "exact integrals along the port's refracted rays" "$work/info.txt"
"$ds" info "$work/a.vdb" | grep -q "^port       none"
"$ds" render --asset "$work/p.vdb" --rgb "$work/in/frame_0001.png" \
  --depth "$work/in/frame_0001_depth.exr" --camera "$work/flat.yaml" -o "$work/p.png" >/dev/null
test -s "$work/p.png"
expect_fail port-asset-without-port "$ds" render --asset "$work/p.vdb" \
  --rgb "$work/in/frame_0001.png" --depth "$work/in/frame_0001_depth.exr" -o "$work/q.png"
grep -q "the asset was baked through a flat port (.*), the frames' camera has no port" \
  "$work/err.txt"
expect_fail port-asset-other-port "$ds" render --asset "$work/p.vdb" \
  --rgb "$work/in/frame_0001.png" --depth "$work/in/frame_0001_depth.exr" \
  --camera "$work/dome.yaml" -o "$work/q.png"
grep -q "the frames' camera looks through a dome port" "$work/err.txt"
expect_absent "$work/q.png"
echo "ok port asset: info prints its port; another port or none refused in one line"
echo "render_port_test: all ok"
