#!/usr/bin/env bash
# Instructions per frame of the camera stage (docs/camera-speed.md): the bench's `camera` case
# under callgrind, at 800x800 and 1920x1080, per frame = (4 frames - 1 frame) / 3.
# Usage: scripts/camera-callgrind.sh [BUILD [SOURCE]] (default: build, this checkout), after
# `deepsea` and the libraries are built there; a few minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:-build}")
src=$(realpath "${2:-.}")
ds=$build/tools/deepsea/deepsea
out=out/camera-callgrind
mkdir -p "$out"
# The demo flight's second frame, rendered to its radiance layers.
if [ ! -f "$out/layers/frame_0002.exr" ]; then
  "$ds" scene --out "$out/in" --frames 2 --camera volumes/demo.yaml > /dev/null
  rm -f "$out/in/camera.yaml"
  "$ds" bake --config volumes/demo.yaml --xy-step 16 --depth-samples 16 -o "$out/a.vdb" \
    > /dev/null 2>&1
  "$ds" render --asset "$out/a.vdb" --rgb "$out/in/*[0-9].png" --depth "$out/in/*_depth.exr" \
    --layers "$out/layers" --layer-set final -q
fi
g++ -std=c++17 -O2 -I"$src/include" -I/usr/include/OpenEXR -I/usr/include/Imath \
  scripts/camera_callgrind.cpp -o "$out/camera_callgrind" \
  "$build/src/camera/libdeepsea_camera.a" "$build/src/optics/libdeepsea_optics.a" \
  "$build/src/core/libdeepsea_core.a" -lOpenEXR -lIex -lImath -ltbb -lpthread
for size in "800 800" "1920 1080"; do
  ir=()
  for n in 1 4; do
    ir+=("$(valgrind --tool=callgrind --callgrind-out-file=/dev/null \
      "$out/camera_callgrind" "$out/layers/frame_0002.exr" $size $n 2>&1 \
      | sed -n 's/.*Collected : //p')")
  done
  echo "${size/ /x}: $(( (ir[1] - ir[0]) / 3 )) instructions per frame"
done
