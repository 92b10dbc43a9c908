#!/usr/bin/env bash
# Makes the fuzzers' seed corpus (docs/fuzzing.md) from the project itself: configs from
# volumes/, tiny assets baked by the deepsea binary, tiny images and depth maps rendered by
# `deepsea scene` and converted with oiiotool and python3. Nothing generated is committed.
#   scripts/fuzz-corpus.sh DEEPSEA_BINARY OUT_DIR
# OUT_DIR gets config/, asset/, depth/ and image/ (one folder per fuzz target; the sealed asset
# target uses asset/ too).
set -euo pipefail
ds=$(realpath "$1") out=$2
src=$(cd "$(dirname "$0")/.." && pwd)
v=$src/volumes
rm -rf "$out"
mkdir -p "$out"/{config,asset,depth,image,paths,work}
w=$out/work

# config: every YAML file under volumes/, and whole setups (camera + rig + water in one file),
# which parse_setup reads as one document.
for f in "$v"/*.yaml "$v"/*/*.yaml; do
  cp "$f" "$out/config/$(basename "$(dirname "$f")")-$(basename "$f")"
done
n=0
for c in "$v"/cameras/*.yaml; do
  for r in "$v"/rigs/*.yaml; do
    for water in "$v"/waters/jerlov-IB.yaml "$v"/waters/deep-clear.yaml; do
      cat "$c" "$r" "$water" > "$out/config/setup-$n.yaml"
      n=$((n + 1))
    done
  done
done

# a tiny camera for the assets and images
cat > "$w/cam.yaml" <<'YAML'
camera: {width: 16, height: 12, fx: 12.0, fy: 12.0, cx: 7.5, cy: 5.5}
YAML
rig=$v/rigs/single-down.yaml
tiny=(--camera "$w/cam.yaml" --rig "$rig" --water jerlov:IB --xy-step 8 --depth-samples 4 --no-check)
"$ds" bake "${tiny[@]}" --no-preview -o "$out/asset/tiny.vdb" >/dev/null
"$ds" bake "${tiny[@]}" --no-preview --full-float --depth-scheme sqrt -o "$out/asset/float-sqrt.vdb" >/dev/null
# (No preview grids and no multiple-scattering lamp tables: those files are 0.2-5 MB, and
# every execution hashes and parses the whole input.)

# images: one frame of the procedural seafloor (8-bit PNG colour, float EXR depth), then the
# same pixels in the other formats the readers take.
"$ds" scene --out "$w/f" --frames 1 --camera "$w/cam.yaml" >/dev/null
rgb=$w/f/frame_0001.png depth=$w/f/frame_0001_depth.exr
cp "$rgb" "$out/image/frame.png"
oiiotool "$rgb" -d uint16 -o "$out/image/frame16.png"
oiiotool "$rgb" -o "$out/image/frame.jpg"
oiiotool "$rgb" -d uint8 -o "$out/image/frame.tif"
oiiotool "$rgb" -d half -o "$out/image/frame.exr"
oiiotool "$rgb" -d float -o "$out/image/frame.hdr"
oiiotool "$rgb" -ch R -o "$out/image/grey.png"
cp "$depth" "$out/depth/depth.exr"
oiiotool "$depth" -d uint16 -o "$out/depth/depth16.png"
oiiotool "$depth" -d float -o "$out/depth/depth.tif"
/usr/bin/python3 - "$depth" "$out" <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio
depth = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[:, :, 0]
out = sys.argv[2]
np.save(f"{out}/depth/depth-f4.npy", depth.astype("<f4"))
np.save(f"{out}/depth/depth-f8.npy", depth.astype("<f8"))
np.save(f"{out}/depth/depth-u2.npy", (depth * 1000).astype("<u2"))
np.save(f"{out}/depth/depth-fortran.npy", np.asfortranarray(depth.astype("<f4")))
np.save(f"{out}/depth/depth-hw1.npy", depth.astype("<f4")[:, :, None])
def pfm(path, a, little=True):
    h, w = a.shape[:2]
    kind = b"PF" if a.ndim == 3 else b"Pf"
    with open(path, "wb") as f:
        f.write(kind + b"\n%d %d\n%s\n" % (w, h, b"-1.0" if little else b"1.0"))
        f.write(np.flipud(a).astype("<f4" if little else ">f4").tobytes())
pfm(f"{out}/depth/depth.pfm", depth)
pfm(f"{out}/depth/depth-be.pfm", depth, little=False)
pfm(f"{out}/image/colour.pfm", np.stack([depth, depth * 0.5, depth * 0.25], axis=2))
PY
# paths (fuzz_paths.cpp): a sequence bit, a count and component indices for -o, then the same
# for --layers: in/nosuch/.., out, link-in/a/.., in/nosuch/../frame_0001.png, out/link-frame
i=0
for seed in '\x01\x02\x00\x04\x02\x00' '\x01\x00\x01\x00' '\x01\x02\x06\x05\x02\x00' \
            '\x00\x03\x00\x04\x02\x09\x00' '\x00\x01\x01\x08\x00' '\x01\x00\x01\x01\x00\x01'; do
  printf "$seed" >"$out/paths/seed-$i"; i=$((i + 1))
done
rm -rf "$w"
for d in "$out"/*/; do echo "$(basename "$d"): $(ls "$d" | wc -l) seeds, $(du -sk "$d" | cut -f1) KB"; done
