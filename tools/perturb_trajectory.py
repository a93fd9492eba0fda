#!/usr/bin/env python3
"""Makes a synthetic 'estimate' from a TUM trajectory, for checking evaluation tools:
a random-walk drift and white noise on positions, rotation noise, an optional scale and a rigid
transform of the whole trajectory (which se3 alignment must remove). Deterministic for a seed.

Usage: perturb_trajectory.py IN.txt OUT.txt [--noise-m 0.01] [--drift-m 0.001] [--rot-noise-deg 0.5]
                             [--scale 1.0] [--rigid] [--every 1]
                             [--time-shift-s 0] [--seed 1]
"""
import argparse

import numpy as np


def quat_mul(a, b):  # (x, y, z, w)
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz])


def small_quat(rng, sigma_rad):
    v = rng.normal(0, sigma_rad, 3)
    th = np.linalg.norm(v)
    if th < 1e-15:
        return np.array([0, 0, 0, 1.0])
    return np.concatenate([np.sin(th / 2) * v / th, [np.cos(th / 2)]])


def rot_of(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--noise-m", type=float, default=0.01, help="white position noise sigma per axis [m]")
    ap.add_argument("--drift-m", type=float, default=0.001, help="random-walk step sigma per pose per axis [m]")
    ap.add_argument("--rot-noise-deg", type=float, default=0.5, help="rotation noise sigma per axis [deg]")
    ap.add_argument("--scale", type=float, default=1.0, help="multiply positions (after noise)")
    ap.add_argument("--rigid", action="store_true", help="apply a fixed rotation + translation to everything")
    ap.add_argument("--every", type=int, default=1, help="keep every k-th pose")
    ap.add_argument("--time-shift-s", type=float, default=0.0, help="add to every timestamp [s]")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    rows = [l.split("#")[0].split() for l in open(a.inp)]
    d = np.array([r for r in rows if r], dtype=float)[:: a.every]
    n = len(d)
    d[:, 1:4] += np.cumsum(rng.normal(0, a.drift_m, (n, 3)), axis=0) + rng.normal(0, a.noise_m, (n, 3))
    d[:, 1:4] *= a.scale
    for k in range(n):
        d[k, 4:8] = quat_mul(d[k, 4:8], small_quat(rng, np.radians(a.rot_noise_deg)))
    if a.rigid:
        q0 = np.array([0.2, -0.3, 0.5, 0.7])
        q0 /= np.linalg.norm(q0)
        R0, t0 = rot_of(q0), np.array([1.5, -2.0, 0.7])
        d[:, 1:4] = d[:, 1:4] @ R0.T + t0
        for k in range(n):
            d[k, 4:8] = quat_mul(q0, d[k, 4:8])
    d[:, 0] += a.time_shift_s
    d[:, 4:8] /= np.linalg.norm(d[:, 4:8], axis=1, keepdims=True)
    with open(a.out, "w") as f:
        f.write("# perturbed copy of %s (noise %g m, drift %g m/step, rot %g deg, scale %g, rigid %s, seed %d)\n"
                % (a.inp, a.noise_m, a.drift_m, a.rot_noise_deg, a.scale, a.rigid, a.seed))
        for r in d:
            f.write("%.6f %s\n" % (r[0], " ".join("%.9g" % v for v in r[1:])))


if __name__ == "__main__":
    main()
