#!/usr/bin/env bash
# deepsea's single-scattering light transport against Blender Cycles (volume_bounces = 0): four
# small scenes (clear and coastal water, empty and with a tilted Lambertian plane), 8 seeds
# each; backscatter, surface and final image sums and 4x4 bins against `deepsea reference` and
# a baked asset, plus a check that a 1 % error in b is caught (docs/validation-cycles.md).
# Skipped (77) where Blender or Debian's python3 with numpy and OpenImageIO is absent.
set -euo pipefail
ds=$1 work=$2 src=$3
source "$src/tests/integration/cycles_lib.sh"
$py "$src/tests/integration/cycles_check.py" "$ds" "$work" --orders single
