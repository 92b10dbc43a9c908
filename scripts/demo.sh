#!/usr/bin/env bash
# The main job on the embedded default: install, build, run `deepsea demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/tools/deepsea/deepsea demo "$@"
