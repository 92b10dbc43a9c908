#!/usr/bin/env bash
# Impossible ports, end to end (docs/ports.md, "Impossible ports"): bake, render and reference
# each refuse in one line naming the key, exit 2, nothing written: glass thickness <= 0,
# the camera outside a dome, indices <= 0, total internal reflection over part of the view, and a
# port through which no pixel sees the input (refused before any frame is read).
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
cam=$src/volumes/cameras/small-320.yaml
rig=$src/volumes/rigs/authors-testset.yaml
"$ds" scene --out "$work/in" --frames 1 --camera "$cam" >/dev/null
"$ds" bake --camera "$cam" --rig "$rig" --water jerlov:IB --xy-step 16 --depth-samples 16 \
  -o "$work/a.vdb" >/dev/null
rgb=$work/in/frame_0001.png depth=$work/in/frame_0001_depth.exr

# refuse NAME CMD...: CMD exits 2 (a configuration error) with one line on stderr.
refuse() {
  local name=$1; shift
  set +e
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$?
  set -e
  if [[ $rc -ne 2 || $(wc -l <"$work/err.txt") -ne 1 ]]; then
    echo "FAIL $name: exit $rc, stderr:"; cat "$work/err.txt"; exit 1
  fi
  echo "ok $name: $(cat "$work/err.txt")"
}

# case NAME KEY PORT: small-320's pinhole with PORT; each command must refuse it naming KEY.
case_() {
  local name=$1 key=$2 port=$3
  { grep -v '^#' "$cam"; printf '  port: %s\n' "$port"; } >"$work/$name.yaml"
  local c
  for c in bake render reference; do
    case $c in
      bake) refuse "$name-bake" "$ds" bake --camera "$work/$name.yaml" --rig "$rig" \
              --water jerlov:IB --xy-step 16 --depth-samples 16 -o "$work/out.vdb" ;;
      render) refuse "$name-render" "$ds" render --asset "$work/a.vdb" --rgb "$rgb" \
                --depth "$depth" --camera "$work/$name.yaml" -o "$work/out.png" ;;
      reference) refuse "$name-reference" "$ds" reference --camera "$work/$name.yaml" \
                   --rig "$rig" --water jerlov:IB --rgb "$rgb" --depth "$depth" \
                   -o "$work/ref.png" ;;
    esac
    grep -qF "$key" "$work/err.txt" || { echo "FAIL $name-$c: no '$key'"; exit 1; }
    expect_absent "$work/out.vdb" "$work/out.png" "$work/ref.png"
  done
}

case_ glass-zero camera.port.flat.glass_thickness \
  "{flat: {normal: [0, 0, 1], distance: 0.03, glass_thickness: 0}}"
case_ glass-negative camera.port.dome.glass_thickness \
  "{dome: {centre: [0, 0, 0], radius: 0.05, glass_thickness: -0.01}}"
case_ outside-dome camera.port.dome.centre \
  "{dome: {centre: [0, 0, 0.06], radius: 0.05, glass_thickness: 0.01}}"
case_ n-air-zero camera.port.flat.n_air \
  "{flat: {normal: [0, 0, 1], distance: 0.03, glass_thickness: 0.01, n_air: 0}}"
case_ n-glass-negative camera.port.dome.n_glass \
  "{dome: {centre: [0, 0, 0], radius: 0.05, glass_thickness: 0.01, n_glass: -1.5}}"
case_ n-water-channel camera.port.flat.n_water \
  "{flat: {normal: [0, 0, 1], distance: 0.03, glass_thickness: 0.01, n_water: [1.34, 0, 1.34]}}"
# n_water 0.5 < n_air: rays beyond 30 degrees from the normal are reflected at the outer surface
case_ partial-reflection camera.port.flat.n_water \
  "{flat: {normal: [0, 0, 1], distance: 0.03, glass_thickness: 0.01, n_water: 0.5}}"
grep -q "total internal reflection at the outer surface" "$work/err.txt"
# 80 degrees off the axis: the water-side rays look beside the input's 67-degree view
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
refuse blind-render "$ds" render --asset "$work/a.vdb" --rgb "$rgb" --depth "$depth" \
  --camera "$work/blind.yaml" -o "$work/out.png"
grep -q "camera.port: no pixel's water-side ray sees" "$work/err.txt"
# the reference refuses it before reading the frame: a missing one is not reported
refuse blind-reference "$ds" reference --camera "$work/blind.yaml" --rig "$rig" \
  --water jerlov:IB --rgb "$work/missing.png" --depth "$work/missing.exr" -o "$work/ref.png"
grep -q "camera.port: no pixel's water-side ray sees" "$work/err.txt"
expect_absent "$work/out.png" "$work/ref.png"
echo "port_bad_input_test: all ok"
