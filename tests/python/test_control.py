# SPDX-License-Identifier: MIT
"""In-process control (docs/python.md): setters, gravity, motions checked as scene files,
coarse-grained fields, stale views, the in-process stage runner with callbacks, and the round
trip: a scene file and the same world built in Python give the same bits."""
import os
import tempfile
import unittest
import warnings

import numpy as np

import support
import sablier

G = 9.806

SCENE = """name = "round_trip"; seed = 1; mass_model = "disk";
effects = ["friction", "vibration"];
time = { dt = 2e-5; end = 0.02; };
contact = { normal = "linear"; tangential = "spring"; clip_tensile = true; };
species = ( { name = "glass"; density = 2500.0; k_n = 2e4; restitution = 0.6; mu = 0.4;
              k_t = 1.5e4; },
            { name = "steel"; density = 7800.0; k_n = 3e4; critical_fraction = 0.3; mu = 0.2;
              k_t = 2e4; } );
motions = { shake = { amplitude = 0.0005; frequency = 20.0; direction = [0.0, 1.0];
                      ramp = 0.005; }; };
walls = ( { from = [0.0, 0.0]; to = [0.02, 0.0]; species = "steel"; motion = "shake"; },
          { from = [0.0, 0.0]; to = [0.0, 0.03]; species = "steel"; },
          { from = [0.02, 0.0]; to = [0.02, 0.03]; species = "steel"; } );
grains = { list = ( %s ); };
stages = ( { name = "one"; time = { end = 0.02; }; } );
"""


def grains():
    x = np.array([0.003, 0.0061, 0.0092, 0.0123, 0.0154, 0.0045, 0.0076, 0.0107, 0.0138])
    y = np.array([0.0013] * 5 + [0.0037] * 4)
    r = np.array([0.0011, 0.001, 0.0012, 0.001, 0.0011, 0.0012, 0.001, 0.0011, 0.0012])
    species = np.array([0, 1, 0, 0, 1, 0, 0, 1, 0])
    return x, y, r, species


def write_scene(folder):
    x, y, r, s = grains()
    items = ", ".join("{ x = %r; y = %r; r = %r; species = %d; }" % (a, b, c, d)
                      for a, b, c, d in zip(x, y, r, s))
    path = os.path.join(folder, "round_trip.scene")
    with open(path, "w") as f:
        f.write(SCENE % items)
    return path


def python_world():
    x, y, r, s = grains()
    materials = [dict(density=2500.0, k_n=2e4, restitution=0.6, mu=0.4, k_t=1.5e4),
                 dict(density=7800.0, k_n=3e4, critical_fraction=0.3, mu=0.2, k_t=2e4)]
    walls = [(0, 0, 0.02, 0, 1, 0), (0, 0, 0, 0.03, 1), (0.02, 0, 0.02, 0.03, 1)]
    motions = {"shake": dict(amplitude=0.0005, frequency=20.0, direction=(0.0, 1.0),
                             ramp=0.005)}
    return sablier.World.from_arrays(x, y, r, species=s, walls=walls, materials=materials,
                                     motions=motions, effects=["friction", "vibration"],
                                     contact=dict(normal="linear", tangential="spring",
                                                  clip_tensile=True),
                                     mass_model="disk", time_step=2e-5)


def drop(n=20):
    """n grains of radius 1 mm in a row over a floor, 1 mm above it, at rest."""
    x = 0.003 * np.arange(n) + 0.002
    return sablier.World.from_arrays(x, np.full(n, 0.002), np.full(n, 0.001),
                                     walls=[(0, 0, 0.003 * n + 0.002, 0)],
                                     materials=[dict(density=2500.0, k_n=1e4,
                                                     restitution=0.5)],
                                     time_step=1e-5)


@unittest.skipUnless(support.has_scene_library(), "libsablier-scene not built")
class Control(unittest.TestCase):
    def test_negative_step_and_missing_scene(self):
        w = drop()
        with self.assertRaises(ValueError):
            w.step(-5)
        self.assertEqual(w.step_count, 0)
        with self.assertRaises(FileNotFoundError):
            sablier.Scene("/nonexistent/x.scene")
        with self.assertRaises(FileNotFoundError):
            sablier.Run("/nonexistent/x.scene")
        with self.assertRaises(FileNotFoundError):
            sablier.run("/nonexistent/x.scene", "/nonexistent/out")
        with self.assertRaises(FileNotFoundError):
            sablier.World.from_state("/nonexistent/x.state")

    def test_a_kept_view_refuses_to_read_the_next_state(self):
        w = drop()
        f = w.frame()
        kept = w.frame(copy=True)
        y0 = kept.y.copy()
        g = w.frame()  # a new frame: f is stale too (the contact list is rebuilt)
        with self.assertRaises(sablier.StaleFrame):
            f.y
        w.step(10)
        self.assertTrue(g.stale)
        with self.assertRaises(sablier.StaleFrame):
            g.x
        self.assertEqual(g.count, 20)  # scalars are copies
        np.testing.assert_array_equal(kept.y, y0)
        self.assertFalse(kept.stale)

    def test_setters_positions_velocities_radii_fixed(self):
        w = drop()
        f = w.frame()
        ids = f.id[:3].copy()
        w.set_positions([0.01, 0.02, 0.03], [0.05, 0.05, 0.05], ids=ids)
        w.set_velocities([1.0, 0.0, 0.0], [0.0, 2.0, 0.0], ids=ids)
        w.set_radii(0.0015, ids=ids[2:])
        f = w.frame()
        k = f.index_of(ids)
        np.testing.assert_array_equal(f.x[k], [0.01, 0.02, 0.03])
        np.testing.assert_array_equal(f.vy[k], [0.0, 2.0, 0.0])
        self.assertEqual(f.radius[k[2]], 0.0015)
        self.assertAlmostEqual(w.masses()[k[2]], 2500.0 * np.pi * 0.0015 ** 2, delta=1e-15)
        w.set_fixed(True, ids=ids[:1])
        self.assertEqual(w.mobile_count, 19)
        w.step(100)
        f = w.frame()
        self.assertEqual(f.x[f.index_of(ids[0])[0]], 0.01)  # held
        self.assertAlmostEqual(f.vy[f.index_of(ids[1])[0]], 2.0 - G * 1e-3, delta=1e-9)
        with self.assertRaises(sablier.InvalidDefinition) as e:
            w.set_radii(-1.0, ids=ids[:1])
        self.assertIn("radius", str(e.exception))
        with self.assertRaises(sablier.InvalidDefinition):
            w.set_positions(0.0, 0.0, ids=[12345])

    def test_gravity_and_motions(self):
        w = drop()
        w.gravity = (0.0, 0.0)
        w.step(100)
        self.assertEqual(float(np.abs(w.frame().vy).max()), 0.0)
        w.gravity = (0.0, -2 * G)
        w.step(100)
        self.assertAlmostEqual(float(w.frame().vy[0]), -2 * G * 1e-3, delta=1e-9)
        with self.assertRaises(sablier.InvalidDefinition) as e:
            sablier.World.from_arrays([0.0], [0.01], [0.001], effects=["vibration"],
                                      motions={"shake": dict(amplitude=0.001, frequency=5,
                                                             amplitdue=3)})
        self.assertIn("amplitdue", str(e.exception))
        with self.assertRaises(sablier.InvalidDefinition) as e:
            sablier.World.from_arrays([0.0], [0.01], [0.001], effects=["vibration"],
                                      motions=[dict(kind="velocity")])
        self.assertIn("velocity", str(e.exception))
        w = sablier.World.from_arrays([0.01], [0.01], [0.001], effects=["vibration"],
                                      walls=[(0, 0, 0.02, 0, 0, 0)], time_step=1e-5,
                                      materials=[dict(density=2500.0, k_n=1e4)],
                                      motions={"lift": dict(kind="velocity",
                                                            velocity=(0.0, 0.1))})
        w.set_motion("lift", on=float("inf"))  # never: the wall stays
        w.step(100)
        self.assertEqual(w.frame().walls["y0"][0], 0.0)

    def test_material_keys_are_the_scene_keys(self):
        m = sablier.material(density=1000.0, k_n=1e5, mu=0.3)
        self.assertEqual((m.normal_stiffness, m.friction), (1e5, 0.3))
        self.assertEqual((m.damping_mode, m.normal_damping), (0, 0.0))  # elastic, as scenes
        self.assertEqual(sablier.material(restitution=0.5).damping_mode, 1)
        with self.assertRaises(sablier.InvalidDefinition) as e:
            sablier.material(k_m=1.0)
        self.assertIn("k_m", str(e.exception))
        with self.assertRaises(sablier.InvalidDefinition):
            sablier.material(restitution=0.5, gamma_n=3.0)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            m = sablier.material(normal_stiffness=2e5, friction=0.1)
        self.assertEqual((m.normal_stiffness, m.friction), (2e5, 0.1))
        self.assertTrue(all(issubclass(c.category, DeprecationWarning) for c in caught))
        self.assertEqual(len(caught), 2)

    def test_coarse_grained_stress_of_a_resting_layer(self):
        w = drop(30)
        w.step(20000)  # 0.2 s: the layer rests on the floor
        cell = 0.0002
        cg = w.coarse(["syy", "rho"], geometry="profile_y", box=(0.0005, -0.002, 0.0905, 0.004),
                      cell=cell, width=0.0005)
        self.assertEqual(cg["syy"].shape, cg["y"].shape)
        # sigma_yy of each grain's floor contact spans its branch (one radius): its integral
        # over y is the weight per length of floor times the radius (30 grains in 0.09 m)
        weight = 2500.0 * np.pi * 0.001 ** 2 * G * 30 / 0.09  # N/m
        self.assertAlmostEqual(float(cg["syy"].sum()) * cell / (weight * 0.001), 1.0, delta=0.02)
        self.assertEqual(float(cg["syy"][cg["y"] < -0.0006].max()), 0.0)  # nothing below
        with self.assertRaises(sablier.InvalidDefinition):
            w.coarse(["sigma"])

    def test_round_trip_scene_file_and_python_world_same_bits(self):
        with tempfile.TemporaryDirectory() as tmp:
            from_file = sablier.World.from_scene(write_scene(tmp))
            from_python = python_world()
            self.assertEqual(from_file.hash(), from_python.hash())
            from_file.step(1000)
            from_python.step(1000)
            print("\nscene 0x%016x, python 0x%016x" % (from_file.hash(), from_python.hash()))
            self.assertEqual(from_file.hash(), from_python.hash())
            self.assertGreater(from_file.frame().contacts.size, 0)

    def test_in_process_stages_with_a_callback(self):
        with tempfile.TemporaryDirectory() as tmp:
            scene = write_scene(tmp)
            plain = sablier.Run(scene, os.path.join(tmp, "plain")).stages()
            calls = []

            def look(world, stage, step):
                calls.append((stage, step, world.step_count))
                world.frame().y  # readable inside

            looked = sablier.Run(scene, os.path.join(tmp, "looked")).stages(callback=look,
                                                                             every=250)
            self.assertEqual([c[1] for c in calls], [0, 250, 500, 750, 1000])
            self.assertEqual(calls[-1][0], "one")
            # looking changes nothing: the same bits as without a callback
            a = sablier.World.from_state(plain.states["one"], scene=scene)
            b = sablier.World.from_state(looked.states["one"], scene=scene)
            self.assertEqual(a.hash(), b.hash())
            kept = []

            def lift(world, stage, step):  # a servo that changes the state: no gravity
                kept.append(world)
                if step == 500:
                    world.gravity = (0.0, 0.0)
                    f = world.frame()
                    n = f.mobile_count
                    world.set_velocities(np.zeros(n), np.full(n, 0.1), ids=f.id[:n])

            lifted = sablier.Run(scene, os.path.join(tmp, "lifted")).stages(callback=lift,
                                                                             every=500)
            c = sablier.World.from_state(lifted.states["one"], scene=scene)
            self.assertGreater(c.frame().y.mean(), a.frame().y.mean())
            with self.assertRaises(ValueError):
                kept[0].frame()  # the runner's world outlives no callback

            def fail(world, stage, step):
                if step == 250:
                    raise KeyError("stop here")

            with self.assertRaises(KeyError):
                sablier.Run(scene, os.path.join(tmp, "failed")).stages(callback=fail,
                                                                       every=250)
            with self.assertRaises(ValueError):
                sablier.Run(scene).stages(callback=fail, every=0)


if __name__ == "__main__":
    unittest.main()
