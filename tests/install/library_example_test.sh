#!/usr/bin/env bash
# s3m as an installed library: `cmake --install` into a scratch prefix, examples/library built
# against it with find_package(s3m), run on a short simulated flight whose folder looks like a real
# camera's (no sim.yaml, no label images), so the library needs the shipped vocabulary and the
# shipped real-image model, and finds them in the prefix ($S3M_DATA_DIR = <prefix>/share/s3m).
# Usage: library_example_test.sh BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR CXX_COMPILER
set -euo pipefail
build=$1 src=$2 work=$3 generator=$4 cxx=$5
rm -rf "$work"
mkdir -p "$work/run" "$work/empty"
prefix=$work/prefix
fail() { echo "FAIL: $*"; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$work/install.log"
for f in bin/s3m lib/cmake/s3m/s3mConfig.cmake include/s3m/pipeline/pipeline.hpp \
         share/s3m/vocab/orb_k10_l5.bin share/s3m/models/deeplabv3plus_mnv2_ade20k_fast.onnx \
         share/s3m/config/sim.yaml share/s3m/tools/plot_report.py share/s3m/tools/viewer/viewer.js; do
  [ -e "$prefix/$f" ] || fail "the install has no $f"
done
# Only the headers a library user needs are installed, and they are self-contained: every s3m
# header an installed one includes is installed too; the module-internal ones are not.
missing=$(cd "$prefix/include" && grep -rhoE '#include "s3m/[^"]+"' s3m | sed -E 's/#include "(.*)"/\1/' |
          sort -u | while read -r h; do [ -e "$h" ] || echo "$h"; done)
[ -z "$missing" ] || fail "installed headers include headers that are not installed: $missing"
for f in slam/io/map_codec.hpp slam/map/depth_points.hpp slam/map/group_search.hpp; do
  [ ! -e "$prefix/include/s3m/$f" ] || fail "the module-internal header $f is installed"
done

cmake -S "$src/examples/library" -B "$work/example" -G "$generator" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" || { cat "$work/configure.log"; fail "find_package(s3m)"; }
cmake --build "$work/example" >"$work/build.log" || { cat "$work/build.log"; fail "building the example"; }

"$prefix/bin/s3m" sim --out "$work/seq" --trajectory figure8 --frames 30 >"$work/sim.log" 2>&1
rm -rf "$work/seq/sim.yaml" "$work/seq/labels.txt" "$work/seq/labels"

cd "$work/run"
S3M_DATA_DIR="$prefix/share/s3m" "$work/example/s3m_library_example" "$work/seq" >out.txt 2>err.txt ||
  { cat out.txt err.txt; fail "the example failed"; }
cat out.txt
grep -q "^segmenter onnx" out.txt || fail "expected the shipped real-image model (segmenter onnx)"
grep -q "^frames 30 tracked 30 " out.txt || fail "expected all 30 frames tracked"
grep -Eq "^map: [1-9][0-9]* occupied voxels" out.txt || fail "expected a non-empty map"
[ -s example_map.ot ] || fail "example_map.ot was not written"

# The shipped files really come from S3M_DATA_DIR: an empty one stops the run, naming the file.
if S3M_DATA_DIR="$work/empty" "$work/example/s3m_library_example" "$work/seq" >out2.txt 2>err2.txt; then
  fail "ran without the shipped files"
fi
grep -q "$work/empty/vocab/orb_k10_l5.bin" err2.txt || { cat err2.txt; fail "the error does not name the missing vocabulary"; }
echo "PASS"
