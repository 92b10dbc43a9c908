#!/usr/bin/env bash
# Regenerates the pictures in docs/ with the project's own commands (needs a build and, for the
# real-data figure, ../shared beside the checkout).
set -euo pipefail
cd "$(dirname "$0")/.."
ds=./build/tools/deepsea/deepsea
work=out/figures
mkdir -p "$work"
"$ds" demo --out "$work/demo"
cp "$work/demo/contact_sheet.png" docs/demo-contact-sheet.png

data=../shared/data/rgbd/seafloor-descent
if [[ -d $data ]]; then
  "$ds" import-config "$data/deepsearenderer_config.yaml" -o "$work/authors.yaml"
  "$ds" bake --config "$work/authors.yaml" -o "$work/authors.vdb"
  "$ds" render --asset "$work/authors.vdb" --rgb "$data/frame_????.png" \
    --depth "$data/frame_????_depth.exr" -o "$work/real" --layers "$work/real-layers"
  /usr/bin/python3 tools/figures/side_by_side.py docs/real-data-comparison.png 400 \
    "$data/frame_0001.png" "$work/real/frame_0001.png" "$data/reference_deepsearenderer_0001.jpg" -- \
    "$data/frame_0005.png" "$work/real/frame_0005.png" "$data/reference_deepsearenderer_0005.jpg"
fi
# single vs all orders vs Cycles, from the Cycles tests' work folders (ctest -R cycles)
cw=build/tests/integration
if [[ -d $cw/cycles_test.work && -d $cw/cycles_all_test.work ]]; then
  /usr/bin/python3 tools/figures/cycles_comparison.py docs/cycles-comparison.png \
    "$cw/cycles_test.work" "$cw/cycles_all_test.work"
fi
echo "figures written to docs/"
