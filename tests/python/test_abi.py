# SPDX-License-Identifier: MIT
"""Every ctypes structure of sablier/_capi.py has the size and field offsets of its C struct
(a probe compiled against the source tree's headers)."""
import os
import tempfile
import unittest

import support
from sablier import _capi
import abi_probe


class Layout(unittest.TestCase):
    def test_structures_match_the_c_headers(self):
        if abi_probe.compiler() is None:
            self.skipTest("no C compiler")
        structs = dict(_capi.STRUCTS)
        # app/scene/scene.h includes libconfig.h; without its headers check sim and render only
        if not os.path.exists("/usr/include/libconfig.h"):
            structs = {k: v for k, v in structs.items() if v[0] != "scene/scene.h"}
        with tempfile.TemporaryDirectory() as tmp:
            c = abi_probe.c_table(structs, support.SOURCE_DIR, tmp)
        py = abi_probe.python_table(structs)
        self.assertGreater(len(c), 200)
        # Scene is mirrored up to its stages only: its offsets must match, not its size
        diffs = {k: (c[k], py[k]) for k in c if c[k] != py[k] and k != "Scene"}
        self.assertEqual(diffs, {}, "C (offset or size) vs ctypes")
        self.assertLessEqual(py["Scene"], c["Scene"])


if __name__ == "__main__":
    unittest.main()
