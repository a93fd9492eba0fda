"""tools/resequence_tum.py on a hand-made 5-frame TUM folder: every 2nd frame backwards gives
source frames 4, 2, 0 at 0, 0.1, 0.2 s (--fps 10), the ground truth of each source frame moves with
it, the image folders are links; --start 3 keeps source frames 3, 4 (and --reverse after it 4, 3);
a --start past the end and a malformed associations line name the file.
Debian's python3, stdlib only."""
import os
import subprocess
import sys
import tempfile
import unittest

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "resequence_tum.py")


def lines(path):
    with open(path) as f:
        return [l.rstrip("\n") for l in f if not l.startswith("#")]


class Resequence(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.src = os.path.join(self.tmp.name, "src")
        os.makedirs(os.path.join(self.src, "rgb"))
        os.makedirs(os.path.join(self.src, "depth"))
        with open(os.path.join(self.src, "associations.txt"), "w") as f:
            f.write("# t_rgb rgb t_depth depth\n")
            for i in range(5):
                f.write(f"{i}.5 rgb/{i}.png {i}.51 depth/{i}.png\n")
        with open(os.path.join(self.src, "groundtruth.txt"), "w") as f:
            for i in range(5):
                f.write(f"{i}.5 {i} 0 0 0 0 0 1\n")
        with open(os.path.join(self.src, "camera.yaml"), "w") as f:
            f.write("fx: 525\n")

    def tearDown(self):
        self.tmp.cleanup()

    def run_tool(self, *args):
        return subprocess.run([sys.executable, TOOL, self.src, os.path.join(self.tmp.name, "out"), *args],
                              capture_output=True, text=True)

    def test_every_second_frame_backwards(self):
        r = self.run_tool("--stride", "2", "--reverse", "--fps", "10")
        self.assertEqual(r.returncode, 0, r.stderr)
        out = os.path.join(self.tmp.name, "out")
        self.assertEqual(lines(os.path.join(out, "associations.txt")),
                         ["0.000000 rgb/4.png 0.000000 depth/4.png", "0.100000 rgb/2.png 0.100000 depth/2.png",
                          "0.200000 rgb/0.png 0.200000 depth/0.png"])
        self.assertEqual(lines(os.path.join(out, "rgb.txt")), ["0.000000 rgb/4.png", "0.100000 rgb/2.png", "0.200000 rgb/0.png"])
        self.assertEqual(lines(os.path.join(out, "depth.txt")),
                         ["0.000000 depth/4.png", "0.100000 depth/2.png", "0.200000 depth/0.png"])
        self.assertEqual(lines(os.path.join(out, "groundtruth.txt")),
                         ["0.000000 4 0 0 0 0 0 1", "0.100000 2 0 0 0 0 0 1", "0.200000 0 0 0 0 0 0 1"])
        self.assertTrue(os.path.islink(os.path.join(out, "rgb")))
        self.assertEqual(os.path.realpath(os.path.join(out, "depth")), os.path.realpath(os.path.join(self.src, "depth")))
        self.assertEqual(lines(os.path.join(out, "camera.yaml")), ["fx: 525"])

    def test_later_start_then_backwards(self):
        r = self.run_tool("--start", "3")
        self.assertEqual(r.returncode, 0, r.stderr)
        out = os.path.join(self.tmp.name, "out")
        self.assertEqual(lines(os.path.join(out, "rgb.txt")), ["0.000000 rgb/3.png", "0.033333 rgb/4.png"])
        self.assertEqual(lines(os.path.join(out, "groundtruth.txt")),
                         ["0.000000 3 0 0 0 0 0 1", "0.033333 4 0 0 0 0 0 1"])
        r = self.run_tool("--start", "3", "--reverse", "--fps", "10")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(lines(os.path.join(out, "depth.txt")), ["0.000000 depth/4.png", "0.100000 depth/3.png"])

    def test_start_past_the_end_is_refused(self):
        r = self.run_tool("--start", "5")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--start 5 leaves no frame", r.stderr)
        self.assertIn("lists 5", r.stderr)

    def test_bad_line_names_file_and_line(self):
        with open(os.path.join(self.src, "associations.txt"), "a") as f:
            f.write("9.5 rgb/9.png\n")
        r = self.run_tool()
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("associations.txt line 7", r.stderr)


if __name__ == "__main__":
    unittest.main()
