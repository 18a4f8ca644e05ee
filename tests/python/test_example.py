# SPDX-License-Identifier: MIT
"""docs/python.md's worked example (examples/python/brazil_nut_rise.py) runs, shortened, and
writes its rise curve."""
import os
import subprocess
import sys
import tempfile
import unittest

import support
import sablier


class BrazilNutExample(unittest.TestCase):
    def test_rise_curve_script(self):
        if support.executable() is None:
            self.skipTest("no sablier command")
        script = os.path.join(support.SOURCE_DIR, "examples", "python", "brazil_nut_rise.py")
        with tempfile.TemporaryDirectory() as tmp:
            r = subprocess.run([sys.executable, script, tmp, "--seeds", "2", "--shake", "12"],
                               capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            rise = sablier.read_csv(os.path.join(tmp, "rise.csv"), pandas=False)
            self.assertEqual(rise.dtype.names, ("cycle", "rise_mean", "rise_std"))
            self.assertEqual(rise.size, 3)  # 12 time units = 3 whole periods of 3.953
            figures = [n for n in ("rise.png", "final.png") if os.path.exists(
                os.path.join(tmp, n))]
            if sablier.render_available():
                self.assertTrue(figures, r.stdout)
            for n in figures:
                self.assertGreater(os.path.getsize(os.path.join(tmp, n)), 1000)

if __name__ == "__main__":
    unittest.main()
