# SPDX-License-Identifier: GPL-3.0-or-later
"""Retrieval: the measures of a distance matrix and whole experiments."""
import ctypes

from . import _support as S
from ._views import DEFAULT_CODEBOOK_SAMPLE


def evaluate(D, labels):
    """evaluate(D: object, labels: object) -> dict

The retrieval measures of a distance matrix (`canonform evaluate --json`),
psbTable's definitions (normalised by C-1).

D: a float (N, N) array or a distance-matrix file (float32 binary or .csv);
labels: N class names (any sequence; str() of each) or a labels file
(path,class rows). Returns a dict: micro and macro ({nn, first_tier,
second_tier, e_measure, dcg, queries}), classes ({class: measures}), precision
and recall (20 points: the averaged precision-recall curve), skipped_classes
(two models or fewer), and the five micro measures and queries again at the
top (d["nn"], ...)."""
    d_path, d = (S.path_in(D), None) if S.is_path(D) else (None, S.matrix_in(D, "D"))
    if S.is_path(labels):
        l_path, names = S.path_in(labels), []
    else:
        l_path, names = None, [str(x).encode("utf-8") for x in labels]
    n = len(names)
    out = ctypes.c_void_p()
    with S.Call() as call:
        call.done(S.lib().canonform_evaluate(S.ptr(d, ctypes.c_double), 0 if d is None else d.shape[0],
                                             0 if d is None else d.shape[1], d_path,
                                             (ctypes.c_char_p * n)(*names) if n else None, n, l_path, ctypes.byref(out)))
    return S.take_json(out)


def retrieve(dataset, out, methods=("none", "euclidean-N"), *, labels=None, words=1500, codebook="kmeans",
             codebook_sample=DEFAULT_CODEBOOK_SAMPLE, simplify=0, noise=0.0, seed=0, sift=None, repair=False, threads=0,
             log=None, progress=None):
    """retrieve(dataset: object, out: object, methods: object = ('none', 'euclidean-N'), *, labels: object = None, words: int = 1500, codebook: str = 'kmeans', codebook_sample: int = 100000, simplify: int = 0, noise: float = 0.0, seed: int = 0, sift: str | None = None, repair: bool = False, threads: int = 0, log: object = None, progress: object = None) -> dict

A retrieval experiment over a labelled collection, as `canonform retrieve` runs it:
per method, canonical forms, 66 views and SIFT per mesh (in parallel, cached in
OUT/cache), a codebook, histograms, clock-matching distances and the measures.
Writes the run folder `out` as the tool does (METHOD/distances.bin,
metrics.json, pr.csv, report.md, ...; no pictures) and reuses its cache.

dataset: the collection folder; labels: its labels file (default
DATASET/labels.csv); methods: a list of method specs ("euclidean-N:beta=65",
"fused:none+euclidean-N") or one comma-separated string; words, codebook
("kmeans", "lloyd", "random" or a codebook file), codebook_sample, simplify,
noise, seed, sift, repair, threads: the tool's options of the same names.
log: None or callable(line) for the tool's log lines; progress:
callable(fraction, stage). Ctrl-C stops the run (between meshes); a second
run continues from the cache.

Returns {"out", "report" (report.md's markdown), "methods": {FOLDER: {folder,
meshes, failed, cached, measures (as evaluate(), or None), no_measures,
pose_consistency (None if not measured), pose_consistency_pairs,
forms_seconds, codebook_seconds, distances_seconds}}}."""
    o = S.L.RetrieveOptions()
    S.lib().canonform_retrieve_options_init(ctypes.byref(o))
    o.words, o.codebook_sample, o.simplify, o.seed = (S.index(x) for x in (words, codebook_sample, simplify, seed))
    o.noise = float(noise)
    o.threads = S.index(threads, -(2**31), 2**31 - 1)
    o.repair = 1 if repair else 0
    call = S.Call(progress, log)
    o.dataset, o.out = S.path_in(dataset), S.path_in(out)
    o.labels = None if labels is None else S.path_in(labels)
    o.methods = (methods if isinstance(methods, str) else ",".join(str(m) for m in methods)).encode("utf-8")
    o.codebook = codebook.encode("utf-8") if isinstance(codebook, str) else S.path_in(codebook)
    o.sift = S.utf8(sift)
    result = ctypes.c_void_p()
    with call:
        call.done(S.lib().canonform_retrieve(ctypes.byref(o), call.progress,
                                             None, call.log, None, ctypes.byref(result)))
    return S.take_json(result)


def read_distance_matrix(path):
    """read_distance_matrix(path: object) -> numpy.ndarray[numpy.float32]

Reads a distance-matrix file (float32 binary, or .csv): float32 (N, N)."""
    p = S.path_in(path)
    out = S.L.P_Array()
    with S.Call() as call:
        call.done(S.lib().canonform_read_distance_matrix(p, ctypes.byref(out)))
    return S.take(out)


def read_labels(path):
    """read_labels(path: object) -> list[tuple[str, str]]

Reads a labels file: a list of (path, class) tuples in file order."""
    p = S.path_in(path)
    out = ctypes.c_void_p()
    with S.Call() as call:
        call.done(S.lib().canonform_read_labels(p, ctypes.byref(out)))
    return [tuple(row) for row in S.take_json(out)]
