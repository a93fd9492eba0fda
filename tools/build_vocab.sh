#!/usr/bin/env bash
# Rebuilds the shipped bag-of-words vocabulary vocab/orb_k10_l5.bin (see vocab/PROVENANCE.md).
# Usage: tools/build_vocab.sh [BUILD_DIR] [DATA_DIR] [SIM_DIR]
#   DATA_DIR: folder with the real sequences (default ../shared/data next to the repo)
#   SIM_DIR:  optional folder of simulator RGB images (e.g. from `s3m sim`); skipped when absent
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$repo/build}"
data="${2:-$repo/../shared/data}"
sim="${3:-}"
images=("$data/7scenes_redkitchen_0000-0499/rgb" "$data/tum_fr3_cabinet_keyframes/rgb")
if [[ -n "$sim" ]]; then images+=("$sim"); fi
"$build/src/apps/s3m" vocab "${images[@]}" --stride 2 --features 1000 --k 10 --levels 5 \
  --out "$repo/vocab/orb_k10_l5.bin"
