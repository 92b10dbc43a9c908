#!/usr/bin/env bash
# The "Choosing the lattice" table of docs/asset-format.md: the fixed 16 px lattice against the
# automatic one for a wide-angle camera and for narrow beams. Each row: the bake's own sample
# check and the full comparison (`--check`, every 5th pixel, all scenes: worst mean, worst max).
# Run after `bash scripts/build.sh`; a few minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
ds=./build/tools/deepsea/deepsea
out=out/lattice-rule; mkdir -p "$out"
cat > "$out/wide-96x72.yaml" <<'YAML'
camera: {width: 96, height: 72, fx: 76.0, fy: 76.0, cx: 47.5, cy: 35.5}
YAML
# the 800x800 demo view's top edge, pixels 540..635 x 0..71: far in narrow beams' tails
cat > "$out/edge-96x72.yaml" <<'YAML'
camera: {width: 96, height: 72, fx: 600.0, fy: 600.0, cx: -140.0, cy: 400.0}
YAML
cat > "$out/narrow-128x96.yaml" <<'YAML'
camera: {width: 128, height: 96, fx: 600.0, fy: 600.0, cx: 63.5, cy: 47.5}
YAML
rig() {  # sigma: volumes/demo.yaml's rig with that beam width
  sed -n '/^rig:/,/^water:/p' volumes/demo.yaml | sed '$d' \
    | sed "s/sigma_deg: 35/sigma_deg: $1/" > "$out/rig-$1.yaml"
  echo "$out/rig-$1.yaml"
}
echo "| camera | sigma | water | lattice | step | K | bake s | sample mean / max | full mean / max |"
echo "|---|---|---|---|---|---|---|---|---|"
run() {  # camera sigma water label bake-options...
  local cam=$1 sigma=$2 water=$3 label=$4; shift 4
  local log="$out/log.txt"
  "$ds" bake --camera "$out/$cam.yaml" --rig "$(rig "$sigma")" --water "$water" \
    -o "$out/a.vdb" --check --check-stride 5 "$@" > "$log" 2>/dev/null
  local step K bake sample full
  step=$(grep -o '(step [0-9]*)' "$log" | tr -dc 0-9)
  K=$(($(grep -o 'x [0-9]* samples' "$log" | tr -dc 0-9) - 1))
  bake=$(grep -o 'bake [0-9.]* s' "$log" | tr -dc 0-9.)
  sample=$(grep -o '^check: mean [0-9.]* %, max [0-9.]* %' "$log" | awk '{print $3 " / " $6 " %"}' || true)
  [[ -n $sample ]] || sample="not checked"
  full=$(awk '/^(plane|open)/ { m = $(NF-2) + 0; x = $(NF-1) + 0;
      if (m > mm) mm = m; if (x > xx) xx = x } END { printf "%.3f / %.3f %%", mm, xx }' "$log")
  echo "| $cam | $sigma | $water | $label | $step | $K | $bake | $sample | $full |"
}
old=(--xy-step 16 --depth-samples 64 --no-check)
run wide-96x72 35 deep:clear "fixed 16 px" "${old[@]}"
run wide-96x72 35 deep:clear "auto"
run wide-96x72 35 jerlov:3C "fixed 16 px" "${old[@]}"
run wide-96x72 35 jerlov:3C "auto"
run narrow-128x96 5 jerlov:IB "fixed 16 px" "${old[@]}"
run narrow-128x96 5 jerlov:IB "auto"
run edge-96x72 5 jerlov:IB "fixed 16 px" "${old[@]}"
run edge-96x72 5 jerlov:IB "auto"
run narrow-128x96 15 jerlov:IB "auto"
