#!/usr/bin/env bash
# deepsea reference --scattering multiple (docs/reference.md) at CI size: order 1 equals the
# exact reference, the standard-error layers are written, all orders add light, and too much
# work or a depth map that is not a plane is refused with one line and nothing written.
set -euo pipefail
deepsea=$1 work=$2 src=$3
source "$src/tests/integration/cli_lib.sh"
py=/usr/bin/python3
if ! $py -c 'import numpy, OpenImageIO' 2>/dev/null; then
  echo "SKIP: $py with numpy and OpenImageIO is absent"; exit 77
fi
rm -rf "$work"; mkdir -p "$work"
cat >"$work/setup.yaml" <<YAML
camera: {width: 16, height: 12, fx: 12.67, fy: 12.67, cx: 7.5, cy: 5.5}
rig:
  name: two
  lights:
    - {position: [-0.5, 0, 0], direction: [0.51, 0, 0.86], intensity: [1, 0.9, 0.8]}
    - {position: [0.5, 0, 0], direction: [-0.51, 0, 0.86], intensity: [0.8, 0.9, 1]}
water:
  name: turbid
  attenuation: [1.0, 0.95, 1.05]
  scattering: [0.8, 0.78, 0.82]
  phase: {henyey_greenstein: {g: 0.85}}
YAML
$py - "$work" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
w = sys.argv[1]
def write(path, a):
    out = oiio.ImageOutput.create(path)
    out.open(path, oiio.ImageSpec(a.shape[1], a.shape[0], a.shape[2], oiio.FLOAT))
    out.write_image(np.ascontiguousarray(a, np.float32)); out.close()
write(f"{w}/albedo.exr", np.tile(np.array([0.7, 0.55, 0.4], np.float32), (12, 16, 1)))
d = np.full((12, 16, 1), 2.0, np.float32)
write(f"{w}/depth.exr", d)
d[5, 7] = 1.5
write(f"{w}/bump.exr", d)
PY
in=(--config "$work/setup.yaml" --rgb "$work/albedo.exr" --depth "$work/depth.exr")
"$deepsea" reference "${in[@]}" --layers "$work/single.exr" >/dev/null
"$deepsea" reference "${in[@]}" --scattering multiple --paths 64 --max-order 1 \
  --layers "$work/order1.exr" >/dev/null
"$deepsea" reference "${in[@]}" --scattering multiple --paths 64 --layers "$work/all.exr" \
  --threads 2 | tee "$work/all.txt"
grep -q "standard error" "$work/all.txt"
$py - "$work" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
w = sys.argv[1]
def layer(path, name):
    b = oiio.ImageBuf(path); n = b.spec().channelnames
    return b.get_pixels(oiio.FLOAT)[:, :, [n.index(f"{name}.{c}") for c in "RGB"]].astype(float)
s, o, a = f"{w}/single.exr", f"{w}/order1.exr", f"{w}/all.exr"
assert np.allclose(layer(o, "direct"), layer(s, "direct"), rtol=1e-6), "order 1: direct"
got, want = layer(o, "backscatter").sum((0, 1)), layer(s, "backscatter").sum((0, 1))
se = np.sqrt((layer(o, "backscatter_se") ** 2).sum((0, 1)))
assert (abs(got - want) <= 4 * se).all(), f"order 1: water light {got} vs {want} +- {se}"
fa, fs = layer(a, "final").sum((0, 1)), layer(s, "final").sum((0, 1))
assert (fa > 1.5 * fs).all(), f"all orders add light in turbid water: {fa} vs {fs}"
assert (layer(a, "final_se") > 0).all() and (layer(a, "forward").sum() > 0)
print(f"ok: order 1 within {np.max(abs(got - want) / se):.2f} SE; all orders / single {fa / fs}")
PY
expect_fail work "$deepsea" reference "${in[@]}" --scattering multiple --paths 100000000 \
  --layers "$work/no.exr"
grep -q "paths x 192 pixels" "$work/err.txt"
expect_fail bump "$deepsea" reference --config "$work/setup.yaml" --rgb "$work/albedo.exr" \
  --depth "$work/bump.exr" --scattering multiple --layers "$work/no.exr"
grep -q "pixel (7, 5) lies" "$work/err.txt"
expect_absent "$work/no.exr"
echo "reference --scattering multiple: OK"
