#!/usr/bin/env python3
"""Replays a TUM-layout dataset in another order or rate, for checking the SLAM on motion it was not
tuned on: every Nth frame (N times the motion per frame), backwards, or both, optionally from a later
first frame (--start: another start of the same recording). Writes rgb.txt, depth.txt,
associations.txt and groundtruth.txt with timestamps re-made at --fps, links rgb/ and depth/ to the
source (nothing is copied) and copies camera.yaml.

Usage: resequence_tum.py SRC_DIR OUT_DIR [--start 4] [--stride 2] [--reverse] [--fps 30]
Then: s3m run OUT_DIR --slam-only --out RUN && s3m eval --gt OUT_DIR/groundtruth.txt --est RUN/trajectory_camera.txt
"""
import argparse
import os
import shutil
import sys


def rows(path):
    """Non-comment rows of a TUM list, each as (line number, fields)."""
    out = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            if line.strip() and not line.startswith('#'):
                out.append((n, line.split()))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('src')
    ap.add_argument('out')
    ap.add_argument('--start', type=int, default=0,
                    help='drop the source\'s first N frames, before --reverse and --stride (default 0)')
    ap.add_argument('--stride', type=int, default=1, help='keep every Nth frame (default 1)')
    ap.add_argument('--reverse', action='store_true', help='play the frames backwards')
    ap.add_argument('--fps', type=float, default=30.0, help='frame rate of the new timestamps')
    a = ap.parse_args()
    if a.stride < 1 or a.fps <= 0 or a.start < 0:
        sys.exit('resequence_tum.py: --stride must be >= 1, --fps > 0 and --start >= 0')
    assoc_path = os.path.join(a.src, 'associations.txt')
    if not os.path.isfile(assoc_path):
        sys.exit(f'resequence_tum.py: {assoc_path} is missing (needs the TUM associations list)')
    assoc = rows(assoc_path)
    for n, p in assoc:
        if len(p) != 4:
            sys.exit(f'resequence_tum.py: {assoc_path} line {n}: expected "t_rgb rgb/FILE t_depth depth/FILE"')
    gt = {}
    gt_path = os.path.join(a.src, 'groundtruth.txt')
    if os.path.isfile(gt_path):
        for n, p in rows(gt_path):
            if len(p) != 8:
                sys.exit(f'resequence_tum.py: {gt_path} line {n}: expected "t tx ty tz qx qy qz qw"')
            gt[p[0]] = p[1:]
    if a.start >= len(assoc):
        sys.exit(f'resequence_tum.py: --start {a.start} leaves no frame ({assoc_path} lists {len(assoc)})')
    order = list(range(a.start, len(assoc)))
    if a.reverse:
        order.reverse()
    order = order[::a.stride]
    os.makedirs(a.out, exist_ok=True)
    for sub in ('rgb', 'depth'):
        link = os.path.join(a.out, sub)
        if not os.path.lexists(link):
            os.symlink(os.path.abspath(os.path.join(a.src, sub)), link)
    if os.path.isfile(os.path.join(a.src, 'camera.yaml')):
        shutil.copyfile(os.path.join(a.src, 'camera.yaml'), os.path.join(a.out, 'camera.yaml'))
    lines = {'rgb.txt': [], 'depth.txt': [], 'associations.txt': [], 'groundtruth.txt': []}
    for k, i in enumerate(order):
        t = f'{k / a.fps:.6f}'
        t_rgb, rgb, _, depth = assoc[i][1]
        lines['rgb.txt'].append(f'{t} {rgb}')
        lines['depth.txt'].append(f'{t} {depth}')
        lines['associations.txt'].append(f'{t} {rgb} {t} {depth}')
        if t_rgb in gt:  # the source's ground truth at the colour image's time
            lines['groundtruth.txt'].append(f'{t} ' + ' '.join(gt[t_rgb]))
    if not gt:
        del lines['groundtruth.txt']
    for name, body in lines.items():
        with open(os.path.join(a.out, name), 'w') as f:
            f.write(f'# resequenced from {a.src}: start {a.start}, stride {a.stride}, reverse {a.reverse}, {a.fps} Hz\n')
            f.write('\n'.join(body) + '\n')
    print(f'{len(order)} frames -> {a.out}' + ('' if gt else ' (no groundtruth.txt in the source)'))


if __name__ == '__main__':
    main()
