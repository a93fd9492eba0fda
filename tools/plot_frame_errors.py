#!/usr/bin/env python3
"""Per-frame camera position error of two sets of `s3m run` outputs on the same sequences, one panel
per sequence: where along a flight two versions differ, and which frames each left out.

Usage: tools/plot_frame_errors.py OUT.png LABEL_A RUNS_A LABEL_B RUNS_B SEQ_DIR...
RUNS_A / RUNS_B hold one output folder per sequence, named as the sequence folder (what
bench/slam_matrix.py and `s3m run --out RUNS/NAME` write). Each run is SE3-aligned to its ground
truth on its own (TUM ATE); frames B reports ODOMETRY (frames.txt) are circled, frames B left LOST
are grey lines. Uses Debian's numpy and matplotlib (Agg backend).
"""
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def positions(path):
    out = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            out[round(v[0], 4)] = np.array(v[1:4])
    return out


def states(path):
    out = {}
    with open(path) as f:
        for line in f:
            if not line.startswith("#") and line.strip():
                fields = line.split()
                out[round(float(fields[1]), 4)] = fields[2]
    return out


def frame_errors_cm(seq, run):
    """(frame positions, errors [cm], stamp -> frame position) after the SE3 alignment (Umeyama)."""
    gt, est = positions(os.path.join(seq, "groundtruth.txt")), positions(os.path.join(run, "trajectory_camera.txt"))
    stamps = sorted(k for k in est if k in gt)
    X, Y = np.array([est[k] for k in stamps]), np.array([gt[k] for k in stamps])
    mx, my = X.mean(0), Y.mean(0)
    U, _, Vt = np.linalg.svd((Y - my).T @ (X - mx) / len(X))
    W = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        W[2, 2] = -1
    R = U @ W @ Vt
    err = np.linalg.norm((R @ X.T).T + (my - R @ mx) - Y, axis=1)
    index = {k: i for i, k in enumerate(sorted(gt))}
    return np.array([index[k] for k in stamps]), 100 * err, index


def main(dst, label_a, runs_a, label_b, runs_b, seqs):
    fig, axes = plt.subplots(len(seqs), 1, figsize=(9, 2.5 * len(seqs)), sharex=True, squeeze=False)
    for ax, seq in zip(axes[:, 0], seqs):
        name = os.path.basename(os.path.normpath(seq))
        for label, runs, colour in ((label_a, runs_a, "tab:red"), (label_b, runs_b, "tab:blue")):
            run = os.path.join(runs, name)
            idx, err, index = frame_errors_cm(seq, run)
            ax.plot(idx, err, ".", ms=3, color=colour,
                    label=f"{label}: ATE {np.sqrt((err ** 2).mean()):.2f} cm, {len(idx)} of {len(index)} frames")
        st = states(os.path.join(runs_b, name, "frames.txt"))
        by_frame = dict(zip(idx, err))
        odo = [index[k] for k, s in st.items() if s == "ODOMETRY" and k in index and index[k] in by_frame]
        if odo:
            ax.plot(odo, [by_frame[i] for i in odo], "o", mfc="none", color="k", ms=7,
                    label=f"{label_b}: ODOMETRY (posed by depth odometry)")
        for k, s in st.items():
            if s == "LOST" and k in index:
                ax.axvline(index[k], color="0.6", lw=0.8)
        ax.set_title(name, fontsize=9)
        ax.set_ylabel("position error [cm]")
        ax.legend(fontsize=7, loc="upper left")
    axes[-1, 0].set_xlabel(f"frame (grey lines: frames {label_b} left LOST)")
    fig.tight_layout()
    fig.savefig(dst, dpi=90)


if __name__ == "__main__":
    if len(sys.argv) < 7:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6:])
