#!/usr/bin/python3
"""SLAM benchmark matrix (issue #20): simulator scenes x trajectories x noise x seeds, plus the shared
7-Scenes kitchen, run through the `s3m` CLI exactly as a user would, scored with `s3m eval`.

  s3m sim --scene S --trajectory T --frames N --seed K [--no-noise] --out CACHE/...   (once, cached)
  s3m run SEQ --slam-only --no-report [--deterministic] --out WORK/...                (no --config)
  s3m eval --gt SEQ/groundtruth.txt --est OUT/trajectory_camera.txt --align se3|sim3 --delta 1 --delta-unit s

Sequences are rendered once into --cache, keyed by their sim parameters (directory name); a changed
simulator needs --rerender. Deterministic runs go through a pool of --jobs workers; threaded runs
(their accuracy depends on timing) run one at a time after them. Timings are only trusted from
--jobs 1 (otherwise marked * = under load). Examples:

  bench/slam_matrix.py --binary build/src/apps/s3m                              # full matrix
  bench/slam_matrix.py --binary OLD_S3M --binary NEW_S3M --quick --modes deterministic --jobs 2
  bench/slam_matrix.py --binary NEW_S3M --baseline old.json --quick              # against a saved run
  bench/slam_matrix.py --binary S3M --scenes office --trajectories figure8,loop --noise off --seeds 1
  bench/slam_matrix.py --binary S3M --stride 6 --noise on --modes deterministic   # a 5 Hz camera

--stride N replays every Nth frame of each sequence at 30/N Hz (tools/resequence_tum.py, links only,
cached next to the sequences): a camera that drops frames or runs slowly; row ids get ' @every N'.

Sensor axis (--sensor): the simulator's sensor profile. ideal and default are the rows this matrix
always had (ids and cache directories 'clean' and 'noisy', as --noise off/on selects them);
realistic is `s3m sim --sensor-profile realistic` (a Kinect v1's lies: colour-depth offset, jitter,
rolling shutter, motion blur, disparity steps, edge fattening, misregistration); offset20 is the
default sensor with depth 20 ms after colour. "Wrong config" axis (--slam-noise 0.3,3): the SLAM
config's depth noise model at that multiple of the simulator's truth, through a two-line --config
(factor 1: no --config; the built-in model is the truth). --quick-sensors: 7 rows on these axes,
including the handheld_pan flight (~70 deg/s median turn rate) with the 20 ms offset.

  bench/slam_matrix.py --binary S3M --quick-sensors --modes deterministic --no-kitchen --jobs 1
  bench/slam_matrix.py --binary S3M --sensor default,realistic --scenes office --seeds 1 --no-kitchen
"""
import argparse
import concurrent.futures as cf
import datetime
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import slam_matrix_report as rep  # noqa: E402
from slam_matrix_rows import (KITCHEN, QUICK, SEEDS, SENSORS, kitchen_rows, seq_dir, sim_rows,  # noqa: E402
                              slam_noise_config)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def replay_dir(args, row):
    """The sequence a row runs on: the rendered (or kitchen) one, or every --stride'th frame of it."""
    src = seq_dir(args, row)
    if args.stride == 1:
        return src
    out = os.path.join(args.cache, f"every{args.stride}", os.path.basename(os.path.normpath(src)))
    if not os.path.exists(os.path.join(out, "associations.txt")):
        tmp = out + ".tmp"
        shutil.rmtree(tmp, ignore_errors=True)
        cmd = [sys.executable, os.path.join(ROOT, "tools", "resequence_tum.py"), src, tmp, "--stride",
               str(args.stride), "--fps", str(30.0 / args.stride)]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"resequence_tum.py exit {p.returncode}: {p.stderr.strip()[-300:]}")
        shutil.rmtree(out, ignore_errors=True)
        os.rename(tmp, out)
    return out


def binary_info(path):
    path = os.path.abspath(path)
    if not os.access(path, os.X_OK):
        sys.exit(f"slam_matrix: '{path}' is not an executable s3m binary")
    with open(path, "rb") as f:
        sha = hashlib.sha256(f.read()).hexdigest()[:12]
    return {"path": path, "sha256_12": sha}


def render(args, row):
    """Render one sequence into the cache unless it is there (atomic: .tmp directory, then rename)."""
    out = seq_dir(args, row)
    stamp = os.path.join(out, "matrix_stamp.json")
    if os.path.exists(stamp) and not args.rerender:
        st = read_json(stamp)
        turn = st.get("turn_deg_s") or rep.turn_rate_deg_s(read_tum(os.path.join(out, "groundtruth.txt")))
        return {"row": row["row"], "cached": True, "seconds": st.get("render_s"), "turn_deg_s": turn,
                "sim_sha256_12": st.get("sim_binary", {}).get("sha256_12")}
    tmp = out + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    cmd = [args.sim_binary["path"], "sim", "--scene", row["scene"], "--trajectory", row["trajectory"],
           "--frames", str(args.frames), "--seed", str(row["seed"])] + SENSORS[row["sensor"]][1] + ["--out", tmp]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except (OSError, subprocess.TimeoutExpired) as e:
        return {"row": row["row"], "error": f"sim: {type(e).__name__}: {e}", "seconds": time.time() - t0}
    secs = time.time() - t0
    if p.returncode != 0:
        return {"row": row["row"], "error": f"sim exit {p.returncode}: {p.stderr.strip()[-300:]}", "seconds": secs}
    turn = rep.turn_rate_deg_s(read_tum(os.path.join(tmp, "groundtruth.txt")))
    with open(os.path.join(tmp, "matrix_stamp.json"), "w") as f:
        json.dump({"command": cmd[1:], "sim_binary": args.sim_binary, "render_s": secs, "turn_deg_s": turn,
                   "date": datetime.datetime.now().isoformat(timespec="seconds")}, f, indent=1)
    shutil.rmtree(out, ignore_errors=True)
    os.rename(tmp, out)
    return {"row": row["row"], "cached": False, "seconds": secs, "turn_deg_s": turn}


def read_tum(path):
    with open(path) as f:
        return [tuple(float(x) for x in line.split()) for line in f if line.strip() and not line.startswith("#")]


def tracking_ms(timings):
    """Mean ms of SLAM's tracker alone (metrics.json timings_ms.slam_tracking); older binaries only
    have the pipeline's `track` stage, which in --deterministic runs includes local mapping."""
    for stage in ("slam_tracking", "track"):
        if stage in timings:
            return timings[stage].get("mean")
    return None


def read_json(path):
    with open(path) as f:
        return json.load(f)


def score(args, seq, traj, out):
    """ATE (se3) and RPE over 1 s, and the Sim3 scale, by `s3m eval` (metrics only)."""
    res = {}
    for align in ("se3", "sim3"):
        d = os.path.join(out, "eval_" + align)
        cmd = [args.eval_binary, "eval", "--gt", os.path.join(seq, "groundtruth.txt"), "--est", traj,
               "--align", align, "--delta", "1", "--delta-unit", "s", "--out", d, "--no-plots"]
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        if p.returncode != 0:
            raise RuntimeError(f"eval --align {align} exit {p.returncode}: {p.stderr.strip()[-300:]}")
        m = read_json(os.path.join(d, "metrics.json"))
        if align == "se3":
            res.update(ate_cm=100 * m["ate"]["rmse_m"], rpe_cm=100 * m["rpe"]["trans_rmse_m"],
                       rpe_deg=m["rpe"]["rot_rmse_deg"], matched=m.get("matched"),
                       est_poses=m["estimates"][0].get("est_poses"), gt_poses=m["estimates"][0].get("gt_poses"))
        else:
            res.update(scale=m["estimates"][0]["alignment"]["scale"], ate_sim3_cm=100 * m["ate"]["rmse_m"])
    return res


def run_once(args, binary, row, mode, k, under_load):
    """One `s3m run` + scoring; every failure becomes the run's error string."""
    out = os.path.join(args.work, binary["label"], row["row"].replace("/", "_").replace(" ", "_")
                       .replace("(", "").replace(")", ""), f"{mode[:3]}_{k}")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    seq = row.get("seq") or seq_dir(args, row)
    cmd = [binary["path"], "run", seq, "--slam-only", "--no-report", "--out", out]
    cmd += ["--deterministic"] if mode == "deterministic" else []
    config = slam_noise_config(args, row["slam_noise"]) if row.get("slam_noise", 1) != 1 else row.get("config")
    cmd += ["--config", config] if config else []
    r = {"out": out, "command": " ".join(cmd), "load_before": os.getloadavg()[0], "timing_under_load": under_load,
         "error": None}
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout, start_new_session=True)
        r["wall_s"] = time.time() - t0
        with open(out + ".log", "w") as f:
            f.write(p.stdout + p.stderr)
        if p.returncode != 0:
            raise RuntimeError(f"run exit {p.returncode}: {(p.stderr or p.stdout).strip()[-300:]}")
        m = read_json(os.path.join(out, "metrics.json"))
        tr = m.get("tracking", {})
        r.update(lost=tr.get("states", {}).get("LOST", 0), relocalised=len(tr.get("relocalised_frames", [])),
                 states=tr.get("states"), lost_ranges=tr.get("lost_frames"), keyframes=m.get("keyframes"),
                 frames=m.get("frames"), track_ms=tracking_ms(m.get("timings_ms", {})),
                 run_ate_cm=100 * m["trajectory"]["ate_rmse_m"] if "ate_rmse_m" in m.get("trajectory", {}) else None,
                 config=m.get("inputs", {}).get("config"), run_mode=m.get("inputs", {}).get("mode"))
        r.update(score(args, seq, os.path.join(out, "trajectory_camera.txt"), out))
        for big in ("slam_map.bin", "kept_clouds.bin"):  # tens of MB per run; not needed to score
            if os.path.exists(os.path.join(out, big)) and not args.keep_maps:
                os.remove(os.path.join(out, big))
    except subprocess.TimeoutExpired:
        r["wall_s"] = time.time() - t0
        r["error"] = f"timeout after {args.timeout} s"
    except Exception as e:  # noqa: BLE001  (a failed run is a row, not a crashed script)
        r["wall_s"] = time.time() - t0
        r["error"] = e.args[0] if isinstance(e, RuntimeError) else f"{type(e).__name__}: {e}"
    if args.verify_determinism and mode == "deterministic" and k == 1 and r["error"] is None:
        again = run_once(args, binary, row, mode, 2, under_load)
        same = all(open(os.path.join(out, f), "rb").read() == open(os.path.join(again["out"], f), "rb").read()
                   for f in ("trajectory_camera.txt", "keyframes.txt", "frames.txt")) if again["error"] is None else None
        r["identical_on_rerun"] = same
    return r


class Progress:
    def __init__(self, total):
        self.total, self.done, self.t0, self.spent = total, 0, time.time(), 0.0

    def tick(self, what, r, jobs):
        self.done += 1
        el = time.time() - self.t0
        eta = el / self.done * (self.total - self.done)
        res = r["error"] or f"ATE {r['ate_cm']:.2f} cm, scale {r['scale']:.4f}, lost {r['lost']}, KF {r['keyframes']}"
        print(f"[{self.done}/{self.total}] {el / 60:.1f} min, ETA {eta / 60:.1f} min  {what}: {res} "
              f"({r['wall_s']:.1f} s)", file=sys.stderr, flush=True)


def run_all(args, binaries, rows):
    """Every (binary, row, mode, k) run; returns {(label, row, mode): [runs]}."""
    det = [(b, row, "deterministic", 1) for row in rows for b in binaries] if "deterministic" in args.modes else []
    thr = [(b, row, "threaded", k) for k in range(1, args.threaded_runs + 1) for row in rows for b in binaries] \
        if "threaded" in args.modes else []  # run k of every row before run k+1; binaries interleaved
    prog = Progress(len(det) + len(thr))
    runs = {}

    def done(job, r):
        b, row, mode, _ = job
        runs.setdefault((b["label"], row["row"], mode), []).append(r)
        prog.tick(f"{b['label']} {row['row']} {mode[:3]}", r, args.jobs)

    with cf.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futs = {pool.submit(run_once, args, *job, args.jobs > 1): job for job in det}
        for f in cf.as_completed(futs):
            done(futs[f], f.result())
    for job in thr:
        done(job, run_once(args, *job, False))
    return runs


def rows_for(label, rows, runs):
    out = []
    for row in rows:
        for mode in ("deterministic", "threaded"):
            if (label, row["row"], mode) in runs:
                agg = rep.aggregate(runs[(label, row["row"], mode)])
                agg.update(row=row["row"], group=row["group"], mode=mode, binary=label,
                           **{k: row[k] for k in ("scene", "trajectory", "noise", "seed", "sensor", "slam_noise",
                                                  "twin", "target_ratio", "turn_deg_s") if k in row})
                out.append(agg)
    return out


def git_commit():
    try:
        return subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True,
                              text=True).stdout.strip()
    except OSError:
        return "?"


def markdown(meta, results, labels):
    lines = [f"Command: `{meta['command']}`", "",
             f"Finished {meta['date']}, script commit {meta['commit']}, {meta['rows']} sequences, {meta['frames']} "
             f"frames per simulator sequence, jobs {meta['jobs']}, load average {meta['load_start']} at start, "
             f"{meta['load_end']} at end. `s3m run` without --config (built-in defaults, what a user gets) except "
             f"rows marked with a preset; --slam-only --no-report. ATE: SE3-aligned RMSE of "
             f"trajectory_camera.txt (LOST frames are not in it, ODOMETRY frames are); scale: Sim3 alignment; "
             f"RPE: translational / rotational RMSE over 1 s; lost / reloc: frames LOST / RELOCALISED per run; "
             f"track ms: mean of SLAM's tracking alone (`slam_tracking`; binaries before it: the "
             f"`track` stage, which with --deterministic holds local mapping too)" + (" (* = measured with parallel jobs, under load)" if meta["jobs"] > 1 else "") + "."]
    for other in labels[1:]:  # the A/B verdict first, then every binary's full table
        lines += ["", f"#### A/B: {labels[0]} vs {other}", ""] + rep.compare_lines(
            results[labels[0]], results[other], labels[0], other)
    for label in labels:
        b = meta["binaries"].get(label, {})
        lines += ["", f"#### {label} ({b.get('path', 'baseline JSON')}, sha256 {b.get('sha256_12', '?')})", ""]
        lines += rep.table_lines(results[label]) + [""] + rep.summary_lines(results[label])
        for mode in ("deterministic", "threaded"):
            twins = rep.sensor_lines(results[label], mode)
            lines += ["", f"Sensor realism and wrong config ({mode}): each row against its twin "
                      f"(ratio = ATE / twin's ATE)", ""] + twins if twins else []
        for mode in ("deterministic", "threaded"):
            pivot = rep.pivot_lines(results[label], mode)
            lines += [""] + pivot if pivot else []
    return "\n".join(lines) + "\n"


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--binary", action="append", help="s3m binary to benchmark (repeat for A/B; default build/src/apps/s3m)")
    p.add_argument("--label", action="append", help="display name per --binary, in order (default A, B, ...)")
    p.add_argument("--compare", nargs=2, metavar=("OLD_S3M", "NEW_S3M"), help="same as --binary OLD --binary NEW")
    p.add_argument("--baseline", help="JSON of an earlier matrix run: compared as A against the first --binary")
    p.add_argument("--sim-binary", help="binary that renders missing sequences (default: the first --binary)")
    p.add_argument("--eval-binary", help="binary that scores every run (default: the first --binary)")
    p.add_argument("--cache", default="/tmp/s3m_matrix_cache", help="rendered sequences (default %(default)s)")
    p.add_argument("--rerender", action="store_true", help="render the selected sequences again (simulator changed)")
    p.add_argument("--work", default="/tmp/s3m_matrix_runs", help="run outputs (default %(default)s)")
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--stride", type=int, default=1, help="replay every Nth frame at 30/N Hz (default 1: all)")
    p.add_argument("--scenes", help="comma-separated; 'none' = no simulator rows (kitchen only)")
    p.add_argument("--trajectories")
    p.add_argument("--noise", choices=["on", "off", "both"], default="both")
    p.add_argument("--seeds", help="seed indices 1..3 (= 101, 202, 303) or seed values, comma-separated")
    p.add_argument("--quick", action="store_true", help="the fixed 12-row subset (every scene, trajectory, noise)")
    p.add_argument("--sensor", help="simulator sensor profiles, comma-separated: " + ", ".join(SENSORS) +
                   " (default: from --noise; ideal = the clean rows, default = the noisy rows)")
    p.add_argument("--slam-noise", default="1", help="SLAM depth-noise model as multiples of the simulator's "
                   "truth, comma-separated (default 1: no --config); e.g. 1,0.3,3")
    p.add_argument("--quick-sensors", action="store_true",
                   help="the fixed 7-row sensor subset: default / 20 ms offset / realistic on handheld_pan, "
                        "default / realistic / realistic with SLAM noise x0.3 and x3 on figure8")
    p.add_argument("--no-kitchen", action="store_true", help="leave out the two shared-kitchen rows")
    p.add_argument("--kitchen", default=KITCHEN, help="kitchen sequence (default %(default)s)")
    p.add_argument("--modes", default="deterministic,threaded", help="deterministic, threaded or both (default)")
    p.add_argument("--threaded-runs", type=int, default=3)
    p.add_argument("--threaded-rows", choices=["all", "quick", "kitchen"], default="all",
                   help="threaded runs on every selected row, or only on the kitchen (+ the --quick subset)")
    p.add_argument("--sim-config", help="run the simulator rows with this preset (row ids get ' +NAME'); "
                                        "default: no --config, as a user types it")
    p.add_argument("--render-only", action="store_true", help="render the missing sequences and stop")
    p.add_argument("--jobs", type=int, default=1, help="parallel deterministic runs (timings then marked *)")
    p.add_argument("--timeout", type=float, default=900, help="seconds per sim/run before it counts as failed")
    p.add_argument("--verify-determinism", action="store_true", help="run each deterministic row twice, compare files")
    p.add_argument("--keep-maps", action="store_true", help="keep slam_map.bin / kept_clouds.bin of every run")
    p.add_argument("--out-md"), p.add_argument("--out-json")
    p.add_argument("--report", metavar="JSON", help="print the tables of a saved --out-json again and exit")
    args = p.parse_args(argv)
    if args.stride < 1:
        p.error(f"--stride must be >= 1 (got {args.stride})")
    unknown = [x for x in (args.sensor or "").split(",") if x and x not in SENSORS]
    if unknown:
        p.error(f"--sensor: unknown {', '.join(unknown)} (expected {', '.join(SENSORS)})")
    if args.sim_config and args.slam_noise != "1":
        p.error("--sim-config and --slam-noise both set the run's --config; give one")
    return args


def main(argv):
    args = parse_args(argv)
    if args.report:  # tables again from a saved JSON, no runs
        saved = read_json(args.report)
        for rows in saved["results"].values():  # aggregate again: the row logic may be newer than the file
            for r in rows:
                r.update(rep.aggregate(r["runs"]))
        print(markdown(saved["meta"], saved["results"], saved["meta"]["labels"]), end="")
        return
    paths = (args.compare or []) + (args.binary or []) or [os.path.join(ROOT, "build/src/apps/s3m")]
    labels = (args.label or []) + [chr(ord("A") + i) for i in range(len(paths))][len(args.label or []):]
    binaries = [dict(binary_info(p), label=l) for p, l in zip(paths, labels)]
    args.sim_binary = binary_info(args.sim_binary or paths[0])
    args.eval_binary = os.path.abspath(args.eval_binary or paths[0])
    args.modes = args.modes.split(",")
    sims = sim_rows(args)
    rows = sims + kitchen_rows(args)
    if not rows:
        sys.exit("slam_matrix: no rows selected")
    load_start = " ".join(f"{x:.2f}" for x in os.getloadavg())
    commit = git_commit()  # at start: the tree may change during a long run
    t0 = time.time()
    os.makedirs(args.cache, exist_ok=True)
    renders = []
    firsts = {}  # rows that differ only in the SLAM config share a sequence: render it once
    for row in sims:
        firsts.setdefault(seq_dir(args, row), row)
    by_seq = {}
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for seq, r in zip(firsts, pool.map(lambda row: render(args, row), firsts.values())):
            renders.append(r)
            by_seq[seq] = r
            if not r.get("cached"):
                turn = r.get("turn_deg_s") or (None, None)
                print(f"[render {len(renders)}/{len(firsts)}] {(time.time() - t0) / 60:.1f} min  {r['row']}: "
                      f"{r.get('error') or '%.0f s' % r['seconds']}, turn rate median {rep._f(turn[0], '{:.0f}')} "
                      f"p90 {rep._f(turn[1], '{:.0f}')} deg/s", file=sys.stderr, flush=True)
    for row in sims:
        row["turn_deg_s"] = by_seq[seq_dir(args, row)].get("turn_deg_s")
    new = [r for r in renders if not r.get("cached")]
    render_s = time.time() - t0
    print(f"sequences: {len(firsts)} ({len(new)} rendered in {render_s:.0f} s, "
          f"{rep.median([r['seconds'] for r in new]) or 0:.1f} s median each; {len(firsts) - len(new)} cached "
          f"in {args.cache})", file=sys.stderr)
    other = [r for r in renders if r.get("cached") and r.get("sim_sha256_12") != args.sim_binary["sha256_12"]]
    if other:
        print(f"note: {len(other)} cached sequences were rendered by another s3m binary; pass --rerender if the "
              f"simulator changed (the stamp is in each sequence's matrix_stamp.json)", file=sys.stderr)
    for r in renders:
        if r.get("error"):
            print(f"render failed: {r['row']}: {r['error']}", file=sys.stderr)
    if args.render_only:
        return
    if args.stride > 1:
        for row in rows:  # a failed render is left to the run, which then names the missing sequence
            if os.path.isdir(seq_dir(args, row)):
                row["seq"] = replay_dir(args, row)
            row["row"] += f" @every{args.stride}"
    runs = run_all(args, binaries, rows) if args.threaded_rows == "all" else run_some_threaded(args, binaries, rows)
    results = {b["label"]: rows_for(b["label"], rows, runs) for b in binaries}
    labels = [b["label"] for b in binaries]
    if args.baseline:
        base = read_json(args.baseline)
        base_label = base["meta"]["labels"][-1]
        results = {"baseline": base["results"][base_label], **results}
        labels = ["baseline"] + labels
        binaries.insert(0, dict(base["meta"]["binaries"].get(base_label, {}), label="baseline",
                                path=f"{args.baseline}: {base['meta']['binaries'].get(base_label, {}).get('path')}"))
    meta = {"command": " ".join([os.path.relpath(sys.argv[0])] + argv), "date": datetime.datetime.now().isoformat(
            timespec="seconds"), "commit": commit, "rows": len(rows), "frames": args.frames, "jobs": args.jobs,
            "load_start": load_start, "load_end": " ".join(f"{x:.2f}" for x in os.getloadavg()),
            "binaries": {b["label"]: b for b in binaries}, "labels": labels, "cache": args.cache,
            "render_s": render_s, "renders": renders, "total_s": time.time() - t0, "seeds": SEEDS,
            "stride": args.stride}
    md = markdown(meta, results, labels)
    print(md)
    if args.out_md:
        with open(args.out_md, "w") as f:
            f.write(md)
    if args.out_json:
        with open(args.out_json, "w") as f:
            json.dump({"meta": meta, "results": results}, f, indent=1)
    print(f"total {meta['total_s'] / 60:.1f} min (rendering {render_s / 60:.1f} min)", file=sys.stderr)


def run_some_threaded(args, binaries, rows):
    """Deterministic on every selected row, threaded only on the kitchen (and the --quick rows)."""
    modes = args.modes
    args.modes = [m for m in modes if m == "deterministic"]
    runs = run_all(args, binaries, rows)
    quick = set(QUICK) if args.threaded_rows == "quick" else set()
    if "threaded" in modes:
        args.modes = ["threaded"]
        runs.update(run_all(args, binaries, [r for r in rows if r["kind"] == "kitchen" or r.get("combo") in quick]))
    args.modes = modes
    return runs


if __name__ == "__main__":
    main(sys.argv[1:])
