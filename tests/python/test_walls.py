# SPDX-License-Identifier: MIT
"""World.wall_loads (sim_world_wall_load): the force of the grains on each wall, from Python,
equals the sum of that wall's contacts in the frame (normal forces along the contact normals,
the scene being frictionless and undamped), and a servo wall's offset and stress are there."""
import os
import unittest

import numpy as np

import support
import sablier

SCENE = os.path.join(support.SOURCE_DIR, "tests", "cli", "servo_lid.scene")


@unittest.skipUnless(support.has_scene_library(), "libsablier-scene not built")
class WallLoads(unittest.TestCase):
    def test_wall_loads_are_the_sums_of_the_wall_contacts(self):
        # undamped contacts: the frame's forces (evaluated again, with the step's end velocities)
        # are then the step's own, so the two sums agree to rounding
        scene = sablier.Scene(SCENE, ["species.0.gamma_n=0.0"])
        with sablier.World.from_scene(scene) as world:
            loads = world.wall_loads()
            self.assertEqual(len(loads), 4)
            self.assertEqual([l["normal"] for l in loads], [0.0] * 4)  # no step yet
            world.run_for(0.25)
            f = world.frame()
            loads = world.wall_loads()
            self.assertGreater(loads[0]["contacts"], 5)  # the base carries the bed
            for k, load in enumerate(loads):
                c = f.contacts[f.contacts["j"] == -1 - k]
                self.assertEqual(load["contacts"], len(c))
                fn = c["normal_force"]
                scale = max(1.0, abs(load["normal"]))
                self.assertAlmostEqual(load["normal"], fn.sum(), delta=1e-9 * scale)
                # the force on the wall pushes along n (from the grain towards the wall)
                self.assertAlmostEqual(load["fx"], (fn * c["nx"]).sum(), delta=1e-9 * scale)
                self.assertAlmostEqual(load["fy"], (fn * c["ny"]).sum(), delta=1e-9 * scale)
                self.assertAlmostEqual(load["stress"], load["normal"] / load["length"])
            self.assertAlmostEqual(loads[0]["length"], 2.0)
            self.assertLess(loads[0]["fy"], 0.0)  # the bed pushes the base down
            self.assertGreater(loads[3]["offset"], 0.05)  # the servo lid came down
            self.assertEqual(loads[0]["offset"], 0.0)


if __name__ == "__main__":
    unittest.main()
