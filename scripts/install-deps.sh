#!/usr/bin/env bash
# Installs what deepsea needs from Debian 12's packages (as root). Skips apt when all are there.
set -euo pipefail
pkgs=(build-essential cmake pkg-config ccache
      libopenvdb-dev libboost-iostreams-dev libblosc-dev libtbb-dev
      libopenexr-dev libopenimageio-dev openimageio-tools
      libspng-dev libdeflate-dev libisal-dev libjpeg62-turbo-dev
      libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libfmt-dev libssl-dev
      libgtest-dev libbenchmark-dev
      python3-dev pybind11-dev python3-numpy python3-venv)
if [[ "${1:-}" == "--tests" ]]; then
  pkgs+=(blender python3-pytest python3-openimageio python3-openvdb mypy clang-format
        clang-14 libclang-rt-14-dev  # scripts/sanitize.sh: ASan, UBSan, libFuzzer
        # ROS 1 (docs/ros.md): deepsea_ros, deepsea_rosbag and their test's master and clients
        ros-core libroscpp-dev librosbag-dev libsensor-msgs-dev libdiagnostic-msgs-dev
        python3-rospy python3-rosbag python3-sensor-msgs python3-diagnostic-msgs)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
