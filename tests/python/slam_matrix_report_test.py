"""The pure parts of bench/slam_matrix.py on fixed numbers: row aggregation (median of threaded runs),
the issue-#20 summary's verdicts, the A/B table, plus the module's doctests. Run by ctest
(bench_slam_matrix_report) with Debian's /usr/bin/python3; stdlib only."""
import doctest
import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
import slam_matrix_report as rep  # noqa: E402
import slam_matrix_rows as rows  # noqa: E402


def run(ate, scale=1.0, lost=0, states=None, error=None):
    return {"ate_cm": ate, "scale": scale, "rpe_cm": 1.0, "rpe_deg": 0.1, "lost": lost, "relocalised": 0,
            "keyframes": 10, "states": states or {"OK": 300 - lost, "LOST": lost}, "track_ms": 5.0,
            "lost_ranges": [[7, 6 + lost]] if lost else [], "error": error}


def row(name, group, mode, runs):
    r = rep.aggregate(runs)
    r.update(row=name, group=group, mode=mode)
    return r


class Aggregate(unittest.TestCase):
    def test_threaded_row_is_the_median_run(self):
        r = rep.aggregate([run(3.0, 0.97), run(1.0, 0.99), run(2.0, 0.98, lost=2)])
        self.assertEqual(r["ate_cm"], 2.0)
        self.assertEqual(r["scale"], 0.98)  # from the run with the median ATE
        self.assertEqual(r["spread_cm"], 2.0)
        self.assertEqual(r["lost_runs"], [0, 0, 2])
        self.assertIsNone(r["error"])

    def test_failed_runs_are_kept_and_do_not_count(self):
        r = rep.aggregate([run(None, error="timeout after 900 s"), run(1.5)])
        self.assertEqual((r["ate_cm"], r["n_ok"], r["error"]), (1.5, 1, "timeout after 900 s"))
        r = rep.aggregate([run(None, error="run exit 1: boom")])
        self.assertIsNone(r["ate_cm"])
        self.assertEqual(r["error"], "run exit 1: boom")


    def test_a_run_that_could_not_be_scored_keeps_its_counts(self):
        lost_all = dict(run(None, lost=298, error="eval --align se3 exit 1: need at least 3"), keyframes=1)
        r = rep.aggregate([lost_all])
        self.assertIsNone(r["ate_cm"])
        self.assertEqual((r["lost"], r["lost_runs"], r["keyframes"]), (298, [298], 1))

    def test_rows_scored_on_part_of_the_sequence_are_marked(self):
        r = row("uav", "clean", "deterministic", [dict(run(0.1, lost=287), est_poses=13, frames=300)])
        self.assertIn("| 0.10 † (4%) |", rep.table_lines([r])[2])
        r = row("f8", "clean", "deterministic", [dict(run(0.4, lost=1), est_poses=299, frames=300)])
        self.assertIn("| 0.40 |", rep.table_lines([r])[2])


class Summary(unittest.TestCase):
    def verdicts(self, rows):
        return [line.rsplit("|", 2)[-2].strip() for line in rep.summary_lines(rows) if line.startswith("| noise")
                or line.startswith("| sensor")]

    def test_noise_free_target_needs_ate_scale_and_no_lost_frames(self):
        good = [row("a", "clean", "deterministic", [run(0.4, 1.002)])]
        self.assertEqual(self.verdicts(good), ["yes"])
        self.assertEqual(self.verdicts(good + [row("b", "clean", "deterministic", [run(0.6)])]), ["**no**"])
        self.assertEqual(self.verdicts(good + [row("b", "clean", "deterministic", [run(0.4, 0.996)])]), ["**no**"])
        self.assertEqual(self.verdicts(good + [row("b", "clean", "deterministic", [run(0.4, lost=1)])]), ["**no**"])

    def test_noisy_target_is_median_and_worst(self):
        rows = [row(n, "noisy", "deterministic", [run(a)]) for n, a in (("a", 0.5), ("b", 0.9), ("c", 2.4))]
        self.assertEqual(self.verdicts(rows), ["yes"])
        rows.append(row("d", "noisy", "deterministic", [run(2.6)]))
        self.assertEqual(self.verdicts(rows), ["**no**"])

    def test_threaded_over_deterministic_names_the_rows(self):
        det = [row("a", "noisy", "deterministic", [run(1.0)]), row("b", "noisy", "deterministic", [run(1.0)])]
        thr = [row("a", "noisy", "threaded", [run(1.0), run(1.04), run(1.2)]),
               row("b", "noisy", "threaded", [run(1.1), run(1.06), run(0.9, lost=3)])]
        text = "\n".join(rep.summary_lines(det + thr))
        self.assertIn("1 rows over (b)", text)
        self.assertIn("differ from deterministic: 1 (b)", text)


class SensorRealism(unittest.TestCase):
    def test_realistic_rows_have_their_own_summary_line(self):
        rows = [row("a/noisy", "noisy", "deterministic", [run(0.5)]),
                row("a/realistic", "realistic", "deterministic", [run(2.6)])]
        lines = [x for x in rep.summary_lines(rows) if x.startswith("| realistic sensor")]
        self.assertEqual(len(lines), 1)
        self.assertTrue(lines[0].endswith("| **no** |"))  # worst 2.6 > 2.5

    def test_twins_give_ratio_and_verdict(self):
        right = row("f8/realistic", "realistic", "deterministic", [run(1.0)])
        wrong = row("f8/realistic x3", "wrong_config", "deterministic", [run(1.2)])
        wrong.update(twin="f8/realistic", target_ratio=1.1)
        offset = row("pan/offset20ms", "offset", "deterministic", [run(1.1)])
        offset.update(twin="pan/noisy", target_ratio=1.2, turn_deg_s=(70.0, 120.0))
        synced = row("pan/noisy", "noisy", "deterministic", [run(1.0)])
        lines = rep.sensor_lines([right, wrong, offset, synced])
        self.assertEqual(len(lines), 4)  # header, separator, the two twinned rows
        self.assertIn("| f8/realistic x3 | f8/realistic | – / – | 1.20 | 1.00 | 1.20 | <= 1.1 | **no** |", lines)
        self.assertIn("| pan/offset20ms | pan/noisy | 70 / 120 | 1.10 | 1.00 | 1.10 | <= 1.2 | yes |", lines)
        self.assertEqual(rep.sensor_lines([right, synced]), [])  # nothing twinned: no table

    def test_missing_twin_is_shown_not_judged(self):
        alone = row("f8/realistic x3", "wrong_config", "deterministic", [run(1.2)])
        alone.update(twin="f8/realistic", target_ratio=1.1)
        self.assertTrue(rep.sensor_lines([alone])[2].endswith("| – | <= 1.1 | – |"))


class Rows(unittest.TestCase):
    def args(self, **kw):
        base = dict(scenes=None, trajectories=None, seeds=None, quick=False, quick_sensors=False, sensor=None,
                    noise="both", slam_noise="1", sim_config=None, cache="/c", frames=300, work="/w")
        return type("Args", (), dict(base, **kw))()

    def test_ideal_and_default_keep_the_old_ids_and_caches(self):
        r = rows.sensor_row("office", "loop", "default", 101, 1)
        self.assertEqual(r["row"], "office/loop/noisy/s101")
        self.assertEqual(rows.seq_dir(self.args(), r), "/c/office_loop_noisy_s101_n300")
        self.assertEqual(rows.sensor_row("office", "loop", "ideal", 101, 1)["group"], "clean")
        self.assertEqual(len(rows.sim_rows(self.args(quick=True))), 12)

    def test_sensor_and_wrong_config_rows_name_their_twins(self):
        wrong = rows.sensor_row("office", "loop", "realistic", 101, 0.3)
        self.assertEqual((wrong["row"], wrong["twin"], wrong["group"]),
                         ("office/loop/realistic/s101 slam-noise x0.3", "office/loop/realistic/s101", "wrong_config"))
        offset = rows.sensor_row("office", "handheld_pan", "offset20", 101, 1)
        self.assertEqual((offset["twin"], offset["target_ratio"]), ("office/handheld_pan/noisy/s101", 1.2))
        picked = rows.sim_rows(self.args(sensor="default,realistic", scenes="office", seeds="1", slam_noise="1,3"))
        self.assertEqual(len(picked), 5 * 2 * 2)
        self.assertEqual(len(rows.sim_rows(self.args(quick_sensors=True))), 7)
        # A preset is the run's config: the two wrong-config rows cannot be run with it.
        preset = rows.sim_rows(self.args(quick_sensors=True, sim_config="/p/vr.yaml"))
        self.assertEqual(len(preset), 5)
        self.assertTrue(all(r["config"] == "/p/vr.yaml" and r["row"].endswith(" +vr.yaml") for r in preset))


class Pivot(unittest.TestCase):
    def test_cell_is_median_over_seeds_per_noise_with_lost_rows(self):
        def sim(seed, group, ate, lost=0):
            r = row(f"office/loop/{group}/s{seed}", group, "deterministic", [run(ate, lost=lost)])
            r.update(scene="office", trajectory="loop")
            return r
        rows = [sim(1, "clean", 1.0), sim(2, "clean", 3.0), sim(1, "noisy", 2.0, lost=4)]
        self.assertEqual(rep.pivot_lines(rows)[-1], "| loop | 2.00 / 2.00 (1 lost) |")


class Compare(unittest.TestCase):
    def test_ratio_and_medians(self):
        a = [row("x", "clean", "deterministic", [run(1.0)]), row("y", "clean", "deterministic", [run(2.0)])]
        b = [row("x", "clean", "deterministic", [run(0.5)]), row("y", "clean", "deterministic", [run(2.2)])]
        text = "\n".join(rep.compare_lines(a, b, "old", "new"))
        self.assertIn("| x | det | 1.00 | 0.50 | 0.500 |", text)
        self.assertIn("| clean | deterministic | 2 | 1.50 | 1.35 | 0.800 | 1 | 1 | 0 | 0 |", text)


def load_tests(loader, tests, ignore):
    tests.addTests(doctest.DocTestSuite(rep))
    return tests


if __name__ == "__main__":
    unittest.main()
