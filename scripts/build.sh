#!/usr/bin/env bash
# Configures and builds deepsea into build/ (Release, tests on). Compiles through ccache where it
# is installed (install-deps.sh installs it): a rebuild of a clean checkout then takes minutes,
# not a quarter of an hour.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
export CCACHE_BASEDIR=$PWD  # a checkout elsewhere hits the same cache
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDEEPSEA_BUILD_TESTS=ON "${launcher[@]}" >/dev/null
cmake --build build -j "$(nproc)"
