#!/usr/bin/env bash
# The same consumer program compiled and linked with nothing but `pkg-config deepsea`.
set -euo pipefail
cxx=$1 prefix=$2 consumer=$3 work=$4 version=$5
rm -rf "$work"; mkdir -p "$work"
pc=$(find "$prefix" -name deepsea.pc)
export PKG_CONFIG_PATH=$(dirname "$pc")
[[ $(pkg-config --modversion deepsea) == "$version" ]] || { echo "FAIL: version"; exit 1; }
# The run path matters only for shared deepsea libraries (BUILD_SHARED_LIBS=ON) in a prefix
# the loader does not search, as for any pkg-config library there.
# shellcheck disable=SC2046
"$cxx" -std=c++17 -O1 -o "$work/consumer" "$consumer/consumer.cpp" $(pkg-config --cflags --libs deepsea) \
  -Wl,-rpath,"$(pkg-config --variable=libdir deepsea)"
"$work/consumer" "$work"
[[ -s $work/final.png ]]
echo "package pkg-config consumer: OK"
