# SPDX-License-Identifier: MIT
"""The installed module at work (run by tests/python/venv_install.sh with a virtual
environment's interpreter, outside the source tree): build a world from arrays, run a scene's
stage in this process with a callback every 50 steps that reads and changes the state, read the
coarse-grained stress, render a figure. Usage: venv_demo.py OUT_DIR."""
import os
import sys

import numpy as np

import sablier

out = sys.argv[1]
here = os.path.dirname(os.path.abspath(sablier.__file__))
print("sablier from", here)
assert "site-packages" in here, "not the installed module: " + here

# 1. a world from arrays: 60 grains dropped into a box
rng = np.random.default_rng(1)
x = np.tile(np.arange(10) * 0.0021 + 0.0015, 6)
y = np.repeat(np.arange(6) * 0.0021 + 0.0015, 10)
r = 0.001 * (1 + 0.05 * rng.random(60))
walls = [(0, 0, 0.024, 0), (0, 0, 0, 0.05), (0.024, 0, 0.024, 0.05)]
mat = dict(density=2500.0, k_n=1e4, restitution=0.5, mu=0.4, k_t=7.5e3)
w = sablier.World.from_arrays(x, y, r, walls=walls, materials=[mat], effects=["friction"],
                              contact=dict(tangential="spring"), time_step=1e-5)
w.step(20000)  # 0.2 s: the grains settle

# 2. the same box as a scene, run in this process with a callback
scene = os.path.join(out, "box.scene")
with open(scene, "w") as f:
    f.write('''name = "venv_box"; seed = 1; effects = ["friction"]; mass_model = "disk";
time = { dt = 1e-5; end = 0.03; };
contact = { tangential = "spring"; };
species = ( { name = "glass"; density = 2500.0; k_n = 1e4; restitution = 0.5; mu = 0.4;
              k_t = 7.5e3; } );
walls = ( { from = [0.0, 0.0]; to = [0.024, 0.0]; }, { from = [0.0, 0.0]; to = [0.0, 0.05]; },
          { from = [0.024, 0.0]; to = [0.024, 0.05]; } );
grains = { rain = { x0 = 0.001; x1 = 0.023; y0 = 0.001; y1 = 0.03; radius_mean = 0.001;
                    polydispersity = 0.05; max_count = 60; }; };
stages = ( { name = "fill"; time = { end = 0.03; }; } );
''')
seen = []


def callback(world, stage, step):
    f = world.frame()
    seen.append((stage, step, float(f.y[:f.mobile_count].mean())))
    if step == 1000:  # a nudge: every mobile grain gets an upward velocity
        n = f.mobile_count
        world.set_velocities(np.zeros(n), np.full(n, 0.05), ids=f.id[:n])


run = sablier.Run(scene, os.path.join(out, "run")).stages(callback=callback, every=500)
print("callbacks:", len(seen), "last:", seen[-1])
assert [s[1] for s in seen] == list(range(0, 3001, 500)), seen
assert run.summary["status"] == "ok"

# 3. the coarse-grained stress of the settled box
cg = w.coarse(["syy", "sxx", "phi"], box=(0.0, 0.0, 0.024, 0.014), cell=0.002)
syy = cg["syy"]
print("sigma_yy (N/m) at the bottom row:", np.round(syy[0], 3))
assert syy.shape == (7, 12) and np.isfinite(syy).all() and syy[0, 3:9].mean() > 0

# 4. a figure
png = os.path.join(out, "box.png")
w.render(png, width=240, height=480, color_by="force")
assert os.path.getsize(png) > 1000
print("figure", png)
