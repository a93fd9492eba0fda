#!/usr/bin/env bash
# s3m set-up: installs the Debian 12 packages the project needs and builds what running needs (the
# s3m CLI and the libraries; the ROS1 node with --with-ros) in Release. The test command
# (scripts/test.sh) builds the tests and benchmarks into the same build/ folder.
# Non-interactive and idempotent; safe to run again.
# Usage: scripts/setup.sh [--with-ros] [--with-training] [--no-build]
#   --with-training  also PyTorch and ONNX for Python, which only tools/train_segmenter.py and
#                    tools/seg_make_test_model.py need (their outputs are committed).
set -euo pipefail
cd "$(dirname "$0")/.."

with_ros=0
with_training=0
build=1
for arg in "$@"; do
  case "$arg" in
    --with-ros) with_ros=1 ;;
    --with-training) with_training=1 ;;
    --no-build) build=0 ;;
    *) echo "setup.sh: unknown option '$arg' (expected --with-ros, --with-training or --no-build)" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake ninja-build pkg-config ccache git clang clang-format libclang-rt-14-dev
  libopencv-dev libopencv-contrib-dev libeigen3-dev libceres-dev liboctomap-dev libdynamicedt3d-dev libompl-dev libembree-dev libtbb-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-matplotlib
  libjs-three chromium  # the map viewer (three.js r111, copied into reports) and its browser test
  libzstd-dev liblz4-dev libsqlite3-dev zlib1g-dev  # ROS 2 recordings: MCAP chunks, CRC-32, .db3
  slurm-wlm munge  # s3m batch --engine slurm; the batch tests start a one-node cluster (tests/batch/slurm_cluster.sh)
)
[ "$with_training" = 1 ] && packages+=(python3-torch python3-onnx)
# Node.js and npm: the ROS 2 tests' independent reference writer (tests/ros2, npm ci below). Only
# when missing: a machine's own Node.js (e.g. NodeSource's, which bundles npm) conflicts with
# Debian's npm package.
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)
if [ "$with_ros" = 1 ]; then
  # ROS1 as packaged by Debian 12: the node's libraries and messages, rosbag (C++ API), and
  # rosmaster/roslaunch for roscore, the launch file and the node test. octomap_msgs is not packaged.
  packages+=(ros-core-dev libroscpp-dev librosbag-dev librosbag-storage-dev libsensor-msgs-dev
             libcv-bridge-dev libtf2-ros-dev libtf2-msgs-dev libtf2-geometry-msgs-dev libnav-msgs-dev libgeometry-msgs-dev libstd-msgs-dev
             libvisualization-msgs-dev libstd-srvs-dev libmessage-filters-dev python3-rosmaster
             python3-roslaunch python3-rosbag)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup.sh: installing ${#missing[@]} Debian packages: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" = 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup.sh: all Debian packages present"
fi

# The ROS 2 tests' reference writer (tests/ros2): npm packages pinned by its package-lock.json.
# Without them those tests report themselves skipped.
if command -v npm >/dev/null; then
  (cd tests/ros2 && npm ci --no-audit --no-fund --loglevel=error) ||
    echo "setup.sh: npm ci in tests/ros2 failed: the ROS 2 reference tests will be skipped"
fi

if [ "$build" = 1 ]; then
  ros_flag=OFF
  [ "$with_ros" = 1 ] && ros_flag=ON
  targets=(s3m)
  [ "$with_ros" = 1 ] && targets+=(s3m_node)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR=1
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DS3M_WITH_ROS=$ros_flag
  # s3m_node exists only when ROS1 was found; build it only then.
  if [ "$with_ros" = 1 ] && ! cmake --build build --target help | grep -q '^s3m_node:'; then targets=(s3m); fi
  cmake --build build -j "$(nproc)" --target "${targets[@]}"
  echo "setup.sh: built ${targets[*]} into build/ (CLI: build/src/apps/s3m); scripts/test.sh builds the tests"
fi
