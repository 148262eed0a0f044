# SPDX-License-Identifier: GPL-3.0-or-later
"""A method's distance matrix from a finished `canonform retrieve` run, for the scripts in tools/.

load_method(folder) reads FOLDER/models.csv (name,class per model, in matrix order) and
FOLDER/distances.bin (little-endian float32, #models x #models) of one method folder (RUN/METHOD)
and returns (names, classes by name, D as float64); a missing file or a matrix of the wrong size
ends the script with the reason.
"""
import csv
import os
import sys

import numpy as np


def load_method(folder):
    for f in ("models.csv", "distances.bin"):
        if not os.path.isfile(os.path.join(folder, f)):
            sys.exit("no %s (is %s a method folder of a finished run?)" % (os.path.join(folder, f), folder))
    rows = list(csv.DictReader(open(os.path.join(folder, "models.csv"))))
    names = [r["name"] for r in rows]
    D = np.fromfile(os.path.join(folder, "distances.bin"), dtype="<f4")
    if D.size != len(names) ** 2:
        sys.exit("%s: distances.bin has %d entries, models.csv %d models" % (folder, D.size, len(names)))
    return names, {r["name"]: r["class"] for r in rows}, D.reshape(len(names), len(names)).astype(np.float64)
