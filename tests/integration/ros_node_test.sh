#!/usr/bin/env bash
# deepsea_ros and deepsea_rosbag (docs/ros.md) against a real ROS 1 master on 127.0.0.1: a
# publisher of RGB-D frames from `deepsea scene`, the node, and a subscriber that checks each
# image against `deepsea render` of the same frame (within one code value), the stamps, frame
# ids and camera_info; malformed messages (wrong encoding, colour/depth size mismatch, empty
# data) counted in /diagnostics and skipped with the node alive; a bag round trip through
# deepsea_rosbag. Skipped (77) where ROS 1 is not installed (scripts/install-deps.sh --tests).
set -euo pipefail
ds=$1 work=$2 src=$3
node=$(dirname "$ds")/deepsea_ros bagtool=$(dirname "$ds")/deepsea_rosbag
py=/usr/bin/python3
if ! command -v rosmaster >/dev/null || [[ ! -x $node || ! -x $bagtool ]] ||
   ! "$py" -c "import rospy, rosbag, sensor_msgs.msg, diagnostic_msgs.msg" 2>/dev/null; then
  echo "SKIP: ROS 1 not installed or the node not built (scripts/install-deps.sh --tests, DEEPSEA_ROS)"
  exit 77
fi
rm -rf "$work"; mkdir -p "$work/ros"
source "$(dirname "$0")/cli_lib.sh"
"$ds" scene --out "$work/in" --frames 3 --width 160 --height 120 --altitude 1.5 -q
"$ds" bake --camera "$work/in/camera.yaml" --rig "$src/volumes/rigs/authors-testset.yaml" \
  --water jerlov:IB --xy-step 16 --depth-samples 16 -o "$work/a.vdb" >/dev/null
# the reference: the CLI's rendering of the same frames at the same fixed exposure
"$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  -o "$work/ref" --exposure 40 >/dev/null

# A master of our own on a free port, everything it and the nodes write under $work.
port=$("$py" -c "import socket; s = socket.socket(); s.bind(('127.0.0.1', 0)); print(s.getsockname()[1])")
export ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOSTNAME=127.0.0.1
export ROS_HOME=$work/ros ROS_LOG_DIR=$work/ros/log
pids=()
cleanup() { local p; for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT
rosmaster --core -p "$port" >"$work/ros/master.txt" 2>&1 &
pids+=($!)
for _ in $(seq 100); do (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && break; sleep 0.1; done
"$node" _asset:="$work/a.vdb" _exposure:=40.0 _publish_depth:=true _publish_backscatter:=true \
  _diagnostics_period:=0.2 >"$work/ros/node.txt" 2>&1 &
pids+=($!)
node_pid=$!

# 1. Live: every frame against the reference; malformed frames counted, node alive after.
timeout 60 "$py" "$src/tests/integration/ros_node_check.py" live "$work/in" "$work/ref" \
  || { echo "FAIL: live check; node log:"; cat "$work/ros/node.txt"; exit 1; }
kill -0 "$node_pid" || { echo "FAIL: the node died"; cat "$work/ros/node.txt"; exit 1; }
# each malformed reason is logged once
for why in "encoding 'mono8'" "is 160x120 but" "empty image"; do
  [[ $(grep -c "$why" "$work/ros/node.txt") -eq 1 ]] || { echo "FAIL: '$why' not logged once"; cat "$work/ros/node.txt"; exit 1; }
done

# 2. A bag round trip: frames recorded into a bag, converted, read back and checked.
"$py" "$src/tests/integration/ros_node_check.py" write_bag "$work/in" "$work/in.bag"
"$bagtool" --asset "$work/a.vdb" --in "$work/in.bag" -o "$work/out.bag" --exposure 40 --depth \
  | grep -q "rendered 3 of 3 pair(s)"
"$py" "$src/tests/integration/ros_node_check.py" read_bag "$work/in" "$work/ref" "$work/out.bag"
[[ -z $(find "$work" -maxdepth 1 -name '*tmp*') ]] || { echo "FAIL: temporary left"; ls "$work"; exit 1; }
# depth stamped 2 ms after colour: approximate sync within 5 ms pairs every frame (the output
# stamped as the colour), exact sync none
"$py" "$src/tests/integration/ros_node_check.py" write_bag "$work/in" "$work/late.bag" 2
"$bagtool" --asset "$work/a.vdb" --in "$work/late.bag" -o "$work/late_out.bag" --exposure 40 \
  --depth --sync approximate --slop 0.005 | grep -q "rendered 3 of 3 pair(s)"
"$py" "$src/tests/integration/ros_node_check.py" read_bag "$work/in" "$work/ref" "$work/late_out.bag"
"$bagtool" --asset "$work/a.vdb" --in "$work/late.bag" -o "$work/late_exact.bag" --exposure 40 \
  | grep -q "rendered 0 of 0 pair(s)"
# a bag without the depth topic: one line naming it, nothing written
expect_fail "no depth topic" "$bagtool" --asset "$work/a.vdb" --in "$work/in.bag" \
  -o "$work/bad.bag" --depth-topic /nothing
grep -q "no messages on /nothing" "$work/err.txt"
expect_absent "$work/bad.bag"
echo "deepsea_ros: ok"
