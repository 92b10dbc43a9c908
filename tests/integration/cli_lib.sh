# Helpers for the CLI tests (sourced; needs $work).

# expect_fail NAME CMD...: CMD must exit non-zero with exactly one line on stderr.
expect_fail() {
  local name=$1; shift
  set +e
  "$@" >"$work/out.txt" 2>"$work/err.txt"
  local rc=$?
  set -e
  if [[ $rc -eq 0 ]]; then echo "FAIL $name: exit 0"; exit 1; fi
  if [[ $(wc -l <"$work/err.txt") -ne 1 ]]; then echo "FAIL $name: stderr:"; cat "$work/err.txt"; exit 1; fi
  echo "ok $name (exit $rc): $(cat "$work/err.txt")"
}

# expect_absent PATH...: none of the paths exists (no half-written output).
expect_absent() {
  local p
  for p in "$@"; do
    if [[ -e $p ]]; then echo "FAIL: $p was written"; exit 1; fi
  done
}

# their INTRINSICS ATTENUATION VSF_TYPE: a DeepSeaRenderer (the authors' renderer) config on stdout.
their() {
  cat <<YAML
image_width_height: [640, 480]
camera_intrinsic_matrix: $1
water_attenuation_RGB: $2
vsf_type: $3
light_spectrum_RGB: [0.25, 0.35, 0.4]
light_RID_type: 0
num_lights: 1
light_positions_XYZ: [[0.5, 0.0, 0.0]]
light_orientations_RollPitchYaw: [[0.0, -0.536, 0.0]]
YAML
}
