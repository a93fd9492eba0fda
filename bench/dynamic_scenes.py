#!/usr/bin/python3
"""People walking through a simulated flight: tracking and map with and without dynamic handling,
against the same flight without people. Runs the `s3m` CLI exactly as a user would.

  s3m sim --scene S --seed K --frames N [--people P] --out WORK/seq_...           (cached)
  s3m run SEQ --config config/sim.yaml --deterministic [--dynamic] [--poses gt] --out WORK/run_...
  bench_dynamic_ghosts SEQ RUN [PEOPLE_SEQ]                                       (ghost voxels)

Rows per (scene, seed, people): SLAM ATE without people, with people (no handling), with --dynamic
(mask + map), with --dynamic and dynamic.mask_tracking false (map only, tracking as without);
ground-truth-pose runs (mapping alone): map mIoU with --dynamic without and with people (the
scene's standing person is left out of both), ghost voxels near the people's paths
(run/ghost_voxels.hpp) without people, with people plain, with --dynamic. The dynamic_mask column is
the pipeline's mean per-frame cost of the tracking mask [ms].

  bench/dynamic_scenes.py --binary build/src/apps/s3m --ghosts build/bench/bench_dynamic_ghosts \\
      --work /tmp/dynamic-bench --seeds 7 --people 3
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PRESET = os.path.join(HERE, "..", "config", "sim.yaml")


def sh(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}; see {log}")


def sequence(a, scene, seed, people):
    out = os.path.join(a.work, f"seq_{scene}_s{seed}_p{people}_f{a.frames}")
    if not os.path.exists(os.path.join(out, "sim.yaml")):
        cmd = [a.binary, "sim", "--scene", scene, "--seed", str(seed), "--frames", str(a.frames), "--out", out]
        if people:
            cmd += ["--people", str(people)]
        sh(cmd, out + ".log")
    return out


def run(a, seq, name, extra, config=PRESET):
    out = os.path.join(a.work, "run_" + os.path.basename(seq) + "_" + name)
    if not os.path.exists(os.path.join(out, "metrics.json")):
        sh([a.binary, "run", seq, "--config", config, "--deterministic", "--no-report", "--no-session-mcap",
            "--out", out] + extra, out + ".log")
    with open(os.path.join(out, "metrics.json")) as f:
        return out, json.load(f)


def ghosts(a, seq, out, people_seq):
    r = subprocess.run([a.ghosts, seq, out, people_seq], capture_output=True, text=True, check=True)
    return json.loads(r.stdout)["ghost_voxels"]


def ate(m):
    t = m.get("trajectory")
    return t["ate_rmse_m"] * 1000 if t else float("nan")


def mask_ms(m):
    t = m.get("timings_ms", {}).get("dynamic_mask")
    return t["mean"] if t else float("nan")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--binary", required=True)
    p.add_argument("--ghosts", required=True)
    p.add_argument("--work", default="/tmp/s3m-dynamic-bench")
    p.add_argument("--scenes", default="office")
    p.add_argument("--seeds", default="7")
    p.add_argument("--people", default="3")
    p.add_argument("--frames", type=int, default=300)
    a = p.parse_args()
    os.makedirs(a.work, exist_ok=True)
    nomask = os.path.join(a.work, "sim_dynamic_nomask.yaml")
    with open(PRESET) as f, open(nomask, "w") as g:
        g.write(f.read() + "\ndynamic:\n  enabled: true\n  mask_tracking: false\n")
    print("| scene | seed | people | ATE no people [mm] | ATE people [mm] | ATE --dynamic [mm] | ATE map-only [mm] "
          "| mIoU gt no people --dynamic | mIoU gt people --dynamic | ghosts no people | ghosts people "
          "| ghosts --dynamic | dynamic_mask [ms/frame] |")
    print("|" + "---|" * 13)
    for scene in a.scenes.split(","):
        for seed in map(int, a.seeds.split(",")):
            free = sequence(a, scene, seed, 0)
            for people in map(int, a.people.split(",")):
                seq = sequence(a, scene, seed, people)
                _, m0 = run(a, free, "slam", [])
                _, m1 = run(a, seq, "slam", [])
                _, m2 = run(a, seq, "slam_dynamic", ["--dynamic"])
                _, m3 = run(a, seq, "slam_maponly", [], config=nomask)
                g0, _ = run(a, free, "gt", ["--poses", "gt"])
                _, n0 = run(a, free, "gt_dynamic", ["--poses", "gt", "--dynamic"])
                g1, _ = run(a, seq, "gt", ["--poses", "gt"])
                g2, n2 = run(a, seq, "gt_dynamic", ["--poses", "gt", "--dynamic"])
                row = [scene, seed, people, f"{ate(m0):.2f}", f"{ate(m1):.2f}", f"{ate(m2):.2f}", f"{ate(m3):.2f}",
                       f"{n0['map']['miou']:.4f}", f"{n2['map']['miou']:.4f}",
                       ghosts(a, free, g0, seq), ghosts(a, seq, g1, seq), ghosts(a, seq, g2, seq),
                       f"{mask_ms(m2):.3f}"]
                print("| " + " | ".join(str(x) for x in row) + " |", flush=True)


if __name__ == "__main__":
    main()
