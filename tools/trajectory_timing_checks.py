#!/usr/bin/env python3
"""Timing and per-frame checks of a TUM-layout RGB-D recording and of a trajectory estimated on it.

Behind the session-6 part of the 7-Scenes analysis in docs/RESULTS.md ("Why the kitchen ATE stalls"):

  duplicates  Frames whose colour (or depth) file is byte-identical to the previous frame's: a
              logger that fills fixed-rate slots repeats the last image when the sensor was late.
              Colour and depth repeats at different indices pair images of different instants.
  timeshift   SE3 (and Sim3) ATE of EST against the ground truth interpolated (linearly, positions
              only) at t_est + shift, for shifts in frames: a minimum away from 0 means the errors
              correlate with velocity (a clock offset, or a lag of one of the two trajectories).
  segments    RMS of the ATE residual (one alignment over the whole trajectory) per block of frames,
              and the ATE of the first N frames aligned on their own.
  windows     Relative motion over `--gap` frames (translation norm, rotation angle) of EST, of the
              ground truth, and of depth-only ICP between the two depth images (started from EST's
              relative pose; slam_motion_diagnostics.icp), with the pairwise differences.
  steps       The `--top` frame steps where EST's and the ground truth's step lengths differ most,
              each with depth-only ICP's step length as a third opinion.

Usage:
  trajectory_timing_checks.py duplicates DATASET_DIR
  trajectory_timing_checks.py timeshift GT.txt EST.txt [--shifts=-1:2:0.25]
  trajectory_timing_checks.py segments GT.txt EST.txt [--block 100]
  trajectory_timing_checks.py windows DATASET_DIR EST.txt [--gap 15]
  trajectory_timing_checks.py steps DATASET_DIR EST.txt [--top 10]
Run with /usr/bin/python3 (numpy and PIL). EST poses are matched to the ground truth by timestamp.
"""
import argparse
import hashlib
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import slam_motion_diagnostics as smd  # noqa: E402  (depth ICP, TUM reading, SO(3) log)


def read_positions(path):
    rows = [line.split() for line in open(path) if line.strip() and not line.startswith("#")]
    a = np.array([[float(x) for x in r[:8]] for r in rows])
    return a[:, 0], a[:, 1:4]


def align(A, B, scale=False):
    """Residuals of A aligned onto B (Umeyama; rigid, or with scale), and the scale."""
    ma, mb = A.mean(0), B.mean(0)
    X, Y = A - ma, B - mb
    U, S, Vt = np.linalg.svd(Y.T @ X)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    R = U @ D @ Vt
    s = np.trace(np.diag(S) @ D) / (X ** 2).sum() if scale else 1.0
    return (s * (R @ X.T)).T + mb - B, s


def rms(E):
    return float(np.sqrt((E ** 2).sum(1).mean()))


def matched(gt_path, est_path):
    tg, pg = read_positions(gt_path)
    te, pe = read_positions(est_path)
    idx = np.array([np.argmin(np.abs(tg - t)) for t in te])
    return pe, pg[idx]


def duplicates(args):
    repeated = {}
    for stream in ("rgb", "depth"):
        files = [l.split()[1] for l in open(os.path.join(args.dataset, stream + ".txt"))
                 if l.strip() and not l.startswith("#")]
        h = [hashlib.md5(open(os.path.join(args.dataset, f), "rb").read()).hexdigest() for f in files]
        rep = [i for i in range(1, len(h)) if h[i] == h[i - 1]]
        print(f"{stream}: {len(rep)} of {len(h)} frames repeat the previous one: {rep}")
        repeated[stream] = set(rep)
    only_c, only_d = sorted(repeated["rgb"] - repeated["depth"]), sorted(repeated["depth"] - repeated["rgb"])
    print(f"repeated in colour only: {only_c}\nrepeated in depth only: {only_d}")


def timeshift(args):
    tg, pg = read_positions(args.gt)
    te, pe = read_positions(args.est)
    a, b, step = (float(x) for x in args.shifts.split(":"))
    dt = np.median(np.diff(tg))
    for d in np.arange(a, b + 1e-9, step):
        tq = te + d * dt
        m = (tq >= tg[0]) & (tq <= tg[-1])
        G = np.stack([np.interp(tq[m], tg, pg[:, k]) for k in range(3)], 1)
        E, _ = align(pe[m], G)
        Es, s = align(pe[m], G, scale=True)
        print(f"shift {d:+.3f} frames: ATE {rms(E) * 100:.3f} cm, Sim3 {rms(Es) * 100:.3f} cm (scale {s:.3f}), {m.sum()} poses")


def segments(args):
    pe, G = matched(args.gt, args.est)
    E, _ = align(pe, G)
    for a in range(0, len(E), args.block):
        print(f"frames {a}-{min(a + args.block, len(E)) - 1}: residual RMS {rms(E[a:a + args.block]) * 100:.2f} cm")
    for n in range(args.block, len(E), args.block):
        print(f"first {n} frames aligned on their own: ATE {rms(align(pe[:n], G[:n])[0]) * 100:.2f} cm")


def icp_setup(dataset):
    cam = smd.read_intrinsics(os.path.join(dataset, "camera.yaml"))
    return cam, smd.Pair(dataset, cam, 1.0, 0.0, 0.0)


def angle_deg(T):
    return float(np.degrees(np.linalg.norm(smd.so3_log(T[:3, :3]))))


def translation_mm(T):
    return float(np.linalg.norm(T[:3, 3]) * 1000)


def translation_difference_mm(S, T):
    return float(np.linalg.norm(S[:3, 3] - T[:3, 3]) * 1000)


def windows(args):
    est, gt = smd.read_tum(args.est), smd.read_tum(os.path.join(args.dataset, "groundtruth.txt"))
    cam, P = icp_setup(args.dataset)
    keys = sorted(gt)
    for a in range(0, len(keys) - args.gap, args.gap):
        ka, kb = keys[a], keys[a + args.gap]
        if ka not in est or kb not in est:
            continue
        Te, Tg = smd.relative(est, ka, kb), smd.relative(gt, ka, kb)
        Td = smd.icp(P.raw_depth(a), P.raw_depth(a + args.gap), Te, cam)
        n, d = translation_mm, translation_difference_mm
        print(f"{a}->{a + args.gap}: translation est {n(Te):6.1f} gt {n(Tg):6.1f} icp {n(Td):6.1f} mm | "
              f"rotation est {angle_deg(Te):.2f} gt {angle_deg(Tg):.2f} icp {angle_deg(Td):.2f} deg | "
              f"|est-gt| {d(Te, Tg):.1f} |icp-gt| {d(Td, Tg):.1f} |icp-est| {d(Td, Te):.1f} mm")


def steps(args):
    est, gt = smd.read_tum(args.est), smd.read_tum(os.path.join(args.dataset, "groundtruth.txt"))
    cam, P = icp_setup(args.dataset)
    keys = [k for k in sorted(gt) if k in est]
    index = {k: i for i, k in enumerate(sorted(gt))}
    se = np.array([np.linalg.norm(smd.relative(est, a, b)[:3, 3]) for a, b in zip(keys, keys[1:])])
    sg = np.array([np.linalg.norm(smd.relative(gt, a, b)[:3, 3]) for a, b in zip(keys, keys[1:])])
    for j in np.argsort(-np.abs(se - sg))[:args.top]:
        a, b = keys[j], keys[j + 1]
        Td = smd.icp(P.raw_depth(index[a]), P.raw_depth(index[b]), smd.relative(est, a, b), cam)
        print(f"frame {index[a]}->{index[b]}: step est {se[j] * 1000:.1f} mm, gt {sg[j] * 1000:.1f} mm, "
              f"depth ICP {np.linalg.norm(Td[:3, 3]) * 1000:.1f} mm")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("duplicates").add_argument("dataset")
    t = sub.add_parser("timeshift")
    t.add_argument("gt")
    t.add_argument("est")
    t.add_argument("--shifts", default="-1:2:0.25", help="from:to:step, in frames")
    s = sub.add_parser("segments")
    s.add_argument("gt")
    s.add_argument("est")
    s.add_argument("--block", type=int, default=100)
    w = sub.add_parser("windows")
    w.add_argument("dataset")
    w.add_argument("est")
    w.add_argument("--gap", type=int, default=15)
    p = sub.add_parser("steps")
    p.add_argument("dataset")
    p.add_argument("est")
    p.add_argument("--top", type=int, default=10)
    args = ap.parse_args()
    np.seterr(divide="ignore")  # the ICP's Huber weight at an exactly zero residual
    {"duplicates": duplicates, "timeshift": timeshift, "segments": segments, "windows": windows,
     "steps": steps}[args.cmd](args)


if __name__ == "__main__":
    main()
