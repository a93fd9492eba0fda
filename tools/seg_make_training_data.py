#!/usr/bin/env python3
"""Renders the simulator sequences that tools/train_segmenter.py trains and validates on.

    /usr/bin/python3 tools/seg_make_training_data.py --s3m build/src/apps/s3m --out /tmp/segdata

Training: 3 scenes x 4 trajectories, a different seed (layout/textures) for each, frames spread out
(low --fps) so consecutive frames differ. Held-out validation: every scene with seed 9 and the
"loop" trajectory, never seen in training. Prints the exact `s3m sim` commands it runs.
"""
import argparse
import subprocess
import sys
from pathlib import Path

# Ordered so that any prefix covers all scenes (training can start on what exists).
TRAIN = [(scene, traj, seed)
         for traj, seeds in (("uav_sweep", (1, 2, 3)), ("handheld", (1, 2, 3)), ("figure8", (4, 5, 6)), ("lawnmower", (7, 8, 10)))
         for scene, seed in zip(("office", "living_room", "corridor"), seeds)]
VAL = [(scene, "loop", 9) for scene in ("office", "living_room", "corridor")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--s3m", required=True, help="path of the s3m binary")
    ap.add_argument("--out", required=True)
    ap.add_argument("--train-frames", type=int, default=40)
    ap.add_argument("--val-frames", type=int, default=40)
    ap.add_argument("--fps", type=float, default=4.0, help="lower = larger motion between frames")
    args = ap.parse_args()
    out = Path(args.out)
    for split, items, frames in (("val", VAL, args.val_frames), ("train", TRAIN, args.train_frames)):
        for scene, traj, seed in items:
            d = out / split / f"{scene}_{traj}_s{seed}"
            if (d / "labels.txt").exists():
                continue
            cmd = [args.s3m, "sim", "--scene", scene, "--trajectory", traj, "--seed", str(seed), "--frames", str(frames),
                   "--fps", str(args.fps), "--out", str(d)]
            print(" ".join(cmd), flush=True)
            r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if r.returncode != 0:
                sys.exit(f"seg_make_training_data: s3m sim failed for {d}:\n{r.stderr[-2000:]}")


if __name__ == "__main__":
    main()
