#!/usr/bin/env bash
# The accuracy table of docs/asset-format.md: bakes the 800x800 authors camera with several
# lattice settings and compares each asset's lookup with exact per-pixel integration.
set -euo pipefail
cd "$(dirname "$0")/.."
ds=./build/tools/deepsea/deepsea
out=out/accuracy; mkdir -p "$out"
v=volumes
run() {  # rig water label bake-options...
  local rig=$1 water=$2 label=$3; shift 3
  echo "== $rig $water $label"
  "$ds" bake --camera $v/cameras/authors-800.yaml --rig $v/rigs/$rig.yaml --water jerlov:$water \
    -o "$out/a.vdb" --check --check-stride 20 "$@"
}
run authors-testset IB "default"
run authors-testset IB "step 8" --xy-step 8
run authors-testset IB "step 32" --xy-step 32
run authors-testset IB "K 16" --depth-samples 16
run authors-testset IB "uniform K 64" --depth-scheme uniform
run authors-testset IB "uniform K 16" --depth-scheme uniform --depth-samples 16
run authors-testset IB "taylor K 8" --depth-scheme taylor --depth-samples 8
run authors-testset IB "taylor K 64" --depth-scheme taylor
run authors-testset 3C "default"
run paper-eval IB "default"
run paper-eval 3C "default"
