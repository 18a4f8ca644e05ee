# SPDX-License-Identifier: MIT
"""Scene files from Python (libsablier-scene) and whole runs through the `sablier` command:
the world a scene starts from is the CLI's, bit for bit; a run's outputs load as arrays."""
import os
import tempfile
import unittest

import numpy as np

import support
import sablier

SMALL = support.scene_path("brazil_nut", "small.scene")


@unittest.skipUnless(support.has_scene_library(), "libsablier-scene not built")
class Scenes(unittest.TestCase):
    def test_scene_attributes(self):
        s = sablier.Scene(SMALL, sets={"seed": 3})
        self.assertEqual(s.name, "bne_small")
        self.assertEqual(s.seed, 3)
        self.assertEqual(s.species_names, ["grain", "intruder", "wall"])
        self.assertEqual(s.stage_names, ["settle", "shake"])
        self.assertEqual(s.stage_index("shake"), 1)
        d = s.world_def("settle")
        self.assertEqual(d.raw.grains.count, 301)
        self.assertEqual(d.raw.wall_count, 3)
        self.assertAlmostEqual(d.raw.time_step, 1e-3)

    def test_bad_scene_reports_file_and_line(self):
        with self.assertRaises(sablier.InvalidDefinition) as e:
            sablier.Scene(SMALL, sets=["species.0.k_n=-1"])
        self.assertIn("k_n", str(e.exception))
        with self.assertRaises(FileNotFoundError):
            sablier.Scene("/nonexistent.scene")

    def test_world_from_scene_matches_the_cli_checkpoint(self):
        exe = support.executable()
        if exe is None:
            self.skipTest("no sablier command")
        with tempfile.TemporaryDirectory() as tmp:
            sablier.run(SMALL, tmp, sets={"stages.settle.time.end": 0.1,
                                          "stages.shake.time.end": 0.2})
            w = sablier.World.from_scene(SMALL)
            w.step(100)  # the settle stage: 0.1 s at dt = 1e-3
            cli = sablier.World.from_state(os.path.join(tmp, "settle.state"), scene=SMALL)
            print("\npython 0x%016x, sablier run 0x%016x" % (w.hash(), cli.hash()))
            self.assertEqual(w.hash(), cli.hash())
            self.assertEqual(cli.time, w.time)


class Runs(unittest.TestCase):
    def setUp(self):
        if support.executable() is None:
            self.skipTest("no sablier command")

    def test_a_shortened_brazil_nut_run_loads_into_arrays(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = sablier.run(SMALL, tmp, sets={"stages.settle.time.end": 2.0,
                                                "stages.shake.time.end": 8.0}, pandas=False)
            bne = out.bne
            self.assertEqual(bne.dtype.names[:5], ("t", "t_shake", "cycles", "box_offset",
                                                   "intruder_y"))
            self.assertGreater(bne.size, 5)
            self.assertTrue(np.all(np.diff(bne["t"]) > 0))
            energy = out.energy
            self.assertEqual(energy["stage"][0], "settle")
            self.assertEqual(energy["stage"][-1], "shake")
            self.assertEqual(out.summary["status"], "ok")
            self.assertEqual(out.summary["mobile_grains"], 301)
            self.assertIn("rise_rate", out.bne_json)
            self.assertEqual(sorted(out.states), ["settle", "shake"])
            # intruder in the trace (id 0) and in bne.csv agree on its height
            trace = out.trace
            self.assertTrue(np.all(trace["id"] == 0))

    def test_failed_run_raises_with_the_exit_status(self):
        with tempfile.TemporaryDirectory() as tmp:
            with self.assertRaises(sablier.RunError) as e:
                sablier.run(SMALL, tmp, sets=["species.0.k_n=-1"])
            self.assertEqual(e.exception.returncode, 2)


class Tables(unittest.TestCase):
    def test_read_csv_types_columns(self):
        with tempfile.TemporaryDirectory() as tmp:
            p = os.path.join(tmp, "a.csv")
            with open(p, "w") as f:
                f.write("# comment\nt,n,stage\n0.5,1,settle\n1.5,,shake\n")
            a = sablier.read_csv(p, pandas=False)
            self.assertEqual(a.dtype.names, ("t", "n", "stage"))
            self.assertEqual(a["t"].tolist(), [0.5, 1.5])
            self.assertTrue(np.isnan(a["n"][1]))
            self.assertEqual(a["stage"].tolist(), ["settle", "shake"])
            kv = os.path.join(tmp, "observables.csv")
            with open(kv, "w") as f:
                f.write("key,value\nbed_coordination,3.5\n")
            self.assertEqual(sablier.load(tmp).observables, {"bed_coordination": 3.5})
            if not sablier.outputs.have_pandas():
                self.assertIsInstance(sablier.read_csv(p), np.ndarray)


if __name__ == "__main__":
    unittest.main()
