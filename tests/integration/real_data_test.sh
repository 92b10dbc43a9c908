#!/usr/bin/env bash
# The authors' real RGB-D sequence (../shared/data/rgbd/seafloor-descent): convert their
# renderer's config with import-config, bake, render all 8 frames, check the layers.
# Skipped (exit 77) where ../shared is absent, as in a user's clone.
set -euo pipefail
deepsea=$1 work=$2 src=$3
data="$src/../shared/data/rgbd/seafloor-descent"
if [[ ! -f "$data/deepsearenderer_config.yaml" ]]; then
  echo "SKIP: ../shared absent ($data)"
  exit 77
fi
rm -rf "$work"; mkdir -p "$work"
"$deepsea" import-config "$data/deepsearenderer_config.yaml" -o "$work/authors.yaml"
"$deepsea" bake --config "$work/authors.yaml" -o "$work/authors.vdb"
"$deepsea" render --asset "$work/authors.vdb" --rgb "$data/frame_????.png" \
  --depth "$data/frame_????_depth.exr" -o "$work/frames" --layers "$work/layers"
n=$(ls "$work"/frames/frame_????.png | wc -l)
[[ $n -eq 8 ]] || { echo "expected 8 frames, got $n"; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
work = sys.argv[1]
for f in ("frame_0001", "frame_0005"):
    buf = oiio.ImageBuf(f"{work}/layers/{f}.exr")
    names = list(buf.spec().channelnames)
    px = buf.get_pixels(oiio.FLOAT)
    layer = lambda l: px[:, :, [names.index(f"{l}.{c}") for c in "RGB"]]
    d, b, fin = layer("direct"), layer("backscatter"), layer("final")
    assert np.isfinite(fin).all(), "non-finite pixels"
    c = slice(300, 500)
    # lamps light the seafloor in the centre; red is attenuated most over ~3 m
    assert d[c, c].mean() > 0, "no direct signal"
    assert d[c, c, 0].mean() < d[c, c, 1].mean(), "red should be darker than green"
    assert (b > 0).all(), "backscatter must be positive everywhere"
    depth = px[:, :, names.index("depth.Z")]
    assert 2.5 < np.median(depth) < 3.5, np.median(depth)
    print(f"{f}: direct centre {d[c, c].mean(axis=(0, 1))}, backscatter mean {b.mean(axis=(0, 1))}")
PY
echo "real data: OK"
