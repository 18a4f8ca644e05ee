# SPDX-License-Identifier: MIT
"""The Python module against the C library: the same bits (sim_world_hash), frames as NumPy
views, checkpoints, errors."""
import os
import subprocess
import tempfile
import unittest

import numpy as np

import support
import sablier
from abi_probe import compiler

C_STEP = r"""
#include "sim/sim.h"
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
/* Loads a state written by the Python module, with the golden "spring" materials, steps it
 * and prints the hash: the C side of the Python-vs-C comparison. */
int main(int argc, char **argv)
{
    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.species_count = 1;
    def.materials[0] = sim_material_default();
    def.materials[0].density = 1000.0;
    def.materials[0].normal_stiffness = 1e5;
    def.materials[0].tangential_stiffness = 7.5e4;
    def.materials[0].friction = 0.5;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.6;
    def.time_step = 2e-5;
    def.skin = atof(argv[3]);
    SimError err;
    SimWorld *w = sim_world_load(argv[1], &def, &err);
    if (!w || sim_world_restore_contacts(w, argv[1], &err) != SIM_OK) {
        fprintf(stderr, "%s: %s\n", err.field, err.message);
        return 2;
    }
    if (sim_world_step(w, atol(argv[2]), &err) != SIM_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    printf("%016" PRIx64 "\n", sim_world_hash(w));
    sim_world_destroy(w);
    return 0;
}
"""

SPRING = dict(density=1000.0, k_n=1e5, k_t=7.5e4, mu=0.5, restitution=0.6)


def lattice_world(skin=0.01):
    """120 grains on a jittered lattice in a box, from NumPy arrays."""
    rng = np.random.default_rng(3)
    i, j = np.meshgrid(np.arange(12), np.arange(10))
    x = 0.1 + 0.105 * i.ravel() + rng.uniform(-0.002, 0.002, i.size)
    y = 0.1 + 0.105 * j.ravel()
    r = rng.uniform(0.045, 0.05, i.size)
    return sablier.World.from_arrays(
        x, y, r, vx=rng.uniform(-0.1, 0.1, i.size), materials=[SPRING], effects=["friction"],
        contact=dict(tangential="spring"), time_step=2e-5, skin=skin,
        walls=[(0, 0, 1.4, 0), (0, 0, 0, 2), (1.4, 0, 1.4, 2)])


class Library(unittest.TestCase):
    def test_the_library_comes_from_sablier_lib_dir(self):
        where = os.environ.get("SABLIER_LIB_DIR")
        if not where:
            self.skipTest("SABLIER_LIB_DIR not set")
        path = os.path.realpath(sablier.library_path())
        self.assertTrue(path.startswith(os.path.realpath(where)), path)


class GoldenHashes(unittest.TestCase):
    def test_every_golden_trajectory_gives_the_c_hash(self):
        # the same worlds as tests/sim/test_golden.c, built and stepped from Python
        for name, case in support.GOLDEN.items():
            with self.subTest(case=name):
                with support.golden_world(name) as w:
                    w.step(3000)
                    self.assertEqual(w.step_count, 3000)
                    self.assertEqual(w.hash(), case[-1], "%s: 0x%016x" % (name, w.hash()))


class Threads(unittest.TestCase):
    def test_threaded_step_gives_the_same_bits(self):
        a, b = support.golden_world("spring"), support.golden_world("spring")
        b.threads = 2
        a.step(3000)
        b.step(3000)
        self.assertEqual(a.hash(), b.hash())
        self.assertEqual(b.hash(), support.GOLDEN["spring"][-1])


class PythonAgainstC(unittest.TestCase):
    def test_world_from_arrays_steps_to_the_same_bits_as_a_c_program(self):
        cc = compiler()
        if cc is None:
            self.skipTest("no C compiler")
        lib = sablier.library_path()
        with tempfile.TemporaryDirectory() as tmp:
            src, exe = os.path.join(tmp, "step.c"), os.path.join(tmp, "step")
            with open(src, "w") as f:
                f.write(C_STEP)
            subprocess.run([cc, "-std=c17", "-I", support.SOURCE_DIR, src, lib,
                            "-Wl,-rpath," + os.path.dirname(lib), "-o", exe], check=True)
            w = lattice_world()
            w.step(500)  # contacts with spring history by now
            state = w.save(os.path.join(tmp, "a.state"))
            w.step(1500)
            c_hash = subprocess.run([exe, state, "1500", repr(w.skin)], check=True,
                                    capture_output=True, text=True).stdout.strip()
            print("\npython 0x%016x, C %s" % (w.hash(), c_hash))
            self.assertEqual("%016x" % w.hash(), c_hash)
            w.close()


class Frames(unittest.TestCase):
    def test_frame_arrays_are_views_over_the_c_state(self):
        w = lattice_world()
        w.step(25000)  # 0.5 s: a pile
        f = w.frame()
        self.assertEqual(f.count, 120)
        self.assertEqual(f.x.dtype, np.float64)
        self.assertFalse(f.x.flags.owndata)  # a view, not a copy
        self.assertFalse(f.x.flags.writeable)
        self.assertGreater(f.contacts.size, 50)
        self.assertTrue(np.all(f.contacts["normal_force"][f.contacts["overlap"] > 0] >= 0))
        self.assertEqual(f.walls.size, 3)
        k = f.copy()
        e = w.energy()
        with self.assertRaises(sablier.StaleFrame):  # energy() rebuilt the frame's arrays
            f.vx
        self.assertAlmostEqual(e["kinetic"], 0.5 * np.sum(
            1000 * np.pi * k.radius ** 2 * (k.vx ** 2 + k.vy ** 2)), delta=1e-9 + 1e-9 * e["kinetic"])
        w.step(10)
        f2 = w.frame()
        self.assertEqual(sorted(f2.id.tolist()), list(range(120)))
        # follow grains by stable id; the copy kept the old values
        idx = f2.index_of(k.id)
        self.assertTrue(np.all(idx >= 0))
        self.assertTrue(np.all(np.abs(f2.y[idx] - k.y) < 0.01))
        self.assertEqual(k.step, 25000)

    def test_contact_forces_balance_gravity_at_rest(self):
        w = lattice_world()
        w.run_for(3.0)
        f = w.frame()
        m = 1000 * np.pi * f.radius ** 2
        # fy of the contacts (no gravity) carries the weight of the pile on average
        self.assertAlmostEqual(np.sum(f.fy) / np.sum(m * 9.806), 1.0, delta=0.03)


class Checkpoints(unittest.TestCase):
    def test_save_and_load_continue_bit_for_bit(self):
        with tempfile.TemporaryDirectory() as tmp:
            a = lattice_world()
            a.step(800)
            path = a.save(os.path.join(tmp, "a.state"))
            a_time_at_save = a.time
            a.step(700)
            b = sablier.World.from_state(path, materials=[SPRING], effects=["friction"],
                                         contact=dict(tangential="spring"), time_step=2e-5,
                                         skin=lattice_world().skin)
            # version-2 states continue exactly: the step count and time go on from the save
            self.assertEqual(b.step_count, 800)
            self.assertEqual(b.time, a_time_at_save)
            b.step(700)
            self.assertEqual(a.hash(), b.hash())

    def test_missing_state_is_an_io_error(self):
        with self.assertRaises(sablier.StateIOError):
            sablier.World.from_state("/nonexistent/x.state")


class Errors(unittest.TestCase):
    def test_bad_definitions_are_refused_with_the_field(self):
        with self.assertRaises(sablier.InvalidDefinition) as e:
            sablier.World.from_arrays([0.0], [0.0], [-1.0], time_step=1e-5)
        self.assertIn("grains", e.exception.field)
        with self.assertRaises(sablier.InvalidDefinition):
            sablier.World.from_arrays([0.0], [0.0], [1.0], effects=["teleport"])
        with self.assertRaises(sablier.InvalidDefinition):
            sablier.World.from_arrays([0.0, 1.0], [0.0], [1.0])

    def test_blow_up_is_reported_and_rolled_back(self):
        # two grains pushed deep into each other at a huge speed
        w = sablier.World.from_arrays([0.0, 0.0999], [0.0, 0.0], [0.05, 0.05],
                                      vx=[500.0, -500.0], gravity=(0, 0), time_step=1e-4,
                                      max_initial_overlap=1.0, guard_every=1,
                                      materials=[dict(density=1000.0, k_n=1e3)])
        with self.assertRaises(sablier.Unstable) as e:
            w.step(1000)
        self.assertGreaterEqual(e.exception.step, 0)


class BodyForce(unittest.TestCase):
    def test_python_body_force_is_applied(self):
        def push(view):
            view.fx += view.mass * 2.0  # a uniform acceleration of 2 m/s^2 along x

        w = sablier.World.from_arrays([0.0], [0.0], [0.05], gravity=(0, 0), time_step=1e-4,
                                      effects=["fluid_drag"], body_force=push)
        w.step(1000)
        f = w.frame()
        self.assertAlmostEqual(f.vx[0], 2.0 * 0.1, places=9)
        self.assertAlmostEqual(f.x[0], 0.5 * 2.0 * 0.1 ** 2, places=6)


if __name__ == "__main__":
    unittest.main()
