#!/usr/bin/env python3
"""Independent numpy re-implementation of the TUM RGB-D benchmark's evaluation formulas, used to
cross-check `s3m eval` (see docs/RESULTS.md, "Evaluation").

  ATE: associate.py (greedy nearest timestamps, |dt| < max_difference) + evaluate_ate.py's align()
       (Horn's closed form via SVD of the centred cross-covariance; Umeyama's scale for --align sim3).
  RPE: pairs (i, j) over the associated poses, j = closest to t_i + delta (seconds) or i + delta
       (frames); error E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) as in Sturm et al. 2012 ("paper"), and the
       evaluate_rpe.py script's own ordering ominus(ominus(P_j, P_i), ominus(Q_j, Q_i)) ("script").

Usage: tum_eval_reference.py GT.txt EST.txt [--align se3|sim3|none] [--delta 1 --delta-unit s|f]
                             [--max-dt 0.02] [--compare metrics.json]
Written from the published formulas, not copied. Run with /usr/bin/python3 (numpy).
"""
import argparse
import json
import sys

import numpy as np


def read_tum(path):
    rows = []
    for line in open(path):
        line = line.split("#")[0].replace(",", " ").replace("\t", " ").strip()
        if line:
            rows.append([float(v) for v in line.split()])
    a = np.array(rows)
    return a[:, 0], a[:, 1:8]


def pose_matrix(v):
    """tx ty tz qx qy qz qw -> 4x4 (quaternion normalised, as TUM's transform44)."""
    t, q = v[:3], v[3:7] / np.linalg.norm(v[3:7])
    x, y, z, w = q
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    return T


def associate(ta, tb, max_dt):
    """associate.py: all pairs with |a - b| < max_dt, greedily by increasing |dt|, each stamp once."""
    cand = sorted((abs(a - b), i, j) for i, a in enumerate(ta) for j, b in enumerate(tb) if abs(a - b) < max_dt)
    used_a, used_b, out = set(), set(), []
    for _, i, j in cand:
        if i not in used_a and j not in used_b:
            used_a.add(i)
            used_b.add(j)
            out.append((i, j))
    return sorted(out)


def align(model, data, with_scale):
    """evaluate_ate.py align(): model (est, 3xN) onto data (gt, 3xN). Returns R, t, s."""
    mu_m, mu_d = model.mean(1, keepdims=True), data.mean(1, keepdims=True)
    m0, d0 = model - mu_m, data - mu_d
    W = d0 @ m0.T
    U, d, Vh = np.linalg.svd(W)
    S = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vh) < 0:
        S[2, 2] = -1
    R = U @ S @ Vh
    s = 1.0
    if with_scale:  # Umeyama 1991, eq. 42
        s = np.trace(np.diag(d) @ S) / (m0 * m0).sum()
    t = mu_d - s * R @ mu_m
    return R, t, s


def stats(e):
    e = np.asarray(e)
    return {"rmse": float(np.sqrt(np.mean(e * e))), "mean": float(np.mean(e)), "median": float(np.median(e)),
            "std": float(np.std(e)), "min": float(np.min(e)), "max": float(np.max(e)), "count": int(len(e))}


def angle(R):
    return float(np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0)))


def rpe_pairs(t, delta, unit):
    n = len(t)
    if unit == "f":
        return [(i, i + int(delta)) for i in range(n - int(delta))]
    half_gap = 0.5 * np.median(np.diff(t))
    pairs = []
    for i in range(n):
        target = t[i] + delta
        if target > t[-1] + half_gap:
            break
        j = int(np.argmin(np.abs(t - target)))  # closest; ties -> first
        if j > i:
            pairs.append((i, j))
    return pairs


def evaluate(args):
    tg, vg = read_tum(args.gt)
    te, ve = read_tum(args.est)
    matches = associate(te, tg, args.max_dt)
    t = np.array([te[i] for i, _ in matches])
    P = [pose_matrix(ve[i]) for i, _ in matches]
    Q = [pose_matrix(vg[j]) for _, j in matches]
    pe = np.array([T[:3, 3] for T in P]).T
    pg = np.array([T[:3, 3] for T in Q]).T
    if args.align == "none":
        R, tr, s = np.eye(3), np.zeros((3, 1)), 1.0
    else:
        R, tr, s = align(pe, pg, args.align == "sim3")
    ate = np.sqrt(((s * R @ pe + tr - pg) ** 2).sum(0))
    paper, script_t, rot = [], [], []
    for i, j in rpe_pairs(t, args.delta, args.delta_unit):
        dP = np.linalg.inv(P[i]) @ P[j]
        dP[:3, 3] *= s
        dQ = np.linalg.inv(Q[i]) @ Q[j]
        E = np.linalg.inv(dQ) @ dP
        paper.append(np.linalg.norm(E[:3, 3]))
        rot.append(np.degrees(angle(E[:3, :3])))
        # evaluate_rpe.py: ominus(a, b) = inv(a) b; error44 = ominus(ominus(P_j, P_i), ominus(Q_j, Q_i))
        Qs = np.linalg.inv(Q[j]) @ Q[i]
        script_t.append(np.linalg.norm((np.linalg.inv(np.linalg.inv(P[j]) @ P[i]) @ Qs)[:3, 3]))
    return {"matched": len(matches), "scale": float(s), "ate": stats(ate), "rpe_trans_paper": stats(paper),
            "rpe_trans_script": stats(script_t), "rpe_rot_deg": stats(rot)}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("gt")
    ap.add_argument("est")
    ap.add_argument("--align", default="se3", choices=["se3", "sim3", "none"])
    ap.add_argument("--delta", type=float, default=1.0)
    ap.add_argument("--delta-unit", default="s", choices=["s", "f"])
    ap.add_argument("--max-dt", type=float, default=0.02)
    ap.add_argument("--compare", help="metrics.json from s3m eval: report the differences")
    args = ap.parse_args()
    r = evaluate(args)
    print(json.dumps(r, indent=1))
    if args.compare:
        m = json.load(open(args.compare))
        checks = [("matched", m["matched"], r["matched"]),
                  ("ate.rmse_m", m["ate"]["rmse_m"], r["ate"]["rmse"]),
                  ("ate.median_m", m["ate"]["median_m"], r["ate"]["median"]),
                  ("ate.max_m", m["ate"]["max_m"], r["ate"]["max"]),
                  ("rpe.trans_rmse_m", m["rpe"]["trans_rmse_m"], r["rpe_trans_paper"]["rmse"]),
                  ("rpe.rot_rmse_deg", m["rpe"]["rot_rmse_deg"], r["rpe_rot_deg"]["rmse"])]
        worst = 0.0
        for name, a, b in checks:
            rel = abs(a - b) / max(abs(b), 1e-12)
            worst = max(worst, rel if abs(a - b) > 1e-9 else 0.0)
            print(f"{name:18s} s3m {a:.9g}  reference {b:.9g}  |diff| {abs(a - b):.2g}")
        print(f"max relative difference (ignoring |diff| <= 1e-9): {worst:.2g}")
        return 0 if worst < 1e-6 else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
