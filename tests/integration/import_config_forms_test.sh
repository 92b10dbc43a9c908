#!/usr/bin/env bash
# deepsea import-config on the forms the authors' renderer accepts beyond their test set's
# config: the field-of-view intrinsics (one number), H-G phase (their type 4: g = +0.3 in the
# standard convention), their Jerlov II Kd triplet (the II preset). Self-contained.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"

# A horizontal field of view of 1.2 rad: f = 320 / tan(0.6) = 467.7427..., centre (320, 240).
their "[1.2]" "[0.4, 0.071, 0.06]" 4 >"$work/fov.yaml"
"$ds" import-config "$work/fov.yaml" -o "$work/fov-setup.yaml" >/dev/null
grep -q "fx: 467.7427" "$work/fov-setup.yaml"
grep -q "fy: 467.7427" "$work/fov-setup.yaml"
grep -q "cx: 320$" "$work/fov-setup.yaml"
grep -q "cy: 240$" "$work/fov-setup.yaml"
grep -q "preset: jerlov:II$" "$work/fov-setup.yaml"
grep -q "phase: {henyey_greenstein: {g: 0.3}}" "$work/fov-setup.yaml"
echo "ok field of view, Jerlov II, H-G g = +0.3"
# the converted setup bakes
"$ds" bake --config "$work/fov-setup.yaml" --xy-step 64 --depth-samples 4 --z-max 4 \
  --no-preview -o "$work/fov.vdb" >/dev/null
"$ds" info "$work/fov.vdb" --json | grep -q '"henyey_greenstein":{"g":0.3}'

# A field of view in degrees by mistake, or a matrix of the wrong length: one line, exit 2.
their "[80]" "[0.37, 0.044, 0.035]" 1 >"$work/degrees.yaml"
expect_fail degrees "$ds" import-config "$work/degrees.yaml" -o "$work/out.yaml"
grep -q "field of view must be in (0, pi) radians, got 80" "$work/err.txt"
their "[600.0, 0.0, 320.0]" "[0.37, 0.044, 0.035]" 1 >"$work/short.yaml"
expect_fail short "$ds" import-config "$work/short.yaml" -o "$work/out.yaml"
set +e; "$ds" import-config "$work/short.yaml" >/dev/null 2>&1; rc=$?; set -e
[[ $rc -eq 2 ]] || { echo "FAIL short: exit $rc"; exit 1; }
expect_absent "$work/out.yaml"
echo "import-config forms: OK"
