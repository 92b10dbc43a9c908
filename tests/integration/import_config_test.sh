#!/usr/bin/env bash
# deepsea import-config: the authors' own config converts into a setup deepsea bakes; bad
# input is one line and a non-zero exit. Skipped (77) where ../shared is absent.
set -euo pipefail
ds=$1 work=$2 src=$3
cfg="$src/../shared/data/rgbd/seafloor-descent/deepsearenderer_config.yaml"
if [[ ! -f $cfg ]]; then echo "SKIP: ../shared absent"; exit 77; fi
rm -rf "$work"; mkdir -p "$work"
"$ds" import-config "$cfg" -o "$work/authors.yaml"
grep -q "preset: jerlov:IB" "$work/authors.yaml"
grep -q "phase: {petzold: clear}" "$work/authors.yaml"
# light_RID_type 1: their lab-measured LED table (BXRA_table), one per lamp
[[ $(grep -c "rid: {table: {angle_deg: \[0, 10, 20, 30, 35, 40, 45, 50, 60, 90\], value: \[1, 0.96, 0.87, 0.75, 0.63, 0.5, 0.28, 0.2, 0.12, 0\]}}" "$work/authors.yaml") -eq 2 ]]
# their white_balance, scale_factor and auto_iso: the camera stage (docs/import-config.md)
grep -q "white_balance: {gains: \[2.28613, 1, 1.361328\]}" "$work/authors.yaml"
grep -q "curve: linear" "$work/authors.yaml"
# the left lamp (x = -0.5) turns toward the optical axis: direction x > 0
awk '/position: \[-0.5/{getline; print}' "$work/authors.yaml" | grep -q "direction: \[0.51"
"$ds" bake --config "$work/authors.yaml" --xy-step 64 --depth-samples 4 --z-max 4 -o "$work/x.vdb" >/dev/null
for bad in missing notours shortmatrix; do
  case $bad in
    missing) in="$work/none.yaml" ;;
    notours) in="$work/notours.yaml"; echo "camera: {width: 3}" > "$in" ;;
    shortmatrix) in="$work/short.yaml"; sed 's/camera_intrinsic_matrix: .*/camera_intrinsic_matrix: [600.0, 0.0]/' "$cfg" > "$in" ;;
  esac
  set +e; "$ds" import-config "$in" -o "$work/out-$bad.yaml" 2>"$work/err.txt"; rc=$?; set -e
  [[ $rc -ne 0 && $(wc -l <"$work/err.txt") -eq 1 && ! -e "$work/out-$bad.yaml" ]] || {
    echo "FAIL $bad: rc=$rc"; cat "$work/err.txt"; exit 1; }
  echo "ok $bad: $(cat "$work/err.txt")"
done
echo "import-config: OK"
