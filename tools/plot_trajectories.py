#!/usr/bin/env python3
"""Plots for `s3m eval`: trajectories (X-Y, X-Z) with ground truth and every estimate overlaid,
RPE over time, and ATE error along the path.

Usage: plot_trajectories.py PLOT_DATA.json OUT_DIR
PLOT_DATA.json is written by s3m (s3m::eval::plot_data_json). Exit code 3 = matplotlib missing.
Run with Debian's /usr/bin/python3 (python3-matplotlib, python3-numpy).
"""
import json
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")  # files only; no display needed
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    import numpy as np
except ImportError as exc:  # the C++ side maps exit code 3 to an install hint
    print(f"plot_trajectories.py: {exc}", file=sys.stderr)
    sys.exit(3)

DPI = 130


def trajectory_plot(data, a, b, path):
    """Projection of all trajectories on axes (a, b) in metres, equal aspect."""
    fig, ax = plt.subplots(figsize=(7, 6))
    gt = data["gt"]
    ax.plot(gt[a], gt[b], "k--", lw=1.5, label="ground truth")
    for e in data["estimates"]:
        ax.plot(e["aligned"][a], e["aligned"][b], lw=1.2,
                label=f'{e["name"]} (ATE {100 * e["ate"]["rmse_m"]:.2f} cm)')
    ax.plot(gt[a][:1], gt[b][:1], "ko", ms=5)  # start
    ax.set_xlabel(f"{a} [m]")
    ax.set_ylabel(f"{b} [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"Trajectory {a.upper()}-{b.upper()} (estimates aligned to ground truth)")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def rpe_plot(data, path):
    fig, (ax_t, ax_r) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    t0 = data["gt"]["t"][0] if data["gt"]["t"] else 0.0
    for e in data["estimates"]:
        t = np.asarray(e["rpe"]["t"]) - t0
        ax_t.plot(t, 100 * np.asarray(e["rpe"]["trans_m"]), lw=1, label=e["name"])
        ax_r.plot(t, e["rpe"]["rot_deg"], lw=1, label=e["name"])
    ax_t.set_ylabel("translational RPE [cm]")
    ax_r.set_ylabel("rotational RPE [deg]")
    ax_r.set_xlabel("time since start of ground truth [s]")
    for ax in (ax_t, ax_r):
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    ax_t.set_title("Relative pose error over time")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def ate_plot(data, path):
    """Per estimate: the aligned X-Y path coloured by its ATE, and the ATE over time."""
    ests = data["estimates"]
    fig, axes = plt.subplots(2, len(ests), figsize=(6 * len(ests), 9), squeeze=False)
    t0 = data["gt"]["t"][0] if data["gt"]["t"] else 0.0
    for k, e in enumerate(ests):
        ax = axes[0][k]
        x, y = np.asarray(e["ate"]["x"]), np.asarray(e["ate"]["y"])
        err_cm = 100 * np.asarray(e["ate"]["error_m"])
        ax.plot(data["gt"]["x"], data["gt"]["y"], "k--", lw=1, label="ground truth")
        if len(x) > 1:
            segments = np.stack([np.column_stack([x[:-1], y[:-1]]), np.column_stack([x[1:], y[1:]])], axis=1)
            lc = LineCollection(segments, cmap="viridis", linewidths=2.5)
            lc.set_array(0.5 * (err_cm[:-1] + err_cm[1:]))
            ax.add_collection(lc)
            fig.colorbar(lc, ax=ax, label="ATE [cm]")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.autoscale()
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
        ax.set_title(f'{e["name"]}\nATE along the path (RMSE {100 * e["ate"]["rmse_m"]:.2f} cm)', fontsize=10)
        ax2 = axes[1][k]
        ax2.plot(np.asarray(e["ate"]["t"]) - t0, err_cm, lw=1)
        ax2.axhline(100 * e["ate"]["rmse_m"], color="r", ls=":", label="RMSE")
        ax2.set_xlabel("time since start of ground truth [s]")
        ax2.set_ylabel("ATE [cm]")
        ax2.grid(True, alpha=0.3)
        ax2.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(sys.argv[1]) as f:
        data = json.load(f)
    out = sys.argv[2]
    os.makedirs(out, exist_ok=True)
    trajectory_plot(data, "x", "y", os.path.join(out, "trajectory_xy.png"))
    trajectory_plot(data, "x", "z", os.path.join(out, "trajectory_xz.png"))
    rpe_plot(data, os.path.join(out, "rpe.png"))
    ate_plot(data, os.path.join(out, "ate.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
