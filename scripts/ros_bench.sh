#!/usr/bin/env bash
# Rate and latency of deepsea_ros on this machine (docs/ros.md, "Speed"): a master of its own on
# 127.0.0.1, frames of `deepsea scene` at SIZE x SIZE, an asset baked for their camera, the node,
# and tools/ros/ros_bench.py publishing at RATE Hz for SECONDS and measuring what comes back.
#   scripts/ros_bench.sh [BUILD_DIR] [SIZE] [RATE] [SECONDS]     (defaults: build 800 30 10)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build} size=${2:-800} rate=${3:-30} seconds=${4:-10}
ds=$build/tools/deepsea/deepsea node=$build/tools/deepsea/deepsea_ros
[[ -x $node ]] || { echo "ros_bench: $node not built (ROS 1: scripts/install-deps.sh --tests)" >&2; exit 1; }
work=$(mktemp -d)
pids=()
cleanup() { local p; for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; rm -rf "$work"; }
trap cleanup EXIT
"$ds" scene --out "$work/in" --frames 4 --width "$size" --height "$size" --altitude 1.5 -q
"$ds" bake --camera "$work/in/camera.yaml" --rig "$root/volumes/rigs/authors-testset.yaml" \
  --water jerlov:IB -o "$work/a.vdb" >/dev/null 2>&1
port=$(/usr/bin/python3 -c "import socket; s = socket.socket(); s.bind(('127.0.0.1', 0)); print(s.getsockname()[1])")
export ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOSTNAME=127.0.0.1
export ROS_HOME=$work/ros ROS_LOG_DIR=$work/ros/log
rosmaster --core -p "$port" >/dev/null 2>&1 &
pids+=($!)
for _ in $(seq 100); do (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && break; sleep 0.1; done
"$node" _asset:="$work/a.vdb" _diagnostics_period:=0.5 >"$work/node.txt" 2>&1 &
pids+=($!)
echo "deepsea_ros ${size}x${size}, input ${rate} Hz, ${seconds} s; $(uptime)"
/usr/bin/python3 "$root/tools/ros/ros_bench.py" "$work/in" "$rate" "$seconds"
