#!/usr/bin/env bash
# One home per equation (docs/architecture.md, "Where each equation lives"): the runtime's rows
# and the exact reference call optics' functions for the pinhole ray, the lamp term and the
# direct signal, and nothing in src/ writes them out again. A copy that drifts from optics'
# would still pass the accuracy tests within their tolerance; this check fails on the copy.
set -euo pipefail
ds=$1 work=$2 src=$3
cd "$src"
fail=0
calls() {  # calls FUNCTION FILE...: each file calls FUNCTION(
  local fn=$1; shift
  for f in "$@"; do
    grep -Eq "\\b$fn(<[A-Za-z]+>)?\\(" "$f" || { echo "FAIL: $f does not call $fn (optics' equation)"; fail=1; }
  done
}
calls direct_signal src/runtime/kernels.cpp src/reference/reference.cpp src/optics/direct.cpp \
  src/reference/path_tracer.cpp
calls gaussian_lamp_term src/runtime/lamps.cpp src/optics/direct.cpp
calls lamp_term src/runtime/lamps.cpp src/optics/direct.cpp
calls lambertian_radiance src/runtime/kernels.cpp src/optics/direct.cpp
calls transmission src/runtime/kernels.cpp src/reference/reference.cpp src/reference/path_tracer.cpp
calls lamp_in_scatter src/reference/path_tracer.cpp
calls surface_radiance src/reference/path_tracer.cpp
calls ray_x src/runtime/compositor.cpp src/runtime/lamps.cpp src/asset/asset.cpp
calls ray_y src/runtime/compositor.cpp src/runtime/lamps.cpp src/asset/asset.cpp
# Code lines (comments and string literals left out) of FILES... that match the Perl regex $1.
code_matching() {
  local re=$1; shift
  perl -ne 'BEGIN { $re = shift @ARGV } my $c = $_; $c =~ s{"(?:[^"\\]|\\.)*"}{""}g;
            $c =~ s{//.*}{}; print "$ARGV:$.: $_" if $c =~ /$re/; close ARGV if eof' "$re" "$@"
}
# The pinhole written out, (u - cx) / fx, anywhere but the camera's own header.
hand=$(code_matching '\([^()]*-[^()]*\bc[xy]\)\s*/\s*[a-z_.]*\bf[xy]\b' \
       $(find src include -name '*.cpp' -o -name '*.h' | grep -v '^include/deepsea/optics/camera.h$'))
[[ -z $hand ]] || { echo "FAIL: the pinhole ray written out (use Camera::ray, ray_x, ray_y):"; echo "$hand"; fail=1; }
# The direct signal written out as a product of its factors in the runtime's rows.
hand=$(code_matching '\bL\[[a-z0-9 +*]+\]\s*\*\s*\(?[^;]*transmission|\bD\[[a-z]\]\s*=\s*L\[' \
       src/runtime/*.cpp)
[[ -z $hand ]] || { echo "FAIL: the direct signal written out (use direct_signal):"; echo "$hand"; fail=1; }
((fail == 0)) && echo "shared equations: OK"
exit $fail
