#!/usr/bin/env bash
# Proves a refactoring behaviour-preserving: runs two s3m binaries with --deterministic on the same
# inputs and compares every trajectory and map byte for byte (metrics.json: all but the timings).
#
#   tools/check_deterministic_identity.sh OLD_S3M NEW_S3M WORKDIR [KITCHEN_DIR]
#
# OLD_S3M: a copy of build/src/apps/s3m from before the change. Inputs (made once in WORKDIR with
# OLD_S3M sim): the office `loop` flight, seed 3, which closes a loop; the same with frames 250-279
# missing (a 1 s gap), which only relocalisation bridges; seed 11 with 12 dropped (blank) frames,
# which are LOST; and KITCHEN_DIR (e.g. ../shared/data/7scenes_redkitchen_0000-0499), if given.
# The loop flight runs a second time threaded (mapping on its own thread; slam.mapping_lag_frames 1,
# the default, makes that deterministic too), so the hand-over between the threads is compared.
# Prints one line per compared file and exits 1 if any differs. REUSE_OLD=1 keeps the old binary's
# outputs of an earlier check in the same WORKDIR (the inputs and KITCHEN_DIR must be the same).
set -euo pipefail
[ $# -ge 3 ] || { sed -n 2,12p "$0"; exit 2; }
OLD=$(realpath "$1") NEW=$(realpath "$2") W=$3 KITCHEN=${4:-}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$W"

make_inputs() {
  [ -f "$W/loop/rgb.txt" ] || "$OLD" sim --scene office --trajectory loop --frames 300 --seed 3 --out "$W/loop" >/dev/null 2>&1
  [ -f "$W/drop/rgb.txt" ] || "$OLD" sim --scene office --trajectory loop --frames 300 --seed 11 --drop-frames 12 \
    --out "$W/drop" >/dev/null 2>&1
  if [ ! -f "$W/gap/rgb.txt" ]; then
    mkdir -p "$W/gap"
    for f in "$W"/loop/*; do
      case $(basename "$f") in rgb.txt|depth.txt|labels.txt|associations.txt) ;; *) ln -sf "$f" "$W/gap/" ;; esac
    done
    for t in rgb depth labels associations; do  # drop data lines 250..279 (0-based), keep comments
      awk '/^#/ {print; next} {if (n < 250 || n >= 280) print; n++}' "$W/loop/$t.txt" > "$W/gap/$t.txt"
    done
  fi
}

run_all() {  # binary, suffix
  for d in loop gap drop; do
    "$1" run "$W/$d" --config "$ROOT/config/sim.yaml" --deterministic --no-report --out "$W/out_${d}_$2" >"$W/out_${d}_$2.log" 2>&1
  done
  "$1" run "$W/loop" --config "$ROOT/config/sim.yaml" --no-report --out "$W/out_threaded_$2" >"$W/out_threaded_$2.log" 2>&1
  if [ -n "$KITCHEN" ]; then
    "$1" run "$KITCHEN" --config "$ROOT/config/kitchen_7scenes.yaml" --segmenter none --deterministic --no-report \
      --out "$W/out_kitchen_$2" >"$W/out_kitchen_$2.log" 2>&1
  fi
}

make_inputs
# REUSE_OLD=1: keep the old binary's outputs from an earlier check in the same WORKDIR.
[ "${REUSE_OLD:-0}" = 1 ] && [ -f "$W/out_loop_old/trajectory_camera.txt" ] || run_all "$OLD" old
run_all "$NEW" new
status=0
for d in loop gap drop threaded ${KITCHEN:+kitchen}; do
  grep -h "^tracking:" "$W/out_${d}_new.log" | sed "s/^/$d: /"
  for f in trajectory_camera.txt trajectory_robot.txt keyframes.txt frames.txt map.ot map.ply; do
    if cmp -s "$W/out_${d}_old/$f" "$W/out_${d}_new/$f"; then echo "same $d/$f"; else echo "DIFF $d/$f"; status=1; fi
  done
  if python3 - "$W/out_${d}_old/metrics.json" "$W/out_${d}_new/metrics.json" <<'EOF'; then echo "same $d/metrics.json (without timings)"; else echo "DIFF $d/metrics.json"; status=1; fi
import json, sys
def strip(d):  # timings and output paths differ run to run
    return {k: v for k, v in d.items() if k not in ("fps", "timings_ms", "wall_time_s", "outputs")}
a, b = (strip(json.load(open(p))) for p in sys.argv[1:])
sys.exit(0 if a == b else 1)
EOF
done
exit $status
