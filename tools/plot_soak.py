#!/usr/bin/env python3
"""Plots the memory curve of a soak run (bench/soak.cpp CSV) into a PNG.

Usage: tools/plot_soak.py soak.csv docs/images/soak_memory.png
Top: process RSS, kept-cloud store and octree memory [MB] over frames; bottom: SLAM's live keyframes
and the kept clouds (counts). A `bench_soak --threaded` CSV has only RSS and CPU time (the other
columns are empty), so only the RSS curve is drawn. Uses Debian's matplotlib (Agg backend).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst):
    with open(src, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_soak.py: {src} has no samples")
    col = lambda k: [float(r[k]) for r in rows]  # noqa: E731
    frames = col("frame")
    full = all(r["kept_mb"] != "" for r in rows)
    if not full:  # threaded run: the stages' structures were not sampled
        fig, a = plt.subplots(1, 1, figsize=(8, 3.5))
        a.plot(frames, col("rss_mb"), label="process RSS (threaded pipeline)")
        a.set_xlabel("frame")
        a.set_ylabel("memory [MB]")
        a.set_ylim(bottom=0)
        a.legend(loc="lower right")
        a.grid(alpha=0.3)
        fig.suptitle("s3m soak, threaded: %d frames, memory over time" % int(frames[-1]))
        fig.tight_layout()
        fig.savefig(dst, dpi=110)
        return
    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    a.plot(frames, col("rss_mb"), label="process RSS")
    a.plot(frames, col("kept_mb"), label="kept clouds (KeyframeStore)")
    a.plot(frames, col("map_mb"), label="semantic octree")
    a.set_ylabel("memory [MB]")
    a.legend(loc="upper left")
    a.grid(alpha=0.3)
    b.plot(frames, col("slam_keyframes"), label="SLAM live keyframes")
    b.plot(frames, col("kept_clouds"), label="kept clouds")
    b.set_xlabel("frame")
    b.set_ylabel("count")
    b.legend(loc="upper left")
    b.grid(alpha=0.3)
    fig.suptitle("s3m soak: %d frames, memory over time" % int(frames[-1]))
    fig.tight_layout()
    fig.savefig(dst, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
