"""Which rows bench/slam_matrix.py runs: the simulator's scenes x trajectories x sensor profiles x
seeds x SLAM noise-model factors, the fixed subsets (--quick, --quick-sensors) and the shared kitchen;
where each row's sequence is cached and the --config a "wrong config" row runs with."""
import itertools
import os

import slam_matrix_report as rep

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["office", "living_room", "corridor"]
TRAJECTORIES = ["uav_sweep", "figure8", "loop", "lawnmower", "handheld"]
SEEDS = [101, 202, 303]  # fixed; none of the seeds in the issue (7, 11, 12, 13, 14)
KITCHEN = "/work/shared/data/7scenes_redkitchen_0000-0499"
KITCHEN_PRESET = "config/kitchen_7scenes.yaml"
# --quick: 12 rows; every scene 4x, every trajectory with and without noise, every seed.
QUICK = [("office", "uav_sweep", False, 101), ("office", "figure8", True, 101),
         ("living_room", "loop", False, 101), ("living_room", "lawnmower", True, 101),
         ("corridor", "handheld", False, 101), ("corridor", "uav_sweep", True, 202),
         ("living_room", "figure8", False, 202), ("corridor", "loop", True, 202),
         ("office", "lawnmower", False, 202), ("office", "handheld", True, 303),
         ("corridor", "figure8", False, 303), ("living_room", "uav_sweep", True, 303)]


# Sensor axis: profile -> (row and cache tag, `s3m sim` options).
SENSORS = {"ideal": ("clean", ["--no-noise"]), "default": ("noisy", []),
           "realistic": ("realistic", ["--sensor-profile", "realistic"]),
           "offset20": ("offset20ms", ["--depth-time-offset", "0.02"])}
# The simulator's depth noise (sim::SensorConfig's default, which every profile keeps) in the SLAM
# config's terms; the "wrong config" rows scale it.
SIM_DEPTH_NOISE = {"sigma0_m": 0.001, "k_per_m": 0.0015}
# --quick-sensors: (scene, trajectory, sensor, seed, SLAM noise factor).
QUICK_SENSORS = [("office", "handheld_pan", "default", 101, 1), ("office", "handheld_pan", "offset20", 101, 1),
                 ("office", "handheld_pan", "realistic", 101, 1), ("living_room", "figure8", "default", 202, 1),
                 ("living_room", "figure8", "realistic", 202, 1), ("living_room", "figure8", "realistic", 202, 0.3),
                 ("living_room", "figure8", "realistic", 202, 3)]


def sensor_row(scene, traj, sensor, seed, factor, suffix=""):
    """A simulator row; twin / target_ratio name the row it is judged against (sensor_lines)."""
    tag = SENSORS[sensor][0]
    base = f"{scene}/{traj}/{{}}/s{seed}{suffix}"
    row = {"row": base.format(tag) + (f" slam-noise x{factor:g}" if factor != 1 else ""), "kind": "sim",
           "scene": scene, "trajectory": traj, "sensor": sensor, "noise": sensor != "ideal", "seed": seed,
           "slam_noise": factor, "combo": (scene, traj, sensor != "ideal", seed),
           "group": tag if factor == 1 and sensor in ("ideal", "default", "realistic") else
           ("wrong_config" if factor != 1 else "offset")}
    if factor != 1:
        row.update(twin=base.format(tag), target_ratio=rep.TARGETS["wrong_config_over_right"])
    elif sensor == "offset20":
        row.update(twin=base.format("noisy"), target_ratio=rep.TARGETS["offset_over_synced"])
    elif sensor == "realistic":
        row.update(twin=base.format("noisy"))
    return row


def sim_rows(args):
    """The selected simulator rows as dicts (row id, scene, trajectory, sensor, seed, group, ...)."""
    if args.scenes == "none":
        return []
    seeds = None if args.seeds is None else {SEEDS[int(k) - 1] if int(k) <= len(SEEDS) else int(k)
                                             for k in args.seeds.split(",")}
    factors = [float(f) for f in args.slam_noise.split(",")]
    if args.sensor:
        sensors = args.sensor.split(",")
    elif args.quick_sensors:
        sensors = list(SENSORS)
    else:
        sensors = {"on": ["default"], "off": ["ideal"], "both": ["ideal", "default"]}[args.noise]
    if args.quick_sensors:
        combos = QUICK_SENSORS
    elif args.quick:
        combos = [(s, t, "default" if n else "ideal", k, f) for s, t, n, k in QUICK for f in factors]
    else:  # the selected seeds, also values beyond the fixed three (--seeds 404)
        flown = SEEDS if seeds is None else sorted(seeds)
        combos = list(itertools.product(SCENES, TRAJECTORIES, sensors, flown, factors))
    pick = lambda value, allowed: allowed is None or value in allowed  # noqa: E731
    rows = []
    for scene, traj, sensor, seed, factor in combos:
        if args.sim_config and factor != 1:  # the preset is the run's config: no wrong-config twin
            continue
        if pick(scene, args.scenes and args.scenes.split(",")) and pick(traj, args.trajectories and
                args.trajectories.split(",")) and sensor in sensors and pick(seed, seeds):
            suffix = f" +{os.path.basename(args.sim_config)}" if args.sim_config else ""
            row = sensor_row(scene, traj, sensor, seed, factor, suffix)
            row["config"] = os.path.abspath(args.sim_config) if args.sim_config else None
            rows.append(row)
    return rows


def slam_noise_config(args, factor):
    """A --config that only sets SLAM's depth noise model to factor x the simulator's truth."""
    path = os.path.join(args.work, "configs", f"slam_noise_x{factor:g}.yaml")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(f"# bench/slam_matrix.py wrong-config axis: depth noise {factor:g} x the simulator's\n"
                f"slam:\n  features:\n    depth_noise: {{model: sensor, sigma0_m: {SIM_DEPTH_NOISE['sigma0_m'] * factor:g}, "
                f"k_per_m: {SIM_DEPTH_NOISE['k_per_m'] * factor:g}}}\n")
    return path


def kitchen_rows(args):
    if args.no_kitchen:
        return []
    return [{"row": "kitchen (no --config)", "kind": "kitchen", "dataset": args.kitchen, "config": None,
             "group": "kitchen"},
            {"row": "kitchen (--config kitchen_7scenes.yaml)", "kind": "kitchen", "dataset": args.kitchen,
             "config": os.path.join(ROOT, KITCHEN_PRESET), "group": "kitchen"}]


def seq_dir(args, row):
    if row["kind"] == "kitchen":
        return row["dataset"]
    return os.path.join(args.cache, f"{row['scene']}_{row['trajectory']}_{SENSORS[row['sensor']][0]}"
                                    f"_s{row['seed']}_n{args.frames}")
