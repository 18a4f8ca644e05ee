# SPDX-License-Identifier: MIT
"""hello_sim.py (installed): hello_sim.c through the Python module over the installed libraries
(docs/python.md): the same 300-grain rain (seed 1) into a box of fixed grains, friction, sphere
masses, 50000 steps of 1e-5 s, and the same `hash 0x...` line, which must equal the C program's
to the bit (tests/install/check.sh).

    PYTHONPATH=<prefix>/lib/python3/dist-packages /usr/bin/python3 hello_sim.py
"""
import sablier

r_max = 0.105
width = 20 * 2 * r_max
buffer = sablier.GrainBuffer()
buffer.fixed_box(0.0, width, 0.0, 60 * r_max, r_max, 0)
buffer.rain(1, thesis000=(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, 300))
with sablier.World.from_arrays(grains=buffer, effects=["friction"], mass_model="sphere",
                               time_step=1e-5) as world:
    world.step(50000)
    print("sablier %s: %d grains, kernels %s" % (sablier.__version__, world.mobile_count,
                                                 sablier.isa()))
    print("hash 0x%016x" % world.hash())
