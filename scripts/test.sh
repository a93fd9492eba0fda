#!/usr/bin/env bash
# s3m test suite. Needs only the repository (no ../shared data).
#  1. Release build (build/, incremental): every unit and integration test with ctest; with ROS
#     installed also the ROS1 node and rosbag tests (-DS3M_WITH_ROS=ON, ctest label "ros").
#     The Slurm batch test runs on a one-node cluster ctest starts and stops around it
#     (slurm_cluster_start/stop: tests/batch/slurm_cluster.sh, as root); skipped without Slurm.
#  2. Sanitizer build (build-asan/: ASan + UBSan, -O1 -g, no benchmarks): the unit tests again
#     (ctest -L unit, which includes the fuzz-corpus replay); any sanitizer report or leak fails.
# Usage: scripts/test.sh [--quick] [--restricted-isa] [extra ctest args]
#   --quick (or S3M_TEST_QUICK=1) runs stage 1 only, for quick local iterations.
#   --restricted-isa pins the vector code chosen at run time to SSE4.2 (Embree's kernels, which
#     render the simulator's frames, and OpenCV's dispatched functions), as an older x86-64 CPU
#     would run it: no test may depend on the machine's SIMD width. Simulator folders cached in
#     the temp folder are kept apart per Embree setting (tests/integration/cached_folder.hpp).
set -euo pipefail
cd "$(dirname "$0")/.."
quick="${S3M_TEST_QUICK:-0}"
args=()
for a in "$@"; do
  case "$a" in
    --quick) quick=1 ;;
    --restricted-isa)
      export S3M_EMBREE_CONFIG="isa=sse4.2"
      export OPENCV_CPU_DISABLE="AVX2,FMA3,FP16,AVX,POPCNT,SSE4.1,SSE4.2"
      echo "test.sh: restricted ISA: S3M_EMBREE_CONFIG=$S3M_EMBREE_CONFIG OPENCV_CPU_DISABLE=$OPENCV_CPU_DISABLE" ;;
    *) args+=("$a") ;;
  esac
done

# ccache keys on paths below the repository relative to it, so another clone of it (CI's) reuses the cache.
# (NOHASHDIR: the -g sanitizer build would otherwise key on the build directory's absolute path.)
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR=1
# The ROS1 front end and its tests (label "ros") are built whenever ROS is installed
# (scripts/setup.sh --with-ros); the ASan stage below stays ROS-free.
ros_flag=OFF
dpkg-query -W -f='${Status}' libroscpp-dev 2>/dev/null | grep -q "install ok installed" && ros_flag=ON
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DS3M_WITH_ROS=$ros_flag >/dev/null
cmake --build build -j "$(nproc)"
ctest --test-dir build --output-on-failure -j "$(nproc)" "${args[@]}"
[ "$quick" = 1 ] && exit 0

echo "test.sh: stage 2, unit tests under ASan + UBSan in build-asan/ (skip with --quick)"
# halt_on_error + -fno-sanitize-recover: the first report aborts the test, so ctest fails on it.
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" -DS3M_SANITIZE=ON -DS3M_BUILD_BENCH=OFF >/dev/null
# Only the unit-test executables (and what they link): the integration tests stay Release-only.
mapfile -t unit_targets < <(cmake --build build-asan --target help | sed -n 's/^\(test_[a-z0-9_]*\): .*/\1/p' |
                            grep -v -E '^test_(integration|browser)$')
cmake --build build-asan -j "$(nproc)" --target "${unit_targets[@]}"
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -L unit "${args[@]}"
