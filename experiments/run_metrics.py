# SPDX-License-Identifier: GPL-3.0-or-later
"""Reading a `canonform retrieve` run: the metrics.json of each method folder (plot_beta.py, plot_noise.py)."""
import json
import os

MEASURES = ["nn", "first_tier", "second_tier", "e_measure", "dcg"]


def method_metrics(run):
    """(folder, metrics.json) of every method folder of RUN, sorted by folder; folders without one skipped."""
    for d in sorted(os.listdir(run)):
        path = os.path.join(run, d, "metrics.json")
        if os.path.isfile(path):
            with open(path) as f:
                yield d, json.load(f)
