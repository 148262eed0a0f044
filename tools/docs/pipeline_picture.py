# SPDX-License-Identifier: GPL-3.0-or-later
"""Composes the pipeline picture from the tool's outputs (called by tools/docs/pipeline_picture.sh).

usage: pipeline_picture.py OUT.png MESH.png PANELS.png CONTACT_SHEET.png DESCRIPTOR.cfvd DISTANCES.csv
                           MODELS.csv LABELS.csv NAME

MESH.png is `canonform picture` of the mesh (one panel), PANELS.png its three panels (conformal
factor, feature points, canonical form), CONTACT_SHEET.png the 66 depth views of `canonform views`,
DESCRIPTOR.cfvd the model's histograms (format: src/canonform/views/descriptor_file.h), DISTANCES.csv
the run's clock-matching matrix with MODELS.csv its rows, LABELS.csv the classes, NAME the model shown.
"""
import csv
import os
import struct
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy  # noqa: E402


def read_histograms(path):
    """The (views x words) counts of a descriptor file written with a codebook."""
    data = open(path, "rb").read()
    if data[:4] != b"CFVD":
        sys.exit(f"{path}: not a descriptor file")
    (length,) = struct.unpack_from("<I", data, 8)
    pos = 12 + length
    views, _, words = struct.unpack_from("<iii", data, pos)
    pos += 12 + 4 * views
    if words <= 0:
        sys.exit(f"{path}: raw SIFT features, not histograms (no codebook)")
    h = numpy.zeros((views, words))
    for v in range(views):
        (nnz,) = struct.unpack_from("<I", data, pos)
        pos += 4
        for _ in range(nnz):
            w, c = struct.unpack_from("<if", data, pos)
            h[v, w] = c
            pos += 8
    return h


def crop(img):
    """The image without its white margins."""
    ink = (img[:, :, :3] < 0.97).any(axis=2)
    rows, cols = numpy.where(ink.any(axis=1))[0], numpy.where(ink.any(axis=0))[0]
    if len(rows) == 0:
        return img
    pad = 6
    return img[max(rows[0] - pad, 0):rows[-1] + pad, max(cols[0] - pad, 0):cols[-1] + pad]


def main():
    out, mesh_png, panels_png, sheet_png, desc, dist_csv, models_csv, labels_csv, name = sys.argv[1:10]
    mesh = matplotlib.image.imread(mesh_png)
    panels = matplotlib.image.imread(panels_png)
    w = panels.shape[1] // 3
    cuts = [panels[:, k * w + 2:(k + 1) * w - 1] for k in range(3)]
    sheet = matplotlib.image.imread(sheet_png)
    hist = read_histograms(desc)
    D = numpy.loadtxt(dist_csv, delimiter=",")
    with open(models_csv) as f:
        rows = list(csv.reader(f))
    models = [r[0] for r in rows[1:]] if rows and not rows[0][0].replace(".", "").isdigit() else [r[0] for r in rows]
    with open(labels_csv) as f:
        labels = {os.path.splitext(os.path.basename(r[0]))[0]: r[1] for r in csv.reader(f) if len(r) > 1}
    ticks = [f"{labels.get(os.path.splitext(os.path.basename(m))[0], '?')} {k}" for k, m in enumerate(models)]
    row = next((k for k, m in enumerate(models) if os.path.splitext(os.path.basename(m))[0] == name), 0)

    titles = ["1. mesh", "2. conformal factor", "3. feature points", "4. canonical form",
              "5. its 66 depth views", "6. bag of features per view", "7. clock-matching distances"]
    fig = plt.figure(figsize=(14, 7.6))
    grid = fig.add_gridspec(2, 12, height_ratios=[1, 1.05], hspace=0.3, wspace=1.2)
    axes = [fig.add_subplot(grid[0, 3 * k:3 * k + 3]) for k in range(4)]
    axes += [fig.add_subplot(grid[1, 0:5]), fig.add_subplot(grid[1, 5:8]), fig.add_subplot(grid[1, 8:12])]
    for ax, img in zip(axes[:4], [crop(mesh[28:, :])] + [crop(c[28:, :]) for c in cuts]):
        ax.imshow(img)
    axes[4].imshow(sheet)
    nz = hist[:, hist.sum(axis=0) > 0]
    axes[5].imshow(numpy.log1p(nz), aspect="auto", cmap="viridis", interpolation="nearest")
    axes[5].set_xlabel(f"visual words ({nz.shape[1]} of {hist.shape[1]} used)")
    axes[5].set_yticks([0, 65])
    axes[5].set_yticklabels(["view 1", "66"])
    axes[5].set_xticks([])
    off = D[~numpy.eye(len(D), dtype=bool)]
    im = axes[6].imshow(D, cmap="magma_r", interpolation="nearest", vmin=0.9 * off.min(), vmax=off.max())
    axes[6].set_xticks(range(len(ticks)))
    axes[6].set_xticklabels(ticks, rotation=90, fontsize=8)
    axes[6].set_yticks(range(len(ticks)))
    axes[6].set_yticklabels(ticks, fontsize=8)
    axes[6].add_patch(plt.Rectangle((-0.5, row - 0.5), len(ticks), 1, fill=False, edgecolor="tab:cyan", linewidth=2))
    fig.colorbar(im, ax=axes[6], fraction=0.046, pad=0.04)
    for k, (ax, t) in enumerate(zip(axes, titles)):
        ax.set_title(t, fontsize=12)
        if k < 5:
            ax.axis("off")
    for k in (0, 1, 2, 4, 5):
        axes[k].annotate("", xy=(1.16 if k < 4 else 1.12, 0.5), xytext=(1.02, 0.5), xycoords="axes fraction",
                         arrowprops={"arrowstyle": "-|>", "lw": 2, "color": "0.3"})
    fig.text(0.5, 0.505, "the canonical form (4) is rendered from 66 directions (5); SIFT features of each view become a "
             "histogram of visual words (6); clock matching compares models (7: this model's row framed; "
             "darker = farther)", ha="center", fontsize=10, color="0.3")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=100, bbox_inches="tight", pad_inches=0.15)
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
