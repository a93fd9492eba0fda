#!/usr/bin/python3
"""Plots and a one-page HTML report for an `s3m run` output directory.

Usage: /usr/bin/python3 tools/plot_report.py OUT_DIR

Reads what `s3m run` wrote into OUT_DIR:
  metrics.json     numbers, class list, per-class IoU, paths of the inputs
  map.ply          semantic map voxels (x y z, colour, label, confidence)
  report/*.png     trajectory X-Y / X-Z, RPE over time and ATE plots, drawn before this script by
                   tools/plot_trajectories.py (the evaluator's script, so `s3m eval` and `s3m run`
                   draw trajectories the same way)
  report/viewer/   the interactive 3-D map (src/s3m/viewer; three.js copied from libjs-three)
  report/camera_views.json + camera_views/*.png   a few frames: colour, depth, segmentation, map labels
and writes report/map_topdown.png, report/class_iou.png and the one-page report/report.html:
numbers first, then the 3-D view, the camera views and the plots.

matplotlib (Debian's python3-matplotlib) is used for the same reason evo uses it: real axes,
legends and equal-aspect plots in a few lines, and PNGs anyone can open.
"""
import html
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

def read_ply(path):
    """Minimal PLY reader (ascii and binary_little_endian, vertex element only) -> dict of arrays."""
    types = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "<i2", "int16": "<i2",
             "ushort": "<u2", "uint16": "<u2", "int": "<i4", "int32": "<i4", "uint": "<u4",
             "uint32": "<u4", "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8"}
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, count, props, element = None, 0, [], None
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: PLY header has no end_header")
            words = line.decode("ascii", "replace").split()
            if not words:
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                element = words[1]
                if element == "vertex":
                    count = int(words[2])
            elif words[0] == "property" and element == "vertex":
                if words[1] == "list":
                    raise ValueError(f"{path}: list properties on vertices are not supported")
                props.append((words[2], types[words[1]]))
            elif words[0] == "end_header":
                break
        dtype = np.dtype(props)
        if fmt == "binary_little_endian":
            data = np.frombuffer(f.read(dtype.itemsize * count), dtype=dtype, count=count)
        elif fmt == "ascii":
            data = np.loadtxt(f, max_rows=count, ndmin=2)
            data = {name: data[:, i] for i, (name, _) in enumerate(props)}
        else:
            raise ValueError(f"{path}: unsupported PLY format {fmt}")
    return {name: np.asarray(data[name]) for name, _ in props}


def class_palette(metrics):
    """id -> (name, (r, g, b) in 0..1) from metrics.json's class list."""
    out = {}
    for c in metrics.get("classes", []):
        out[int(c["id"])] = (c["name"], tuple(v / 255.0 for v in c["rgb"]))
    return out


def plot_map_topdown(out_dir, report_dir, palette):
    """Top-down view: per map column the highest non-ceiling voxel, coloured by its class."""
    path = os.path.join(out_dir, "map.ply")
    if not os.path.exists(path):
        return
    ply = read_ply(path)
    if "x" not in ply or len(ply["x"]) == 0:
        return
    key = next((k for k in ("label", "class", "class_id") if k in ply), None)
    pts = np.stack([ply["x"], ply["y"], ply["z"]], 1).astype(float)
    ids = ply[key].astype(int) if key else np.zeros(len(pts), int)
    if key and palette:
        colours = np.array([palette.get(i, ("?", (1, 0, 1)))[1] for i in ids])
    else:
        colours = np.stack([ply[c] for c in ("red", "green", "blue")], 1) / 255.0
    up = vertical_axis(ids, *pts.T)
    horiz = [a for a in (0, 1, 2) if a != up]
    keep = ids != 3 if key else np.ones(len(pts), bool)  # the ceiling (id 3) would hide the room
    pts, ids, colours = pts[keep], ids[keep], colours[keep]
    if len(pts) == 0:
        return
    # Rasterise at the map resolution (the smallest spacing of voxel centres): the highest voxel
    # of each column wins, so walls and furniture tops show as they do from above.
    res = voxel_size(pts)
    cells = np.floor((pts[:, horiz] - pts[:, horiz].min(0)) / res + 0.5).astype(int)
    h = height_sign(pts[:, up], ids) * pts[:, up]
    order = np.argsort(h)  # later (higher) voxels overwrite lower ones
    img = np.ones((cells[:, 1].max() + 1, cells[:, 0].max() + 1, 3))
    img[cells[order, 1], cells[order, 0]] = colours[order]
    lo = pts[:, horiz].min(0) - res / 2
    extent = [lo[0], lo[0] + img.shape[1] * res, lo[1], lo[1] + img.shape[0] * res]
    fig, ax = plt.subplots(figsize=(7.5, 6))
    ax.imshow(img, origin="lower", extent=extent, interpolation="nearest")
    names = "xyz"
    ax.set_xlabel(f"{names[horiz[0]]} [m]")
    ax.set_ylabel(f"{names[horiz[1]]} [m]")
    ax.set_title(f"Semantic map from above ({len(ply['x'])} voxels of {res * 100:.0f} cm; ceiling hidden)")
    if key and palette:
        present = sorted(set(ids.tolist()))
        handles = [plt.Line2D([], [], marker="s", ls="", color=palette[i][1], label=palette[i][0])
                   for i in present if i in palette]
        ax.legend(handles=handles, loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(report_dir, "map_topdown.png"), dpi=110)
    plt.close(fig)


def voxel_size(pts):
    """Map resolution from the voxel centres: the smallest non-zero gap between sorted coordinates."""
    gaps = np.diff(np.unique(np.round(pts[:, 0], 5)))
    gaps = gaps[gaps > 1e-4]
    return float(np.min(gaps)) if len(gaps) else 0.05


def vertical_axis(ids, x, y, z):
    """The world's vertical axis: the one along which floor (2) and ceiling (3) voxels differ most;
    without those classes, the axis with the smallest extent (rooms are wider than tall)."""
    pts = np.stack([x, y, z], 1)
    floor, ceil = pts[ids == 2], pts[ids == 3]
    if len(floor) > 10 and len(ceil) > 10:
        return int(np.argmax(np.abs(np.median(ceil, 0) - np.median(floor, 0))))
    if len(floor) > 10:
        return int(np.argmin(np.std(floor, 0)))  # the floor is flat along the vertical
    return int(np.argmin(np.ptp(pts, 0)))


def height_sign(h, ids):
    """+1 if larger coordinates are higher (floor below the rest), -1 otherwise (camera y-down worlds)."""
    floor = h[ids == 2]
    if len(floor) > 10:
        return 1.0 if np.median(floor) <= np.median(h) else -1.0
    return 1.0


def plot_class_iou(metrics, report_dir):
    bars = {}
    for section, label in (("segmentation", "single frame"), ("map", "fused map (3-D voxels)")):
        per_class = metrics.get(section, {}).get("per_class_iou", {})
        if per_class:
            bars[label] = per_class
    rep = metrics.get("map", {}).get("reprojected", {}).get("per_class_iou", {})
    if rep:
        bars["fused map seen from the frames"] = {n: v["map"] for n, v in rep.items()}
    if not bars:
        return
    names = sorted({n for v in bars.values() for n in v})
    fig, ax = plt.subplots(figsize=(max(6, 0.55 * len(names) + 2), 4))
    width = 0.8 / len(bars)
    for i, (label, per_class) in enumerate(bars.items()):
        vals = [per_class.get(n, np.nan) for n in names]
        ax.bar(np.arange(len(names)) + (i - (len(bars) - 1) / 2) * width, vals, width, label=label)
    ax.set_xticks(np.arange(len(names)))
    ax.set_xticklabels(names, rotation=45, ha="right")
    ax.set_ylabel("IoU")
    ax.set_ylim(0, 1.18)  # headroom for the legend row above the bars
    ax.set_yticks(np.linspace(0, 1, 6))
    ax.grid(axis="y", alpha=0.3)
    ax.legend(loc="upper center", ncol=len(bars), fontsize="small", frameon=False)
    ax.set_title("Per-class IoU")
    fig.tight_layout()
    fig.savefig(os.path.join(report_dir, "class_iou.png"), dpi=110)
    plt.close(fig)


def fmt_value(v):
    if isinstance(v, float):
        return f"{v:.4g}"
    return html.escape(str(v))


def summary_rows(metrics):
    rows = [("frames", metrics.get("frames")), ("keyframes", metrics.get("keyframes")),
            ("frames/s (wall clock)", metrics.get("fps")),
            # Unreadable image files the run skipped (s3m run names each in metrics.json).
            ("frames skipped (unreadable files)", ", ".join(
                str(f["index"]) for f in metrics.get("skipped_frames", [])[:20])
             + (" ..." if len(metrics.get("skipped_frames", [])) > 20 else "") or None),
            # A depth factor that looks off (s3m run's depth-scale check; absent when plausible).
            ("depth scale warning", metrics.get("inputs", {}).get("depth_scale_warning")),
            ("map voxels", metrics.get("map", {}).get("voxels")),
            ("map classes (share of labelled voxels)", ", ".join(
                f"{c['class']} {100 * c['share']:.0f} %" for c in metrics.get("map", {}).get("class_voxels", [])[:8])
             or None)]
    traj = metrics.get("trajectory", {})
    if "ate_rmse_m" in traj:
        rows += [("ATE RMSE [m]", traj["ate_rmse_m"]), ("RPE trans RMSE [m]", traj.get("rpe_trans_rmse_m")),
                 ("RPE rot RMSE [deg]", traj.get("rpe_rot_rmse_deg"))]
    if "miou" in metrics.get("segmentation", {}):
        rows.append(("segmentation mIoU (single frame, all pixels)", metrics["segmentation"]["miou"]))
    rep = metrics.get("map", {}).get("reprojected", {})
    if "miou" in rep:
        rows.append(("image mIoU, single frames (pixels the map covers)", rep["frame_miou"]))
        rows.append(("image mIoU, fused map projected into the same frames", rep["miou"]))
    if "miou" in metrics.get("map", {}):
        rows.append(("3-D map mIoU vs ground-truth voxels", metrics["map"]["miou"]))
    return [(k, v) for k, v in rows if v is not None]


STYLE = """
body{font-family:sans-serif;max-width:1280px;margin:auto;padding:0 12px;color:#222}
h2{margin:22px 0 8px;border-bottom:1px solid #ddd}
td,th{padding:2px 10px;text-align:left;vertical-align:top}
.numbers{display:flex;flex-wrap:wrap;gap:28px;align-items:flex-start}
.numbers table{border-collapse:collapse}
.numbers tr:nth-child(even){background:#f6f6f6}
.plots{display:grid;grid-template-columns:1fr 1fr;gap:8px}
.plots img{width:100%;border:1px solid #ddd}
.plots img:last-child:nth-child(odd){grid-column:span 2;width:60%;justify-self:center}
.views{display:grid;grid-template-columns:auto repeat(4,1fr);gap:4px;align-items:center}
.views img{width:100%;display:block}
.views .head{font-weight:bold;text-align:center}
.views .frame{font-size:12px;color:#555;padding-right:6px;white-space:nowrap}
.note{color:#555;font-size:13px}
"""


def numbers_section(metrics):
    """The run's numbers first: inputs, the summary and the per-stage timings, side by side."""
    inputs = metrics.get("inputs", {})
    parts = ["<p class='note'>" + "<br>".join(f"<b>{html.escape(k)}</b>: {fmt_value(v)}" for k, v in inputs.items()) + "</p>",
             "<div class='numbers'><table>" + "".join(f"<tr><th>{html.escape(k)}</th><td>{fmt_value(v)}</td></tr>"
                                                      for k, v in summary_rows(metrics)) + "</table>"]
    timings = metrics.get("timings_ms", {})
    if timings:
        parts.append("<table><tr><th>stage [ms]</th><th>mean</th><th>p50</th><th>p95</th><th>count</th></tr>")
        for stage, t in timings.items():
            parts.append(f"<tr><td>{html.escape(stage)}</td><td>{t['mean']:.2f}</td><td>{t['p50']:.2f}</td>"
                         f"<td>{t['p95']:.2f}</td><td>{t['count']}</td></tr>")
        parts.append("</table>")
    parts.append("</div>")
    return parts


def viewer_section(report_dir):
    """The interactive 3-D map (report/viewer/, written by s3m before this script: src/s3m/viewer)."""
    viewer = os.path.join(report_dir, "viewer")
    if not os.path.exists(os.path.join(viewer, "map_data.js")):
        return []
    parts = ["<h2>The map in 3-D</h2>",
             "<p class='note'>Drag to orbit, right-drag to pan, wheel to zoom; click a voxel for its labels. "
             "<a href='viewer/index.html'>Open on its own page</a>.</p>",
             "<link rel='stylesheet' href='viewer/viewer.css'><div id='s3m-viewer'></div>"]
    if not os.path.exists(os.path.join(viewer, "three.min.js")):
        parts.append("<p class='note'>The 3-D view needs three.js: <code>apt-get install libjs-three</code>, then run again.</p>")
    parts += ["<script src='viewer/three.min.js'></script>", "<script src='viewer/OrbitControls.js'></script>",
              "<script src='viewer/map_data.js'></script>", "<script src='viewer/viewer_voxels.js'></script>", "<script src='viewer/viewer.js'></script>",
              "<script src='viewer/viewer_pick.js'></script>",
              "<script>S3MViewer.start(document.getElementById('s3m-viewer'), window.S3M_VIEWER_DATA);</script>"]
    return parts


def camera_views_section(report_dir):
    """Rows of colour | depth | segmentation | map labels for a few frames (report/camera_views.json)."""
    path = os.path.join(report_dir, "camera_views.json")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        frames = json.load(f).get("frames", [])
    if not frames:
        return []
    cols = (("colour", "colour"), ("depth", "depth (near blue, far red)"), ("segmentation", "segmentation"),
            ("map", "final map's labels seen from this pose"))
    parts = ["<h2>What the camera saw</h2>", "<div class='views'><div></div>"]
    parts += [f"<div class='head'>{label}</div>" for _, label in cols]
    for fr in frames:
        parts.append(f"<div class='frame'>frame {fr['index']}<br>t={fr['t_s']:.2f} s</div>")
        for key, label in cols:
            parts.append(f"<img src='{html.escape(fr[key])}' alt='{label}'>" if key in fr else "<div class='note'>n/a</div>")
    parts.append("</div>")
    return parts


def plots_section(report_dir):
    """Trajectory, error and map plots two per row (an odd last one centred): no holes."""
    pngs = [p for p in ("trajectory_xy.png", "trajectory_xz.png", "rpe.png", "ate.png", "map_topdown.png", "class_iou.png")
            if os.path.exists(os.path.join(report_dir, p))]
    if not pngs:
        return []
    return ["<h2>Trajectory, errors and map</h2><div class='plots'>"] + \
        [f"<img src='{p}' alt='{p}'>" for p in pngs] + ["</div>"]


def write_html(metrics, report_dir):
    parts = ["<!doctype html><html><head><meta charset='utf-8'><title>s3m report</title>",
             f"<style>{STYLE}</style></head><body>", "<h1>s3m run report</h1>"]
    parts += numbers_section(metrics)
    parts += viewer_section(report_dir)
    parts += camera_views_section(report_dir)
    parts += plots_section(report_dir)
    parts.append("<p>Full numbers: <a href='../metrics.json'>metrics.json</a></p></body></html>")
    tmp = os.path.join(report_dir, "report.html.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(parts))
    os.replace(tmp, os.path.join(report_dir, "report.html"))


def main(argv):
    if len(argv) != 2:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    out_dir = argv[1]
    report_dir = os.path.join(out_dir, "report")
    os.makedirs(report_dir, exist_ok=True)
    with open(os.path.join(out_dir, "metrics.json")) as f:
        metrics = json.load(f)
    palette = class_palette(metrics)
    plot_map_topdown(out_dir, report_dir, palette)
    plot_class_iou(metrics, report_dir)
    write_html(metrics, report_dir)
    print(os.path.join(report_dir, "report.html"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
