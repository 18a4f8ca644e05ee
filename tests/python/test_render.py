# SPDX-License-Identifier: MIT
"""Figures from Python: render_figure_write through libsablier-render."""
import os
import tempfile
import unittest

import support
import sablier
from test_world import lattice_world


class Figures(unittest.TestCase):
    def test_png_of_a_world(self):
        if not sablier.render_available():
            self.skipTest("libsablier-render not built")
        w = lattice_world()
        w.step(5000)
        with tempfile.TemporaryDirectory() as tmp:
            p = w.render(os.path.join(tmp, "a.png"), width=320, height=240, color_by="force",
                         force_chains=True, title="from python")
            with open(p, "rb") as f:
                head = f.read(24)
            self.assertEqual(head[:8], b"\x89PNG\r\n\x1a\n")
            width = int.from_bytes(head[16:20], "big")
            height = int.from_bytes(head[20:24], "big")
            self.assertEqual((width, height), (320, 240))
            with self.assertRaises(ValueError):
                w.render(os.path.join(tmp, "b.png"), colour="red")


if __name__ == "__main__":
    unittest.main()
