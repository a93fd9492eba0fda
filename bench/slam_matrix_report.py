"""Pure parts of bench/slam_matrix.py: aggregating runs into rows, the summary against the targets of
issue #20, and the markdown tables (single binary and A/B). No I/O, no subprocesses: tested by
tests/python/slam_matrix_report_test.py.

A *run* is one `s3m run` scored by `s3m eval` (a dict: ate_cm, scale, rpe_cm, rpe_deg, lost,
relocalised, keyframes, states, track_ms, timing_under_load, error). A *row* is one (binary, sequence,
mode): 1 run for deterministic, N (3) for threaded; its headline numbers come from the run with the
median ATE."""
import math
import statistics

TARGETS = {  # issue #20; the sensor-realism ones from issue #53
    "clean_worst_ate_cm": 0.5, "clean_worst_scale_pct": 0.3,
    "noisy_median_ate_cm": 1.0, "noisy_worst_ate_cm": 2.5,
    "threaded_over_det": 1.05, "kitchen_ate_cm": 3.2, "kitchen_track_ms": 10.0,
    "wrong_config_over_right": 1.10, "offset_over_synced": 1.20,
}


def median(values):
    """Median of the non-None values, None when there are none.
    >>> median([3.0, 1.0, 2.0]), median([1.0, None, 4.0]), median([])
    (2.0, 2.5, None)
    """
    v = [x for x in values if x is not None]
    return statistics.median(v) if v else None


def aggregate(runs):
    """Row numbers from its runs: the run with the median ATE (lower median for even counts) gives
    scale, RPE, counts; spread is max - min ATE; errors are kept. A row whose runs all failed has
    ate_cm None and error set."""
    ok = [r for r in runs if r.get("error") is None and r.get("ate_cm") is not None]
    errors = [r["error"] for r in runs if r.get("error")]
    row = {"n_runs": len(runs), "n_ok": len(ok), "error": "; ".join(errors) if errors else None,
           "runs": runs}
    if not ok:  # counts still come from runs that ran but could not be scored (e.g. < 3 poses left)
        ran = [r for r in runs if r.get("states") is not None]
        first = ran[0] if ran else {}
        row.update(ate_cm=None, spread_cm=None, scale=None, rpe_cm=None, rpe_deg=None, coverage=None,
                   track_ms=None, timing_under_load=None, lost_runs=[r.get("lost") for r in ran],
                   reloc_runs=[r.get("relocalised") for r in ran],
                   **{k: first.get(k) for k in ("lost", "relocalised", "keyframes", "states")})
        return row
    by_ate = sorted(ok, key=lambda r: r["ate_cm"])
    mid = by_ate[(len(by_ate) - 1) // 2]
    row.update({k: mid.get(k) for k in ("scale", "rpe_cm", "rpe_deg", "lost", "relocalised", "keyframes",
                                        "states")})
    row["ate_cm"] = median([r["ate_cm"] for r in ok])
    row["spread_cm"] = by_ate[-1]["ate_cm"] - by_ate[0]["ate_cm"]
    row["track_ms"] = median([r.get("track_ms") for r in ok])
    row["timing_under_load"] = any(r.get("timing_under_load") for r in ok)
    row["coverage"] = coverage(mid)
    row["lost_runs"] = [r.get("lost") for r in ok]
    row["reloc_runs"] = [r.get("relocalised") for r in ok]
    return row


def coverage(run):
    """Share of the sequence's frames that have a pose in the scored trajectory (LOST frames have none).
    >>> coverage({"est_poses": 13, "frames": 300}), coverage({"ate_cm": 1.0})
    (0.043333333333333335, None)
    """
    if not run.get("frames") or run.get("est_poses") is None:
        return None
    return run["est_poses"] / run["frames"]


PARTIAL = 0.9  # rows scored on less of the sequence than this are marked: their ATE is not comparable


def partial(row):
    return row.get("coverage") is not None and row["coverage"] < PARTIAL


def scale_err_pct(row):
    return None if row.get("scale") is None else abs(row["scale"] - 1.0) * 100.0


def _worst(rows, key):
    cand = [(key(r), r["row"]) for r in rows if key(r) is not None]
    return max(cand) if cand else (None, None)


def group_summary(rows):
    """Median / worst ATE, worst |scale-1|, rows with lost frames (in any run), errors.
    >>> s = group_summary([{"row": "a", "ate_cm": 1.0, "scale": 0.99, "lost_runs": [0]},
    ...                    {"row": "b", "ate_cm": 3.0, "scale": 1.001, "lost_runs": [0, 2]},
    ...                    {"row": "c", "ate_cm": None, "error": "crash", "lost_runs": []}])
    >>> s["median_ate_cm"], s["worst_ate_cm"], s["worst_ate_row"], round(s["worst_scale_pct"], 3)
    (2.0, 3.0, 'b', 1.0)
    >>> s["lost_rows"], s["error_rows"], s["n"]
    (['b'], ['c'], 3)
    """
    worst_ate, worst_ate_row = _worst(rows, lambda r: r.get("ate_cm"))
    worst_scale, worst_scale_row = _worst(rows, scale_err_pct)
    full = [r for r in rows if r.get("ate_cm") is not None and not any((x or 0) > 0 for x in r.get("lost_runs", []))]
    return {"n_full": len(full), "median_ate_full_cm": median([r["ate_cm"] for r in full]),
            "worst_ate_full_cm": max((r["ate_cm"] for r in full), default=None),"n": len(rows), "median_ate_cm": median([r.get("ate_cm") for r in rows]),
            "worst_ate_cm": worst_ate, "worst_ate_row": worst_ate_row,
            "worst_scale_pct": worst_scale, "worst_scale_row": worst_scale_row,
            "lost_rows": [r["row"] for r in rows if any((x or 0) > 0 for x in r.get("lost_runs", []))],
            "partial_rows": [r["row"] for r in rows if partial(r)],
            "error_rows": [r["row"] for r in rows if r.get("ate_cm") is None]}


def threaded_vs_det(det_rows, thr_rows):
    """Per sequence: threaded median ATE / deterministic ATE, and whether every threaded run had the
    deterministic run's tracking-state counts.
    >>> d = [{"row": "a", "ate_cm": 1.0, "states": {"OK": 9, "LOST": 1}}]
    >>> t = [{"row": "a", "ate_cm": 1.1, "runs": [{"states": {"OK": 9, "LOST": 1}}, {"states": {"OK": 10}}]}]
    >>> v = threaded_vs_det(d, t); round(v["a"]["ratio"], 3), v["a"]["same_states"]
    (1.1, False)
    """
    det = {r["row"]: r for r in det_rows}
    out = {}
    for t in thr_rows:
        d = det.get(t["row"])
        if d is None or d.get("ate_cm") is None or t.get("ate_cm") is None:
            continue
        ratio = t["ate_cm"] / d["ate_cm"] if d["ate_cm"] > 0 else None
        same = all(r.get("states") == d.get("states") for r in t["runs"] if r.get("error") is None)
        out[t["row"]] = {"ratio": ratio, "same_states": same}
    return out


def _f(x, fmt="{:.2f}"):
    return "–" if x is None else fmt.format(x)


def _pass(ok):
    return "–" if ok is None else ("yes" if ok else "**no**")


def summary_lines(rows):
    """Markdown summary of one binary's rows (row dicts with group 'clean'/'noisy'/'kitchen' and mode)."""
    t = TARGETS
    out = ["| group | mode | rows | median ATE cm | worst ATE cm (row) | worst abs(scale-1) % (row) | rows with lost frames | "
           "median / worst ATE of rows without lost frames | errors | targets | met |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for group in ("clean", "noisy", "realistic"):
        for mode in ("deterministic", "threaded"):
            rs = [r for r in rows if r["group"] == group and r["mode"] == mode]
            if not rs:
                continue
            s = group_summary(rs)
            if group == "clean":
                target = f"worst ATE <= {t['clean_worst_ate_cm']}, abs(scale-1) <= {t['clean_worst_scale_pct']} %, 0 lost"
                met = (None if s["worst_ate_cm"] is None else s["worst_ate_cm"] <= t["clean_worst_ate_cm"]
                       and (s["worst_scale_pct"] or 0) <= t["clean_worst_scale_pct"] and not s["lost_rows"])
            else:
                target = f"median <= {t['noisy_median_ate_cm']}, worst <= {t['noisy_worst_ate_cm']} (lost: see rows)"
                met = (None if s["worst_ate_cm"] is None else s["median_ate_cm"] <= t["noisy_median_ate_cm"]
                       and s["worst_ate_cm"] <= t["noisy_worst_ate_cm"])
            if s["error_rows"]:
                met = False
            lost = f"{len(s['lost_rows'])}" + (f" ({len(s['partial_rows'])} scored on < {PARTIAL:.0%} of the "
                                               f"frames)" if s["partial_rows"] else "")
            name = {"clean": "noise-free", "noisy": "sensor noise", "realistic": "realistic sensor"}[group]
            out.append(f"| {name} | {mode} | {s['n']} | "
                       f"{_f(s['median_ate_cm'])} | {_f(s['worst_ate_cm'])} ({s['worst_ate_row']}) | "
                       f"{_f(s['worst_scale_pct'])} ({s['worst_scale_row']}) | {lost} | {_f(s['median_ate_full_cm'])} / "
                       f"{_f(s['worst_ate_full_cm'])} ({s['n_full']} rows) | {len(s['error_rows'])} | "
                       f"{target} | {_pass(met)} |")
    for r in rows:
        if r["group"] == "kitchen":
            ms = r.get("track_ms")
            tgt = f"ATE <= {t['kitchen_ate_cm']}" + (f", track <= {t['kitchen_track_ms']:.0f} ms" if r["mode"] == "deterministic" else "")
            met = None if r.get("ate_cm") is None else (r["ate_cm"] <= t["kitchen_ate_cm"] and (
                r["mode"] != "deterministic" or ms is None or ms <= t["kitchen_track_ms"]))
            spread = "spread " + _f(r.get("spread_cm")) if r.get("n_runs", 1) > 1 else "–"
            out.append(f"| {r['row']} | {r['mode']} | {r.get('n_runs', 1)} runs | {_f(r.get('ate_cm'))} | {spread} | "
                       f"{_f(scale_err_pct(r))} | {_runs(r.get('lost_runs'))} | – | "
                       f"{1 if r.get('error') else 0} | {tgt} | {_pass(met)} |")
    det = [r for r in rows if r["mode"] == "deterministic"]
    thr = [r for r in rows if r["mode"] == "threaded"]
    if det and thr:
        v = threaded_vs_det(det, thr)
        over = sorted(k for k, x in v.items() if x["ratio"] is not None and x["ratio"] > t["threaded_over_det"])
        diff = sorted(k for k, x in v.items() if not x["same_states"])
        worst = max(((x["ratio"], k) for k, x in v.items() if x["ratio"] is not None), default=(None, None))
        out.append("")
        out.append(f"Threaded (median of runs) / deterministic ATE over {len(v)} rows: median "
                   f"{_f(median([x['ratio'] for x in v.values()]))}, worst {_f(worst[0])} ({worst[1]}); "
                   f"target <= {t['threaded_over_det']} on every row: {len(over)} rows over"
                   + (f" ({', '.join(over)})" if over else "") + f"; rows where a threaded run's tracking-state "
                   f"counts differ from deterministic: {len(diff)}" + (f" ({', '.join(diff)})" if diff else "") + ".")
    return out


def turn_rate_deg_s(poses):
    """Median and 90th percentile of the turn rate [deg/s] of TUM poses (t, tx, ty, tz, qx, qy, qz, qw).
    >>> import math; c, s = math.cos(math.radians(1)), math.sin(math.radians(1))  # 2 deg per 0.1 s
    >>> turn_rate_deg_s([(0, 0, 0, 0, 0, 0, 0, 1), (0.1, 0, 0, 0, 0, 0, s, c), (0.2, 0, 0, 0, 0, 0, s, c)])
    (10.0, 20.0)
    """
    rates = []
    for a, b in zip(poses, poses[1:]):
        dot = min(1.0, abs(sum(x * y for x, y in zip(a[4:8], b[4:8]))))
        rates.append(2.0 * math.degrees(math.acos(dot)) / (b[0] - a[0]))
    if not rates:
        return None, None
    ordered = sorted(rates)
    return round(statistics.median(ordered), 6), round(ordered[min(len(ordered) - 1, int(0.9 * len(ordered)))], 6)


def sensor_lines(rows, mode="deterministic"):
    """Rows measured against a twin (row["twin"]: the same flight with the default sensor, or the
    correctly configured run): ATE of both, the ratio and, where the issue sets one, its target.
    >>> a = {"row": "f8/noisy", "mode": "deterministic", "ate_cm": 1.0}
    >>> b = {"row": "f8/realistic x3", "mode": "deterministic", "ate_cm": 1.05, "twin": "f8/noisy",
    ...      "target_ratio": 1.1, "turn_deg_s": (30.0, 70.0)}
    >>> sensor_lines([a, b])[2]
    '| f8/realistic x3 | f8/noisy | 30 / 70 | 1.05 | 1.00 | 1.05 | <= 1.1 | yes |'
    """
    by_row = {r["row"]: r for r in rows if r["mode"] == mode}
    twinned = [r for r in by_row.values() if r.get("twin")]
    if not twinned:
        return []
    out = [f"| row | against | turn deg/s median / p90 | ATE cm | ATE cm against | ratio | target | met |",
           "|---|---|---|---|---|---|---|---|"]
    for r in twinned:
        t = by_row.get(r["twin"], {})
        q = ratio(t.get("ate_cm"), r.get("ate_cm"))
        goal = r.get("target_ratio")
        turn = " / ".join(_f(x, "{:.0f}") for x in (r.get("turn_deg_s") or (None, None)))
        out.append(f"| {r['row']} | {r['twin']} | {turn} | {_f(r.get('ate_cm'))} | {_f(t.get('ate_cm'))} | "
                   f"{_f(q)} | {'<= ' + str(goal) if goal else '–'} | "
                   f"{_pass(None if goal is None or q is None else q <= goal)} |")
    return out


def pivot_lines(rows, mode="deterministic"):
    """Median ATE over the seeds per trajectory x scene, noise-free / noisy, and how many of the
    cell's rows lost frames (simulator rows of one mode only)."""
    sim = [r for r in rows if r.get("scene") and r["mode"] == mode]
    scenes = sorted({r["scene"] for r in sim}, key=lambda x: ["office", "living_room", "corridor"].index(x)
                    if x in ("office", "living_room", "corridor") else 9)
    trajs = list(dict.fromkeys(r["trajectory"] for r in sim))
    if not sim:
        return []
    out = [f"Median ATE cm over the seeds ({mode}), noise-free / noisy; (n lost) = rows with LOST frames, "
           "x = rows that could not be scored:", "", "| trajectory | " + " | ".join(scenes) + " |",
           "|---|" + "---|" * len(scenes)]
    for t in trajs:
        cells = []
        for sc in scenes:
            cell = [r for r in sim if r["scene"] == sc and r["trajectory"] == t]
            parts = [_f(median([r.get("ate_cm") for r in cell if r["group"] == g])) for g in ("clean", "noisy")]
            lost = len(group_summary(cell)["lost_rows"]) if cell else 0
            err = sum(1 for r in cell if r.get("ate_cm") is None)
            cells.append(" / ".join(parts) + (f" ({lost} lost)" if lost else "") + (f" {err} x" if err else ""))
        out.append(f"| {t} | " + " | ".join(cells) + " |")
    return out


def _ms(r):
    if r.get("track_ms") is None:
        return "–"
    return f"{r['track_ms']:.2f}" + ("*" if r.get("timing_under_load") else "")


def _runs(values):
    return "/".join("–" if v is None else str(v) for v in values) if values else "–"


def lost_note(row):
    """The LOST frame ranges of the row's median run, e.g. 'LOST 1, 12-40'.
    >>> lost_note({"runs": [{"ate_cm": 1.0, "lost_ranges": [[1, 1], [12, 40]]}]})
    'LOST 1, 12-40'
    """
    ok = sorted((r for r in row.get("runs", []) if r.get("ate_cm") is not None), key=lambda r: r["ate_cm"])
    ranges = ok[(len(ok) - 1) // 2].get("lost_ranges") if ok else None
    if not ranges:
        return ""
    return "LOST " + ", ".join(str(a) if a == b else f"{a}-{b}" for a, b in ranges)


def rerun_note(row):
    same = [r.get("identical_on_rerun") for r in row.get("runs", []) if "identical_on_rerun" in r]
    if not same:
        return ""
    return "rerun identical" if all(same) else "**rerun differs**"


def _ate(r):
    return _f(r.get("ate_cm")) + (f" † ({r['coverage']:.0%})" if partial(r) else "")


def table_lines(rows):
    """One binary's rows as a markdown table."""
    out = ["| row | mode | ATE cm | spread cm | Sim3 scale | RPE cm/1s | RPE deg/1s | lost | reloc | KF | track ms | note |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        spread = _f(r.get("spread_cm")) if r.get("n_runs", 1) > 1 else ""
        note = "; ".join(x for x in (lost_note(r), rerun_note(r), (r.get("error") or "")[:120]) if x)
        note = note.replace("|", "/").replace("\n", " ")
        ate = _ate(r)
        out.append(f"| {r['row']} | {r['mode'][:3]}{'' if r.get('n_runs', 1) == 1 else ' x' + str(r['n_runs'])} | "
                   f"{ate} | {spread} | {_f(r.get('scale'), '{:.4f}')} | {_f(r.get('rpe_cm'))} | "
                   f"{_f(r.get('rpe_deg'))} | {_runs(r.get('lost_runs'))} | {_runs(r.get('reloc_runs'))} | "
                   f"{_f(r.get('keyframes'), '{}')} | {_ms(r)} | {note} |")
    return out


def ratio(a, b):
    """b / a, None when either is missing or a is 0.
    >>> ratio(2.0, 3.0), ratio(None, 1.0), ratio(0.0, 1.0)
    (1.5, None, None)
    """
    return None if a is None or b is None or a == 0 else b / a


def compare_lines(rows_a, rows_b, label_a, label_b):
    """A/B table on the (row, mode) pairs both have, with per-row B/A and the medians per group."""
    a_by = {(r["row"], r["mode"]): r for r in rows_a}
    pairs = [(a_by[(r["row"], r["mode"])], r) for r in rows_b if (r["row"], r["mode"]) in a_by]
    out = [f"A = {label_a}, B = {label_b}; B/A < 1 means B is more accurate; † = ATE over < {PARTIAL:.0%} of the "
           "frames (the rest LOST).", "",
           "| row | mode | ATE A | ATE B | B/A | abs(s-1)% A | abs(s-1)% B | lost A | lost B | KF A | KF B | ms A | ms B |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for a, b in pairs:
        out.append(f"| {a['row']} | {a['mode'][:3]} | {_ate(a)} | {_ate(b)} | "
                   f"{_f(ratio(a.get('ate_cm'), b.get('ate_cm')), '{:.3f}')} | {_f(scale_err_pct(a))} | "
                   f"{_f(scale_err_pct(b))} | {_runs(a.get('lost_runs'))} | {_runs(b.get('lost_runs'))} | "
                   f"{_f(a.get('keyframes'), '{}')} | {_f(b.get('keyframes'), '{}')} | {_ms(a)} | {_ms(b)} |")
    out += ["", "| group | mode | rows | median ATE A | median ATE B | median B/A | rows B better >5 % | rows B worse >5 % | lost rows A | lost rows B |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for group in ("clean", "noisy", "kitchen"):
        for mode in ("deterministic", "threaded"):
            ps = [(a, b) for a, b in pairs if a["group"] == group and a["mode"] == mode]
            if not ps:
                continue
            rs = [ratio(a.get("ate_cm"), b.get("ate_cm")) for a, b in ps]
            out.append(f"| {group} | {mode} | {len(ps)} | {_f(median([a.get('ate_cm') for a, _ in ps]))} | "
                       f"{_f(median([b.get('ate_cm') for _, b in ps]))} | {_f(median(rs), '{:.3f}')} | "
                       f"{sum(1 for x in rs if x is not None and x < 0.95)} | "
                       f"{sum(1 for x in rs if x is not None and x > 1.05)} | "
                       f"{len(group_summary([a for a, _ in ps])['lost_rows'])} | "
                       f"{len(group_summary([b for _, b in ps])['lost_rows'])} |")
    return out
