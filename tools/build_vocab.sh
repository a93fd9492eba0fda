#!/usr/bin/env bash
# Rebuilds the shipped bag-of-words vocabulary vocab/orb_k10_l5.bin (see vocab/PROVENANCE.md) from
# real images and simulator renders.
# Usage: tools/build_vocab.sh [BUILD_DIR] [DATA_DIR] [SIM_DIR]
#   DATA_DIR: folder with the real sequences (default ../shared/data next to the repo)
#   SIM_DIR:  where the simulator sequences are rendered (default: a temporary folder, removed after)
# The simulator scenes/seeds below are deliberately not those of the tests (office seed 7
# handheld/figure8, office seed 3 loop), so the tests keep measuring unseen views.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$repo/build}"
data="${2:-$repo/../shared/data}"
sim="${3:-}"
s3m="$build/src/apps/s3m"
if [[ -z "$sim" ]]; then
  sim="$(mktemp -d)"
  trap 'rm -rf "$sim"' EXIT
fi
# scene:trajectory:seed, 60 frames each at 640x480 (every 2nd image is used: 30 per sequence).
sequences=(living_room:uav_sweep:21 corridor:forward:22 office:lawnmower:23)
images=("$data/7scenes_redkitchen_0000-0499/rgb" "$data/tum_fr3_cabinet_keyframes/rgb")
for s in "${sequences[@]}"; do
  IFS=: read -r scene traj seed <<<"$s"
  out="$sim/${scene}_${traj}_seed${seed}"
  if [[ ! -f "$out/rgb.txt" ]]; then
    "$s3m" sim --scene "$scene" --trajectory "$traj" --seed "$seed" --frames 60 --out "$out" >/dev/null
  fi
  images+=("$out/rgb")
done
"$s3m" vocab "${images[@]}" --stride 2 --features 1000 --k 10 --levels 5 \
  --out "$repo/vocab/orb_k10_l5.bin"
