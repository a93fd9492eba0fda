#!/usr/bin/env python3
"""Where does a trajectory disagree with its ground truth, and which of the two do the images favour?

Two diagnostics behind the 7-Scenes analysis in docs/RESULTS.md ("Why the kitchen ATE stalls"):

  motion   Relative motions over `--step` frames, per camera axis: least-squares slope est/gt and
           RMS ratio of the rotation vector (x = tilt, y = pan, z = roll about the optical axis) and
           of the translation in the first camera's frame. A focal-length error scales pan/tilt but
           not roll; a scale error scales all translations.
  images   For frame pairs (i, i + step): photometric error of colour image i warped into j, and the
           depth error of depth image j moved into i (projective association, as KinectFusion),
           for relative poses T(lam) = T_gt * exp(lam * log(T_gt^-1 * T_est)), lam in --lams:
           lam 0 is the ground truth, lam 1 the estimate. Depth is registered to the colour image
           with depth_px = c + s (colour_px - c) + (f_d b / z, dy) (bench_depth_registration's fit),
           colour focal f_d / s.
  icp      Depth-only point-to-plane ICP (projective association, as KinectFusion) between
           consecutive keyframes of EST's keyframe file, started from EST's relative pose: per-axis
           slopes against the ground truth of EST's and ICP's relative motions, and the keyframe
           ATE of the chained estimate, of chained ICP, and of EST's translations with ICP's
           rotations.

Usage:
  slam_motion_diagnostics.py motion GT.txt EST.txt [--step 10]
  slam_motion_diagnostics.py images DATASET_DIR EST.txt [--step 10] [--every 40] [--lams 0,0.5,1]
                             [--scale 1.1075 --baseline 0.0225 --dy 1.5] [--gt FILE]
  slam_motion_diagnostics.py icp DATASET_DIR EST.txt KEYFRAMES.txt [--gt FILE]
Run with /usr/bin/python3 (numpy and PIL; matplotlib's dependencies). Times are poses matched by timestamp (1 ms).
"""
import argparse
import os

import numpy as np
from PIL import Image


def skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def quat_to_matrix(q):  # q = [qx, qy, qz, qw]
    x, y, z, w = np.asarray(q) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def so3_log(R):
    """Rotation vector [rad] of R (angles below pi)."""
    a = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return 0.5 * v if a < 1e-9 else a / (2 * np.sin(a)) * v


def so3_exp(w):
    a = np.linalg.norm(w)
    K = skew(w)
    if a < 1e-12:
        return np.eye(3) + K
    return np.eye(3) + np.sin(a) / a * K + (1 - np.cos(a)) / a ** 2 * K @ K


def _left_jacobian(w):
    a = np.linalg.norm(w)
    K = skew(w)
    if a < 1e-9:
        return np.eye(3) + 0.5 * K
    return np.eye(3) + (1 - np.cos(a)) / a ** 2 * K + (a - np.sin(a)) / a ** 3 * K @ K


def se3_exp(xi):  # xi = [rho, phi]
    T = np.eye(4)
    T[:3, :3] = so3_exp(xi[3:])
    T[:3, 3] = _left_jacobian(xi[3:]) @ xi[:3]
    return T


def se3_log(T):
    phi = so3_log(T[:3, :3])
    return np.concatenate([np.linalg.solve(_left_jacobian(phi), T[:3, 3]), phi])


def read_tum(path):
    poses = {}
    for line in open(path):
        line = line.split("#")[0].strip()
        if not line:
            continue
        v = [float(x) for x in line.split()]
        T = np.eye(4)
        T[:3, :3] = quat_to_matrix(v[4:8])
        T[:3, 3] = v[1:4]
        poses[round(v[0], 3)] = T
    return poses


def relative(T, a, b):
    return np.linalg.inv(T[a]) @ T[b]


def motion(args):
    gt, est = read_tum(args.gt), read_tum(args.est)
    keys = sorted(set(gt) & set(est))
    pairs = list(zip(keys[:-args.step], keys[args.step:]))
    out = {}
    for name, f in (("rotation", lambda T: so3_log(T[:3, :3])), ("translation", lambda T: T[:3, 3])):
        G = np.array([f(relative(gt, a, b)) for a, b in pairs])
        E = np.array([f(relative(est, a, b)) for a, b in pairs])
        slope = (G * E).sum(0) / (G ** 2).sum(0)
        ratio = np.sqrt((E ** 2).mean(0) / (G ** 2).mean(0))
        out[name] = (slope, ratio)
        print(f"{name:11s} over {args.step} frames, camera axes x y z: slope est/gt {np.round(slope, 3)}  "
              f"rms ratio {np.round(ratio, 3)}  rms gt {np.round(np.sqrt((G ** 2).mean(0)), 4)}")
    return out


def read_list(path):
    return [l.split()[1] for l in open(path) if l.strip() and not l.startswith("#")]


def read_intrinsics(path):
    vals = {}
    for line in open(path):
        line = line.split("#")[0]
        if ":" in line:
            k, v = line.split(":", 1)
            try:
                vals[k.strip()] = float(v)
            except ValueError:
                pass
    return vals


class Pair:
    def __init__(self, d, cam, scale, baseline, dy):
        self.d, self.cam = d, cam
        self.rgb, self.depth = read_list(os.path.join(d, "rgb.txt")), read_list(os.path.join(d, "depth.txt"))
        self.fd, self.cx, self.cy = cam["fx"], cam["cx"], cam["cy"]
        self.fc, self.b, self.dy = cam["fx"] / scale, baseline, dy

    def gray(self, i):
        return np.asarray(Image.open(os.path.join(self.d, self.rgb[i])).convert("L"), dtype=np.float64)

    def raw_depth(self, i):
        return np.asarray(Image.open(os.path.join(self.d, self.depth[i])), dtype=np.float64) / self.cam["depth_factor"]

    def registered_depth(self, i):
        D = self.raw_depth(i)
        v, u = np.mgrid[0:D.shape[0], 0:D.shape[1]].astype(np.float64)
        m = D > 0
        z = D[m]
        uc = np.round(self.cx + self.fc * ((u[m] - self.cx) / self.fd - self.b / z)).astype(int)
        vc = np.round(self.cy + self.fc * ((v[m] - self.cy - self.dy) / self.fd)).astype(int)
        R = np.full(D.shape, np.inf)
        ok = (uc >= 0) & (uc < D.shape[1]) & (vc >= 0) & (vc < D.shape[0])
        np.minimum.at(R, (vc[ok], uc[ok]), z[ok])  # z-buffer: the nearest surface wins
        R[~np.isfinite(R)] = 0
        return R


def bilinear(I, x, y):
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    ax, ay = x - x0, y - y0
    return (I[y0, x0] * (1 - ax) * (1 - ay) + I[y0, x0 + 1] * ax * (1 - ay) + I[y0 + 1, x0] * (1 - ax) * ay
            + I[y0 + 1, x0 + 1] * ax * ay)


def warp(T_j_i, Z, f, cx, cy, step=2):
    v, u = np.mgrid[2:Z.shape[0] - 2:step, 2:Z.shape[1] - 2:step]
    z = Z[v, u]
    m = z > 0
    X = np.stack([(u[m] - cx) * z[m] / f, (v[m] - cy) * z[m] / f, z[m], np.ones(m.sum())])
    Y = T_j_i @ X
    x, y = Y[0] / Y[2] * f + cx, Y[1] / Y[2] * f + cy
    ok = (x >= 1) & (x < Z.shape[1] - 2) & (y >= 1) & (y < Z.shape[0] - 2) & (Y[2] > 0)
    return u[m][ok], v[m][ok], x[ok], y[ok], Y[2][ok]


def photometric(P, Gi, Gj, Ri, T_i_j):
    """Gi, Gj: grey images i, j; Ri: depth i registered to colour."""
    u, v, x, y, _ = warp(np.linalg.inv(T_i_j), Ri, P.fc, P.cx, P.cy)
    return np.mean(np.minimum(np.abs(Gi[v, u] - bilinear(Gj, x, y)), 50))  # grey levels, capped


def depth_error(P, Di, Dj, T_i_j):
    """Di, Dj: raw depth images i, j."""
    _, _, x, y, z = warp(T_i_j, Dj, P.fd, P.cx, P.cy, step=4)
    xi, yi = np.round(x).astype(int), np.round(y).astype(int)
    d = Di[yi, xi]
    return np.median(np.abs(d[d > 0] - z[d > 0]))


def images(args):
    gt = read_tum(args.gt or os.path.join(args.dataset, "groundtruth.txt"))
    est = read_tum(args.est)
    P = Pair(args.dataset, read_intrinsics(os.path.join(args.dataset, "camera.yaml")), args.scale, args.baseline, args.dy)
    stamps = [round(float(l.split()[0]), 3) for l in open(os.path.join(args.dataset, "rgb.txt"))
              if l.strip() and not l.startswith("#")]
    lams = [float(x) for x in args.lams.split(",")]
    frames = [i for i in range(0, len(stamps) - args.step, args.every)
              if stamps[i] in gt and stamps[i + args.step] in gt and stamps[i] in est and stamps[i + args.step] in est]
    print(f"{len(frames)} pairs, step {args.step}; colour focal {P.fc:.1f} px (depth {P.fd:.1f} px / {args.scale})")
    ph = {lam: [] for lam in lams}
    de = {lam: [] for lam in lams}
    for i in frames:  # each pair's images are read (and registered) once for every lam
        j = i + args.step
        Gi, Gj, Ri, Di, Dj = P.gray(i), P.gray(j), P.registered_depth(i), P.raw_depth(i), P.raw_depth(j)
        Tg, Te = relative(gt, stamps[i], stamps[j]), relative(est, stamps[i], stamps[j])
        for lam in lams:
            T = Tg @ se3_exp(lam * se3_log(np.linalg.inv(Tg) @ Te))
            ph[lam].append(photometric(P, Gi, Gj, Ri, T))
            de[lam].append(depth_error(P, Di, Dj, T))
    for lam in lams:
        label = "ground truth" if lam == 0 else "estimate" if lam == 1 else "blend"
        print(f"lam {lam:4.2f} ({label:12s}): photometric {np.mean(ph[lam]):6.2f} grey levels  "
              f"depth median {np.mean(de[lam]) * 1000:6.2f} mm")


def grid_cloud(D, cam, stride, max_depth=4.0):
    v, u = np.mgrid[stride // 2:D.shape[0]:stride, stride // 2:D.shape[1]:stride]
    z = D[v, u].copy()
    z[z > max_depth] = 0
    return np.stack([(u - cam["cx"]) * z / cam["fx"], (v - cam["cy"]) * z / cam["fy"], z], -1)


def grid_normals(P, max_edge_ratio=0.05):
    N = np.zeros_like(P)
    n = np.cross(P[1:-1, 2:] - P[1:-1, :-2], P[2:, 1:-1] - P[:-2, 1:-1])
    n /= np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-12)
    z, c = P[..., 2], P[1:-1, 1:-1, 2]
    ok = c > 0
    for nb in (z[1:-1, 2:], z[1:-1, :-2], z[2:, 1:-1], z[:-2, 1:-1]):
        ok &= (nb > 0) & (np.abs(nb - c) < max_edge_ratio * c)
    n[~ok] = 0
    facing = np.sign((n * P[1:-1, 1:-1]).sum(-1, keepdims=True))
    N[1:-1, 1:-1] = -n * np.where(facing == 0, 1, facing)
    return N


def icp(D_target, D_source, T0, cam, iterations=20):
    """T (source camera -> target camera) minimising point-to-plane distances, Huber at 2 cm."""
    Pt = grid_cloud(D_target, cam, 4)
    Nt = grid_normals(Pt)
    Ps = grid_cloud(D_source, cam, 8).reshape(-1, 3)
    Ps = Ps[Ps[:, 2] > 0]
    T = T0.copy()
    for _ in range(iterations):
        q = Ps @ T[:3, :3].T + T[:3, 3]
        u = np.floor((q[:, 0] / q[:, 2] * cam["fx"] + cam["cx"]) / 4).astype(int)
        v = np.floor((q[:, 1] / q[:, 2] * cam["fy"] + cam["cy"]) / 4).astype(int)
        ok = (q[:, 2] > 0.1) & (u >= 0) & (u < Pt.shape[1]) & (v >= 0) & (v < Pt.shape[0])
        u, v, q = u[ok], v[ok], q[ok]
        n, p = Nt[v, u], Pt[v, u]
        has = np.abs(n).sum(1) > 0
        n, p, q = n[has], p[has], q[has]
        e = (n * (q - p)).sum(1)
        near = np.abs(e) < 0.05
        n, q, e = n[near], q[near], e[near]
        J = np.concatenate([n, np.cross(q, n)], 1)  # T <- exp(xi) T: d e / d xi = [n, q x n]
        w = np.where(np.abs(e) > 0.02, 0.02 / np.abs(e), 1.0)
        xi = -np.linalg.solve((J * w[:, None]).T @ J + 1e-9 * np.eye(6), (J * w[:, None]).T @ e)
        T = se3_exp(xi) @ T
        if np.linalg.norm(xi) < 1e-6:
            break
    return T


def ate_se3(P, Q):
    X, Y = P - P.mean(0), Q - Q.mean(0)
    U, _, Vt = np.linalg.svd(Y.T @ X)
    D = np.diag([1, 1, np.sign(np.linalg.det(U @ Vt))])
    return np.sqrt(((((U @ D @ Vt) @ X.T).T - Y) ** 2).sum(1).mean())


def icp_chain(args):
    gt = read_tum(args.gt or os.path.join(args.dataset, "groundtruth.txt"))
    est = read_tum(args.est)
    kfs = [k for k in sorted(read_tum(args.keyframes)) if k in est and k in gt]
    cam = read_intrinsics(os.path.join(args.dataset, "camera.yaml"))
    P = Pair(args.dataset, cam, 1.0, 0.0, 0.0)
    index = {round(float(l.split()[0]), 3): i for i, l in enumerate(
        l for l in open(os.path.join(args.dataset, "depth.txt")) if l.strip() and not l.startswith("#"))}
    chains = {"estimate": [np.eye(4)], "depth ICP": [np.eye(4)], "estimate + ICP rotations": [np.eye(4)]}
    rot = {"gt": [], "estimate": [], "depth ICP": []}
    tra = {"gt": [], "estimate": [], "depth ICP": []}
    for a, b in zip(kfs[:-1], kfs[1:]):
        Te, Tg = relative(est, a, b), relative(gt, a, b)
        Td = icp(P.raw_depth(index[a]), P.raw_depth(index[b]), Te, cam)
        Tm = Te.copy()
        Tm[:3, :3] = Td[:3, :3]
        for name, T in (("estimate", Te), ("depth ICP", Td), ("estimate + ICP rotations", Tm)):
            chains[name].append(chains[name][-1] @ T)
        for name, T in (("gt", Tg), ("estimate", Te), ("depth ICP", Td)):
            rot[name].append(so3_log(T[:3, :3]))
            tra[name].append(T[:3, 3])
    G = {k: np.array(v) for k, v in rot.items()}
    Gt = {k: np.array(v) for k, v in tra.items()}
    for name in ("estimate", "depth ICP"):
        sr = (G["gt"] * G[name]).sum(0) / (G["gt"] ** 2).sum(0)
        st = (Gt["gt"] * Gt[name]).sum(0) / (Gt["gt"] ** 2).sum(0)
        print(f"{name:10s} keyframe-to-keyframe slope vs gt: rotation {np.round(sr, 3)}  translation {np.round(st, 3)}")
    Q = np.array([gt[k][:3, 3] for k in kfs])
    for name, c in chains.items():
        print(f"chained {name:26s}: keyframe ATE {ate_se3(np.array([T[:3, 3] for T in c]), Q) * 100:.2f} cm")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("motion")
    m.add_argument("gt")
    m.add_argument("est")
    m.add_argument("--step", type=int, default=10)
    i = sub.add_parser("images")
    i.add_argument("dataset")
    i.add_argument("est")
    i.add_argument("--gt")
    i.add_argument("--step", type=int, default=10)
    i.add_argument("--every", type=int, default=40)
    i.add_argument("--lams", default="0,0.5,1")
    i.add_argument("--scale", type=float, default=1.1075)
    i.add_argument("--baseline", type=float, default=0.0225)
    i.add_argument("--dy", type=float, default=1.5)
    c = sub.add_parser("icp")
    c.add_argument("dataset")
    c.add_argument("est")
    c.add_argument("keyframes")
    c.add_argument("--gt")
    args = ap.parse_args()
    {"motion": motion, "images": images, "icp": icp_chain}[args.cmd](args)


if __name__ == "__main__":
    main()
