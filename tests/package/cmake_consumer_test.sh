#!/usr/bin/env bash
# A consumer project (tests/package/consumer) configured with find_package(deepsea) against
# the installed prefix only, built and run: it bakes, writes, reloads and composites.
set -euo pipefail
cmake=$1 cxx=$2 prefix=$3 consumer=$4 work=$5
rm -rf "$work"; mkdir -p "$work/run"
# Only the prefix: no package registry, so the build tree cannot stand in for the install.
"$cmake" -S "$consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/configure.txt" 2>&1 \
  || { cat "$work/configure.txt"; exit 1; }
prefix_abs=$(cd "$prefix" && pwd -P)
grep -q "deepsea .* from $prefix_abs/" "$work/configure.txt" \
  || { echo "FAIL: deepsea not found in $prefix_abs"; grep deepsea "$work/configure.txt"; exit 1; }
"$cmake" --build "$work/build" >"$work/build.txt" 2>&1 || { cat "$work/build.txt"; exit 1; }
"$work/build/consumer" "$work/run"
[[ -s $work/run/final.png && -s $work/run/tiny.vdb ]]
echo "package cmake consumer: OK"
