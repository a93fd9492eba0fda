#!/usr/bin/env bash
# A map that lasts, on real data (issue 23): the shared 7-Scenes kitchen split into two sessions,
# frames 0-249 and 250-499 (folders of symlinks with trimmed rgb/depth/associations/groundtruth
# files). Runs the whole sequence once, the first half, and the second half with --map of the
# first; prints whether the second half localised at its first frame and the ATE of the combined
# trajectory (first half's file + second half's file, one se3 alignment to the whole ground truth)
# next to the single run's.
#
#   tools/kitchen_halves_benchmark.sh S3M KITCHEN_DIR WORKDIR
#
# S3M: the built binary (build/src/apps/s3m); KITCHEN_DIR: ../shared/data/7scenes_redkitchen_0000-0499.
# Every run is --deterministic --segmenter none (the SLAM map is under test; the colour-only
# semantic map still goes with the session).
set -euo pipefail
[ $# -ge 3 ] || { sed -n 2,14p "$0"; exit 2; }
S3M=$(realpath "$1") K=$(realpath "$2") W=$3
ROOT=$(cd "$(dirname "$0")/.." && pwd)
CFG="$ROOT/config/kitchen_7scenes.yaml"
mkdir -p "$W"

half() {  # name, first data line, end data line (0-based, exclusive)
  local d="$W/$1" from=$2 to=$3
  mkdir -p "$d"
  for f in "$K"/*; do
    case $(basename "$f") in rgb.txt|depth.txt|associations.txt|groundtruth.txt) ;; *) ln -sfn "$f" "$d/" ;; esac
  done
  for t in rgb depth associations; do  # data lines [from, to), comments kept
    awk -v a="$from" -v b="$to" '/^#/ {print; next} {if (n >= a && n < b) print; n++}' "$K/$t.txt" > "$d/$t.txt"
  done
  # Ground truth: the poses within the half's time range (one line per frame in this dataset).
  local t0 t1
  t0=$(awk '!/^#/ {print $1; exit}' "$d/rgb.txt")
  t1=$(awk '!/^#/ {t=$1} END {print t}' "$d/rgb.txt")
  awk -v a="$t0" -v b="$t1" '/^#/ {print; next} {if ($1 >= a - 1e-6 && $1 <= b + 1e-6) print}' "$K/groundtruth.txt" \
    > "$d/groundtruth.txt"
}

half first 0 250
half second 250 500
run() {  # dataset, out, extra args...
  local data=$1 out=$2
  shift 2
  "$S3M" run "$data" --config "$CFG" --segmenter none --deterministic --no-report --out "$out" "$@" > "$out.log" 2>&1
}
run "$K" "$W/out_full"
run "$W/first" "$W/out_first"
run "$W/second" "$W/out_second_map" --map "$W/out_first"
run "$W/second" "$W/out_second_alone"

echo "second half with --map of the first: first frame $(awk '!/^#/ {print $1, $3; exit}' "$W/out_second_map/frames.txt")"
grep -h "^tracking:\|^sub-maps:" "$W/out_second_map.log" | sed 's/^/  /'
cat "$W/out_first/trajectory_camera.txt" > "$W/combined.txt"
grep -v '^#' "$W/out_second_map/trajectory_camera.txt" >> "$W/combined.txt"
# One se3 alignment per estimate against the whole sequence's ground truth.
"$S3M" eval --gt "$K/groundtruth.txt" --est "$W/out_full/trajectory_camera.txt" "$W/combined.txt" \
  "$W/out_first/trajectory_camera.txt" "$W/out_second_map/trajectory_camera.txt" \
  --name single_run_0-499 combined_halves first_half second_half_in_first --out "$W/eval"
echo "second half alone (its own world): $(grep -h '^ATE' "$W/out_second_alone.log")"
