# SPDX-License-Identifier: GPL-3.0-or-later
"""A mesh and its Euclidean canonical form side by side, coloured by the conformal factor.

    python3 examples/python/canonical_form.py [MESH] [OUT.png]

MESH: an OFF, PLY, OBJ or STL file (default: a procedural figure in pose 3). docs/python.md shows
the same lines; the tests run this script (tests/python/test_examples.py).
"""
import sys

import matplotlib
matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import canonform

# --- the example of docs/python.md ---
V, F = canonform.read_mesh(sys.argv[1]) if len(sys.argv) > 1 else canonform.figure(5000, pose=3)
Y, info = canonform.canonical_form(V, F)          # variant N, the tool's defaults
phi = canonform.conformal_factor(V, F)            # (#V,) in [0, 1]
print(f"{info['vertices']} vertices: {info['iterations']} SMACOF iterations, "
      f"stress {info['initial_stress']:.1f} -> {info['final_stress']:.1f}, {info['seconds']:.2f} s")

fig = plt.figure(figsize=(9, 4.5))
for k, (X, title) in enumerate([(V, "mesh"), (Y, "canonical form")]):
    ax = fig.add_subplot(1, 2, k + 1, projection="3d")
    ax.add_collection3d(Poly3DCollection(X[F], facecolors=plt.cm.viridis(phi[F].mean(axis=1)), linewidth=0))
    ax.auto_scale_xyz(*[(c.min(), c.max()) for c in X.T])
    ax.set_box_aspect(X.max(axis=0) - X.min(axis=0))
    ax.set_title(title)
    ax.set_axis_off()
fig.savefig(sys.argv[2] if len(sys.argv) > 2 else "canonical_form.png", dpi=100)
