#!/usr/bin/env bash
# The whole test suite: install (with the test-only packages), build, run CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
