# SPDX-License-Identifier: GPL-3.0-or-later
"""A retrieval experiment from Python, as `canonform retrieve` runs it, then the same measures
recomputed from the run's distance matrix.

    python3 examples/python/retrieval.py [DATASET OUT]

DATASET: a folder with the meshes and labels.csv (path,class rows), e.g. /work/data/tosca_r5k;
default: a small procedural collection written to OUT/collection (2 body types x 3 poses).
"""
import os
import sys

import canonform

if len(sys.argv) > 2:
    dataset, out = sys.argv[1], sys.argv[2]
else:  # a collection of our own: 6 figures, 2 classes
    out = sys.argv[1] if len(sys.argv) > 1 else "retrieval_run"
    dataset = os.path.join(out, "collection")
    os.makedirs(dataset, exist_ok=True)
    rows = ["path,class"]
    for body in ("standard", "long-arms"):
        for pose in range(3):
            name = f"{body}_{pose}.ply"
            canonform.write_mesh(os.path.join(dataset, name), *canonform.figure(800, pose=pose, body=body))
            rows.append(f"{name},{body}")
    with open(os.path.join(dataset, "labels.csv"), "w") as f:
        f.write("\n".join(rows) + "\n")

# --- the example of docs/python.md ---
# (the wheel has no FAISS, so no "kmeans" codebooks: "lloyd", our own k-means, is in every build)
codebook = "kmeans" if "kmeans" in canonform.codebook_methods() else "lloyd"
run = canonform.retrieve(dataset, os.path.join(out, "run"), ["none", "euclidean-N"], words=50, codebook=codebook,
                         log=print)
for method, r in run["methods"].items():
    m = r["measures"]
    print(f"{method:12s} NN {m['nn']:.3f}  1-tier {m['first_tier']:.3f}  DCG {m['dcg']:.3f}")

# the measures again, from the distance matrix and the models' classes the run wrote
folder = run["methods"]["euclidean-N"]["folder"]
D = canonform.read_distance_matrix(os.path.join(folder, "distances.bin"))
labels = [cls for _, cls in canonform.read_labels(os.path.join(folder, "models.csv"))[1:]]  # after "name,class"
assert canonform.evaluate(D, labels)["micro"] == run["methods"]["euclidean-N"]["measures"]["micro"]
