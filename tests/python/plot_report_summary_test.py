"""tools/plot_report.py's numbers table (summary_rows) on hand-made metrics: skipped frames are
listed by index (the first 20, then "..."), and the row is absent when nothing was skipped; the
depth-scale warning is shown when the run gave one. Needs
Debian's numpy and matplotlib (the script imports them); exits 77 (ctest: skipped) without them."""
import os
import sys
import unittest

try:
    import numpy  # noqa: F401
    import matplotlib  # noqa: F401
except ImportError:
    print("numpy or matplotlib missing: skipped")
    sys.exit(77)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import plot_report  # noqa: E402

ROW = "frames skipped (unreadable files)"


class SummaryRows(unittest.TestCase):
    def test_skipped_frames_are_listed(self):
        m = {"frames": 43, "skipped_frames": [{"index": 20, "error": "a"}, {"index": 35, "error": "b"}]}
        self.assertEqual(dict(plot_report.summary_rows(m))[ROW], "20, 35")

    def test_long_lists_are_cut(self):
        m = {"frames": 10, "skipped_frames": [{"index": i, "error": "x"} for i in range(25)]}
        self.assertEqual(dict(plot_report.summary_rows(m))[ROW], ", ".join(str(i) for i in range(20)) + " ...")

    def test_no_row_without_skipped_frames(self):
        for m in ({"frames": 10}, {"frames": 10, "skipped_frames": []}):
            self.assertNotIn(ROW, dict(plot_report.summary_rows(m)))

    def test_depth_scale_warning_is_shown_when_given(self):
        w = "depth scale check: median depth 0.35 m ..."
        self.assertEqual(dict(plot_report.summary_rows({"frames": 3, "inputs": {"depth_scale_warning": w}}))
                         ["depth scale warning"], w)
        self.assertNotIn("depth scale warning", dict(plot_report.summary_rows({"frames": 3, "inputs": {}})))


if __name__ == "__main__":
    unittest.main()
