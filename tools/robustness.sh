#!/usr/bin/env bash
# Feeds the real s3m binary bad inputs and prints what the user sees, as the markdown table rows of
# docs/ROBUSTNESS.md (case | command | exit | message). Every case must fail cleanly: exit 1
# ("s3m: error: ...") or a command-line usage error (CLI11, exit 100..127); never succeed, crash
# (exit >= 128), hang (every case has 120 s and 4 GB of address space; exit 124 is a hang) or report
# an unexpected error (exit 2). The script exits 1 otherwise. The exception: `skipped` rows, a bad
# file of one frame after the first, which `s3m run` skips with a warning naming it (exit 0, the
# warning shown; dataset.max_unreadable_in_a_row in config/README.md).
# Usage: tools/robustness.sh [path/to/s3m]   (default build/src/apps/s3m)
# The `s3m run` cases render an 8-frame simulator sequence first (a few seconds) and edit copies of it.
# The out-of-disk case for `s3m run` uses a real 768 KiB tmpfs when mounting works (root), else the
# file-size limit.
set -uo pipefail
cd "$(dirname "$0")/.."
REPO="$(pwd)"
S3M="$(realpath "${1:-build/src/apps/s3m}")"
[ -x "$S3M" ] || { echo "robustness.sh: no s3m binary at $S3M (build it first)" >&2; exit 2; }
W="$(mktemp -d /tmp/s3m_robust_XXXXXX)"
trap 'rm -rf "$W"' EXIT
cd "$W"
bad=0

# row "case" cmd args... : runs the command in $W, prints one table row with its first stderr line.
row() {
  local name="$1"; shift
  local err code
  rm -rf out  # each case writes into a folder of its own (an earlier case's run would be refused)
  (ulimit -v 4000000; exec timeout 120 "$@") >/dev/null 2>stderr.txt
  code=$?
  err="$(grep -v '^\s*$' stderr.txt | head -n 3 | tr '\n' ' ' | sed 's/ *$//; s/|/\\|/g')"
  err="${err//$W\//}"  # files the script made, named relative to its folder
  local shown="${*/#$S3M/s3m}"
  shown="${shown//$REPO\//}"
  printf '| %s | `%s` | %s | %s |\n' "$name" "$shown" "$code" "$err"
  if [ "$code" != 1 ] && { [ "$code" -lt 100 ] || [ "$code" -ge 124 ]; }; then bad=1; printf '| ^ NOT CLEAN | | | |\n'; fi
}

# skipped "case" cmd args... : a run that must finish (exit 0) and warn that one frame was skipped.
skipped() {
  local name="$1"; shift
  local err code
  rm -rf out
  (ulimit -v 4000000; exec timeout 120 "$@") >stderr.txt 2>&1  # the warning goes where the log goes
  code=$?
  err="$(grep -o 'run: frame [0-9]* skipped: .*' stderr.txt | head -n 1 | sed 's/|/\\|/g')"
  local shown="${*/#$S3M/s3m}"
  shown="${shown//$REPO\//}"
  printf '| %s | `%s` | %s | %s |\n' "$name" "$shown" "$code" "$err"
  if [ "$code" != 0 ] || [ "$(grep -c 'run: frame [0-9]* skipped: ' stderr.txt)" != 1 ]; then bad=1; printf '| ^ NOT CLEAN | | | |\n'; fi
}

# ---- inputs --------------------------------------------------------------------------------
gt=gt.txt
{ echo "# t tx ty tz qx qy qz qw"; for i in $(seq 0 49); do printf '%d.%02d0000 %s 0 1 0 0 0 1\n' $((i / 10)) $((i % 10 * 10)) "0.0$i"; done; } > $gt
head -c 700 $gt > truncated.txt                        # cut in the middle of a line
# setcol FILE LINE COL VALUE: data line LINE (1-based, comments not counted) gets VALUE in column COL.
setcol() { awk -v l="$2" -v c="$3" -v v="$4" '/^#/ {print; next} {n++; if (n == l) $c = v; print}' "$1"; }
setcol $gt 5 2 nan > nan_pose.txt
setcol $gt 5 8 2 > bad_quat.txt
printf '# only comments\n\n' > empty.txt
awk '!/^#/ {printf "%.6f %s %s %s %s %s %s %s\n", $1 + 1000, $2, $3, $4, $5, $6, $7, $8}' $gt > shifted.txt
setcol $gt 6 1 0.300000 > unsorted.txt
head -c 300 /dev/urandom > garbage.txt
printf '1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0.1 0 1 0 0 0 0 1 0\n1 0 0 0.2 0 1 0 0 0 0 1 0\n' > kitti_gt.txt
printf '1 0 0 0 0 1 0 0 0 0 1 0\n1e308 1e308 0 0 1e308 -1e308 0 0 0 0 1 0\n' > kitti_bad.txt
setcol $gt 5 2 1e300 > huge.txt
mkdir -p outdir && cp $gt est.txt
mkfifo fifo_gt.txt                                      # a named pipe: opening it would block forever

echo "| case | command | exit | message |"
echo "|---|---|---|---|"
row "missing file" "$S3M" eval --gt missing.txt --est $gt
row "truncated trajectory (cut mid-line)" "$S3M" eval --gt $gt --est truncated.txt --no-plots
row "NaN in a pose" "$S3M" eval --gt $gt --est nan_pose.txt --no-plots
row "non-unit quaternion" "$S3M" eval --gt $gt --est bad_quat.txt --no-plots
row "empty trajectory (comments only)" "$S3M" eval --gt $gt --est empty.txt --no-plots
row "timestamps that match nothing in the ground truth" "$S3M" eval --gt $gt --est shifted.txt --no-plots
row "timestamps not increasing" "$S3M" eval --gt $gt --est unsorted.txt --no-plots
row "binary garbage as trajectory" "$S3M" eval --gt $gt --est garbage.txt --no-plots
row "KITTI matrix that is not a rotation (huge entries)" "$S3M" eval --gt kitti_gt.txt --est kitti_bad.txt --format kitti --no-plots
row "huge translation (1e300 m)" "$S3M" eval --gt $gt --est huge.txt --no-plots
row "ground truth is a FIFO (named pipe)" "$S3M" eval --gt fifo_gt.txt --est $gt --no-plots
# Out of disk while writing results: the file-size limit makes every write beyond 1 KiB fail
# (SIGXFSZ ignored, so the write returns EFBIG like a full disk returns ENOSPC).
"$S3M" eval --gt $gt --est est.txt --out outdir --no-plots >/dev/null 2>&1
before=$(md5sum outdir/metrics.json | cut -d' ' -f1)
sed -i '3,$s/ 1 0 0 0 1$/ 1.001 0 0 0 1/' est.txt
row "disk full while writing outputs (ulimit -f 1)" bash -c "trap '' XFSZ; ulimit -f 1; exec \"\$0\" \"\$@\"" "$S3M" eval --gt $gt --est est.txt --out outdir --no-plots
after=$(md5sum outdir/metrics.json | cut -d' ' -f1)
if [ "$before" = "$after" ] && /usr/bin/python3 -c "import json,sys; json.load(open('outdir/metrics.json'))"; then
  echo "<!-- disk-full case: previous outdir/metrics.json unchanged and still valid JSON -->"
else
  echo "<!-- disk-full case: previous metrics.json was changed or is unreadable -->"; bad=1
fi

# ---- s3m run ------------------------------------------------------------------------------
PY=/usr/bin/python3
"$S3M" sim --frames 8 --trajectory handheld --out seq >/dev/null 2>&1 || { echo "robustness.sh: s3m sim failed" >&2; exit 2; }
"$S3M" sim --frames 2 --trajectory handheld --width 320 --height 240 --out small >/dev/null 2>&1
RUN=("$S3M" run --config "$REPO/config/sim.yaml" --deterministic --no-report)  # the preset's oracle segmenter
# mk NAME: a fresh copy of the sequence; prints its path. nth LIST N: the N-th (0-based) image path.
mk() { rm -rf "$1"; cp -r seq "$1"; echo "$1"; }
nth() { grep -v '^#' "$1" | sed -n "$(( $2 + 1 ))p" | awk '{print $2}'; }
d=$(mk no_rgb_list); rm $d/rgb.txt $d/associations.txt
d=$(mk missing_png); rm $d/$(nth $d/rgb.txt 3)
d=$(mk corrupt_png); echo "this is not a PNG" > $d/$(nth $d/rgb.txt 2)
d=$(mk truncated_png); f=$d/$(nth $d/depth.txt 4); head -c $(( $(stat -c %s $f) / 2 )) $f > t.png && mv t.png $f
d=$(mk depth8); $PY -c "from PIL import Image; Image.new('L', (640, 480), 100).save('$d/$(nth $d/depth.txt 1)')"
d=$(mk wrong_size); cp small/$(nth small/rgb.txt 0) $d/$(nth $d/rgb.txt 5)
d=$(mk wrong_size_first); cp small/$(nth small/rgb.txt 0) $d/$(nth $d/rgb.txt 0)
# A JPEG cut short: libjpeg would decode it with grey rows; every colour image a JPEG for this case.
d=$(mk truncated_jpg); for f in $(grep -v '^#' $d/rgb.txt | awk '{print $2}'); do
  $PY -c "from PIL import Image; Image.open('$d/$f').save('$d/${f%.png}.jpg', quality=90)"; rm $d/$f; done
sed -i 's/\.png$/.jpg/' $d/rgb.txt; sed -i 's/\(rgb\/[0-9.]*\)\.png/\1.jpg/' $d/associations.txt
f=$d/$(nth $d/rgb.txt 3); head -c $(( $(stat -c %s $f) / 2 )) $f > t.jpg && mv t.jpg $f
sed 's/^dataset:$/dataset:\n  max_unreadable_in_a_row: 0/' "$REPO/config/sim.yaml" > strict.yaml
d=$(mk shifted); rm $d/associations.txt; awk '/^#/ {print; next} {printf "%.6f %s\n", $1 + 5, $2}' seq/depth.txt > $d/depth.txt
d=$(mk empty); rm $d/associations.txt; printf '# color images\n# timestamp filename\n' > $d/rgb.txt
d=$(mk nan_gt); awk '/^#/ {print; next} {n++; if (n == 3) $2 = "nan"; print}' seq/groundtruth.txt > $d/groundtruth.txt
d=$(mk huge_gt); awk '/^#/ {print; next} {n++; if (n == 3) $2 = "1e300"; print}' seq/groundtruth.txt > $d/groundtruth.txt
d=$(mk fx0); sed -i 's/^fx: .*/fx: 0/' $d/camera.yaml
d=$(mk fy_neg); sed -i 's/^fy: .*/fy: -525/' $d/camera.yaml
d=$(mk width_huge); sed -i 's/^width: .*/width: 1e300/' $d/camera.yaml
d=$(mk depth_factor0); sed -i 's/^depth_factor: .*/depth_factor: 0/' $d/camera.yaml
d=$(mk cx_far); sed -i 's/^cx: .*/cx: 5000/' $d/camera.yaml
d=$(mk fx_normalised); sed -i 's/^fx: .*/fx: 0.9/; s/^fy: .*/fy: 0.9/; s/^cx: .*/cx: 0.5/; s/^cy: .*/cy: 0.5/' $d/camera.yaml
"${RUN[@]}" small --out run_of_small >/dev/null 2>&1  # a complete run of another recording
DEPTH_CAMERA='depth_camera:\n  width: 848\n  height: 480\n  fx: 425\n  fy: 425\n  cx: 423.5\n  cy: 239.5\n  T_c_d:\n'
d=$(mk depth_camera_mm); printf "$DEPTH_CAMERA    translation: [-15, 0.3, 0.2]\n    quaternion: [0, 0, 0, 1]\n" >> $d/camera.yaml
d=$(mk depth_camera_aligned); printf "$DEPTH_CAMERA    translation: [-0.015, 0, 0]\n    quaternion: [0, 0, 0, 1]\n" >> $d/camera.yaml
mkdir -p card && cp "$REPO/tests/data/semantics/tiny_rgb.onnx" "$REPO/tests/data/semantics/tiny_rgb.yaml" card/
printf 'wall\nfloor\nchair\n' > card/tiny_rgb.classes.txt
echo "not a folder" > out_is_a_file
d=$(mk fifo_assoc); rm $d/associations.txt; mkfifo $d/associations.txt
d=$(mk fifo_png); f=$d/$(nth $d/rgb.txt 3); rm $f; mkfifo $f
d=$(mk dir_assoc); rm $d/associations.txt; mkdir $d/associations.txt
mkfifo fifo_preset.yaml
# s7 NAME: seq as Microsoft 7-Scenes ships a sequence (frame-NNNNNN.color.png, .depth.png, .pose.txt; no lists).
s7() { rm -rf "$1"; mkdir -p "$1"; local n=0 _a rgb _b depth; while read -r _a rgb _b depth; do
  cp "seq/$rgb" "$(printf '%s/frame-%06d.color.png' "$1" $n)"; cp "seq/$depth" "$(printf '%s/frame-%06d.depth.png' "$1" $n)"
  printf '1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n' > "$(printf '%s/frame-%06d.pose.txt' "$1" $n)"; n=$((n + 1))
  done < <(grep -v '^#' seq/associations.txt); }
# sn NAME: seq as ScanNet's SensReader exports a scan (color/N, depth/N.png; no intrinsic/ here).
sn() { rm -rf "$1"; mkdir -p "$1/color" "$1/depth"; local n=0 _a rgb _b depth; while read -r _a rgb _b depth; do
  cp "seq/$rgb" "$1/color/$n.png"; cp "seq/$depth" "$1/depth/$n.png"; n=$((n + 1)); done < <(grep -v '^#' seq/associations.txt); }
sn scannet_no_intrinsics
s7 7scenes_no_depth; rm 7scenes_no_depth/frame-000003.depth.png
s7 7scenes_bad_pose; printf '1 0 0 0\n0 1 0 0\n0 0 1\n0 0 0 1\n' > 7scenes_bad_pose/frame-000002.pose.txt
# preset NAME SED-EXPR...: config/sim.yaml edited; absurd settings of issue 24.
preset() { local n=$1; shift; cp "$REPO/config/sim.yaml" $n.yaml; for e in "$@"; do sed -i "$e" $n.yaml; done; }
preset threads_65537 's/radius_min_neighbors: 1}/radius_min_neighbors: 1, num_threads: 65537}/'
preset cost 's/pixel_stride: 2 /pixel_stride: 1 /' 's/resolution_m: 0.05 /resolution_m: 0.005 /' 's/max_depth_m: 4.0 /max_depth_m: 100 /'
mkdir -p card_threads && cp "$REPO/tests/data/semantics/"tiny_rgb.* card_threads/ && echo "threads: 65537" >> card_threads/tiny_rgb.yaml
mkfifo fifo_map.ot

echo
echo "| case | command | exit | message |"
echo "|---|---|---|---|"
row "dataset folder missing" "${RUN[@]}" nope --out out
row "rgb.txt missing" "${RUN[@]}" no_rgb_list --out out
row "image file missing" "${RUN[@]}" missing_png --out out
row "7-Scenes folder: a frame without its depth image" "${RUN[@]}" 7scenes_no_depth --out out
row "7-Scenes folder: a pose file with a short row" "${RUN[@]}" 7scenes_bad_pose --out out
row "ScanNet export without intrinsic/intrinsic_color.txt" "${RUN[@]}" scannet_no_intrinsics --out out
skipped "corrupt PNG (text), frame 2" "${RUN[@]}" corrupt_png --out out
skipped "truncated depth PNG (first half), frame 4" "${RUN[@]}" truncated_png --out out
skipped "truncated colour JPEG (first half), frame 3" "${RUN[@]}" truncated_jpg --out out
skipped "8-bit depth PNG, frame 1" "${RUN[@]}" depth8 --out out
skipped "colour image of the wrong size (320x240), frame 5" "${RUN[@]}" wrong_size --out out
row "colour image of the wrong size (320x240), first frame" "${RUN[@]}" wrong_size_first --out out
row "corrupt PNG, frame 2, with dataset.max_unreadable_in_a_row 0" "$S3M" run --config strict.yaml --deterministic --no-report corrupt_png --out out
row "depth timestamps 5 s off, no associations.txt" "${RUN[@]}" shifted --out out
row "empty sequence (rgb.txt comments only)" "${RUN[@]}" empty --out out
row "NaN in groundtruth.txt" "${RUN[@]}" nan_gt --out out
row "1e300 m in groundtruth.txt" "${RUN[@]}" huge_gt --out out
row "fx = 0 in camera.yaml" "${RUN[@]}" fx0 --out out
row "fy < 0 in camera.yaml" "${RUN[@]}" fy_neg --out out
row "width = 1e300 in camera.yaml" "${RUN[@]}" width_huge --out out
row "depth_factor = 0 in camera.yaml" "${RUN[@]}" depth_factor0 --out out
row "principal point cx = 5000 px in a 640 px image" "${RUN[@]}" cx_far --out out
row "normalised intrinsics (fx 0.9, cx 0.5)" "${RUN[@]}" fx_normalised --out out
row "--out is the recording being read" "${RUN[@]}" seq --out seq
row "--out holds a run of another recording" "${RUN[@]}" seq --out run_of_small
row "s3m sim --frames 2000000000" "$S3M" sim --frames 2000000000 --out huge_sim
row "camera.yaml depth_camera 15 mm away, written as 15 m" "${RUN[@]}" depth_camera_mm --out out
row "camera.yaml depth_camera 848x480, depth images 640x480 (already aligned)" "${RUN[@]}" depth_camera_aligned --out out
row "model card with 3 classes, model with 4 outputs" "${RUN[@]}" seq --out out --segmenter onnx:card/tiny_rgb.yaml
row "--out is an existing file" "${RUN[@]}" seq --out out_is_a_file
row "associations.txt is a FIFO (named pipe)" "${RUN[@]}" fifo_assoc --out out
row "colour image is a FIFO (named pipe)" "${RUN[@]}" fifo_png --out out
row "associations.txt is a directory" "${RUN[@]}" dir_assoc --out out
row "preset is a FIFO (named pipe)" "$S3M" run --config fifo_preset.yaml --deterministic --no-report seq --out out
row "map.insert.num_threads: 65537 in the preset" "$S3M" run --config threads_65537.yaml --deterministic --no-report seq --out out
row "threads: 65537 in the model card" "${RUN[@]}" seq --out out --segmenter onnx:card_threads/tiny_rgb.yaml
row "cloud.pixel_stride 1, map.resolution_m 0.005, cloud.max_depth_m 100" "$S3M" run --config cost.yaml --deterministic --no-report seq --out out
row "s3m query on a map that is a FIFO (named pipe)" "$S3M" query fifo_map.ot --class chair
# Bags (ROS builds only: tum2bag and --rosbag exist there): a recorder s3m does not know, and a
# config camera that does not fit the recording's images.
if "$S3M" tum2bag seq --out unknown.bag --rgb-topic /cam/left --depth-topic /cam/depth --camera-info-topic /cam/info >/dev/null 2>&1; then
  printf 'fx: 262.5\nfy: 262.5\ncx: 159.5\ncy: 119.5\nwidth: 320\nheight: 240\ndepth_factor: 1000\n' > cam320.yaml
  preset bag_cam320 "s|  camera: \"\" |  camera: $W/cam320.yaml |"
  "$S3M" tum2bag seq --out tum.bag >/dev/null 2>&1
  row "rosbag whose topics no known recorder wrote (ROS builds)" "${RUN[@]}" --rosbag unknown.bag --out out
  row "rosbag of 640x480 images, config camera 320x240 (ROS builds)" "$S3M" run --config bag_cam320.yaml --deterministic --no-report --rosbag tum.bag --out out
fi
# ROS 2 recordings (every build): the sequence written by tum2bag --format mcap|db3, then damaged.
"$S3M" tum2bag seq --format mcap --out seq.mcap >/dev/null 2>&1
head -c "$(( $(stat -c %s seq.mcap) / 2 ))" seq.mcap > cut.mcap
cp seq.mcap flip.mcap
printf '\377\377\377\377' | dd of=flip.mcap bs=1 seek="$(( $(stat -c %s seq.mcap) / 3 ))" conv=notrunc 2>/dev/null
printf 'not a database' > text.db3
"$S3M" tum2bag seq --format mcap --out unknown.mcap --rgb-topic /cam/left --depth-topic /cam/depth --camera-info-topic /cam/info >/dev/null 2>&1
row "ROS 2 MCAP recording cut in half" "${RUN[@]}" cut.mcap --out out
row "ROS 2 MCAP recording with 4 bytes overwritten inside a chunk" "${RUN[@]}" flip.mcap --out out
row "a .db3 file that is not a database" "${RUN[@]}" text.db3 --out out
row "ROS 2 recording whose topics no known driver wrote" "${RUN[@]}" unknown.mcap --out out
# Out of disk: a good run first, then the same run into the same folder on a full file system.
if mkdir -p tmpfs && mount -t tmpfs -o size=768k tmpfs tmpfs 2>/dev/null; then
  how="768 KiB tmpfs"; trap 'umount "$W/tmpfs" 2>/dev/null; rm -rf "$W"' EXIT
  "${RUN[@]}" seq --out tmpfs/run --slam-only >/dev/null 2>&1  # its outputs fit (~0.5 MB, slam_map.bin most of it)
  cp -r tmpfs/run run_before
  row "disk full during the map write ($how)" "${RUN[@]}" seq --out tmpfs/run
else
  how="ulimit -f 64"; "${RUN[@]}" seq --out tmpfs/run >/dev/null 2>&1; cp -r tmpfs/run run_before
  row "disk full during the map write ($how)" bash -c "trap '' XFSZ; ulimit -f 64; exec \"\$0\" \"\$@\"" "${RUN[@]}" seq --out tmpfs/run
fi
# Outputs are staged and moved in at the end: the failed run must leave the earlier run exactly as it
# was, with no staging folder or temporary file left.
if diff -r run_before tmpfs/run >/dev/null && ! ls -a tmpfs/run | grep -q '\.tmp\|\.s3m-staging'; then
  echo "<!-- run disk-full case ($how): the earlier run is byte-identical, no staging folder or temporary file was left -->"
else
  echo "<!-- run disk-full case ($how): earlier outputs changed or a staging/temporary file was left -->"; bad=1
fi
exit $bad
