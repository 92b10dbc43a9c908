#!/usr/bin/env bash
# deepsea's multiple scattering (all orders) against Blender Cycles with every bounce count 64:
# `deepsea bake --scattering multiple` + `deepsea render` (forward scatter from the phase
# function) on four small scenes (clear and coastal water, empty and with a tilted Lambertian
# plane), 16 Cycles seeds each. Asserted, per channel: image sums of the backscatter (empty
# water), the surface signal, the final image within max(5 %, 3 SE), the plane scenes' water
# light (backscatter + forward) within max(10 %, 3 SE), and the quadrants within
# max(10 %, 5 SE) where Cycles resolves 10 % (docs/validation-cycles.md, "All orders").
# Skipped (77) where Blender or Debian's python3 with numpy and OpenImageIO is absent.
set -euo pipefail
ds=$1 work=$2 src=$3
source "$src/tests/integration/cycles_lib.sh"
$py "$src/tests/integration/cycles_check.py" "$ds" "$work" --orders all
