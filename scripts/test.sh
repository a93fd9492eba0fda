#!/usr/bin/env bash
# s3m test suite: builds (Release, incremental) and runs every unit and integration test with ctest.
# Needs only the repository (no ../shared data). Usage: scripts/test.sh [extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
