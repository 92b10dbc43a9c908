#!/usr/bin/env bash
# Configures and builds deepsea into build/ (Release, tests on).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDEEPSEA_BUILD_TESTS=ON >/dev/null
cmake --build build -j "$(nproc)"
