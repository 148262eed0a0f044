# SPDX-License-Identifier: GPL-3.0-or-later
"""The view-based descriptor (CM-BOF): views and SIFT, codebooks, histograms, clock-matching
distances, descriptor files."""
import ctypes

from . import _support as S

DEFAULT_CODEBOOK_SAMPLE = 100000  # views::kDefaultCodebookSample


def _split(features, counts):
    """Stacked (n, 128) features as one new array per view (counts: keypoints per view)."""
    out, start = [], 0
    for c in counts.tolist():
        out.append(features[start:start + c].copy())
        start += c
    return out


def sift_backends():
    """sift_backends() -> list[str]

The names of the SIFT extractors view_descriptor() and retrieve() take as sift=..."""
    names = S.text(S.lib().canonform_sift_backends())
    return names.split(",") if names else []


def default_sift():
    """default_sift() -> str

The SIFT extractor used when sift=None (the library's default, as the tool's)."""
    return S.text(S.lib().canonform_default_sift())


def sift_backend_available(name):
    """sift_backend_available(name: str) -> bool

Whether this build has the SIFT extractor `name`: the `opencv` one is not in the
wheel (it needs OpenCV); asking for it there raises InputError saying so."""
    return bool(S.lib().canonform_sift_backend_available(S.utf8(name)))


def codebook_methods():
    """codebook_methods() -> list[str]

The codebook-training methods this build has: "kmeans" (FAISS), "lloyd" and
"random"; builds without FAISS (the wheel) lack "kmeans" and say so when asked for it."""
    names = S.text(S.lib().canonform_codebook_methods())
    return names.split(",") if names else []


def view_descriptor(V, F, codebook=None, *, sift=None, image_size=256, seed=0):
    """view_descriptor(V: object, F: object, codebook: object = None, *, sift: str | None = None, image_size: int = 256, seed: int = 0) -> object

The CM-BOF view descriptor of a mesh (`canonform descriptor`): pose normalisation,
66 depth views of image_size pixels, SIFT per view.

V: float32/float64 (#V, 3); F: integer (#F, 3) (several components allowed).
codebook: None, a (W, 128) float array of visual words (train_codebook()) or a
codebook file. With a codebook, returns float32 (66, W): one bag-of-features
histogram per view (word counts); without, the raw features: a list of 66
float32 (n_i, 128) arrays (n_i keypoints of view i). sift: None (default_sift())
or one of sift_backends(); seed: the pose's rectilinearity restarts."""
    image_size, seed = S.index(image_size), S.index(seed)
    path, words = None, None
    if codebook is not None:
        if S.is_path(codebook):
            path = S.path_in(codebook)
        else:
            words = S.descriptors_in(codebook, "codebook")
    v, f, mesh = S.mesh_args(V, F)
    a, counts = S.arrays(2)
    with S.Call() as call:
        call.done(S.lib().canonform_view_descriptor(*mesh, S.ptr(words, ctypes.c_float), 0 if words is None else len(words),
                                                    path, S.utf8(sift), image_size, seed, ctypes.byref(a),
                                                    ctypes.byref(counts)))
    data, n = S.take(a), S.take(counts)
    return data if codebook is not None else _split(data, n)


def _collect(o, out, depth):
    """Appends every (n, 128) array of a nested sequence, in order (a model's list of views, a list of models)."""
    numpy = S.np()
    if isinstance(o, numpy.ndarray) and o.ndim == 2:
        out.append(S.descriptors_in(o, "features"))
    elif depth < 3 and isinstance(o, (list, tuple)):
        for x in o:
            _collect(x, out, depth + 1)
    else:
        out.append(S.descriptors_in(o, "features"))  # anything else array-like, or its error


def train_codebook(features, words=1500, sample=DEFAULT_CODEBOOK_SAMPLE, seed=0, *, method="kmeans"):
    """train_codebook(features: object, words: int = 1500, sample: int = 100000, seed: int = 0, *, method: str = 'kmeans') -> numpy.ndarray[numpy.float32]

Trains a codebook of visual words (`canonform codebook`).

features: a float (n, 128) array, or a list of them (view_descriptor()'s raw
features), or a list of such lists (several models), stacked in order. sample:
descriptors drawn (seeded) to train on, 0 = all; method: "kmeans" (FAISS),
"lloyd" or "random". Returns float32 (words, 128); fewer descriptors than words
raises InputError with both numbers."""
    words, sample, seed = S.index(words), S.index(sample), S.index(seed)
    numpy = S.np()
    parts = []
    _collect(features, parts, 0)
    X = numpy.concatenate(parts) if parts else numpy.zeros((0, 128), numpy.float32)
    out = S.L.P_Array()
    with S.Call() as call:
        call.done(S.lib().canonform_train_codebook(S.ptr(X, ctypes.c_float), len(X), words, sample, seed, S.utf8(method),
                                                   ctypes.byref(out)))
    return S.take(out)


def save_codebook(path, words):
    """save_codebook(path: object, words: object) -> None

Writes words (W, 128) as a codebook file (the tool's format; atomic)."""
    p = S.path_in(path)
    w = S.descriptors_in(words, "words")
    with S.Call() as call:
        call.done(S.lib().canonform_save_codebook(p, S.ptr(w, ctypes.c_float), len(w)))


def load_codebook(path):
    """load_codebook(path: object) -> numpy.ndarray[numpy.float32]

Reads a codebook file: float32 (W, 128) words."""
    p = S.path_in(path)
    out = S.L.P_Array()
    with S.Call() as call:
        call.done(S.lib().canonform_load_codebook(p, ctypes.byref(out)))
    return S.take(out)


def read_descriptor(path):
    """read_descriptor(path: object) -> dict

Reads a descriptor file (.cfvd, `canonform descriptor`): a dict with source,
views, image_size, codebook_words, keypoints_per_view and either histograms
(float32 (views, codebook_words)) or features (a list of float32 (n_i, 128))."""
    p = S.path_in(path)
    meta, data = ctypes.c_void_p(), S.L.P_Array()
    with S.Call() as call:
        call.done(S.lib().canonform_read_descriptor(p, ctypes.byref(meta), ctypes.byref(data)))
    out = S.take_json(meta)
    a = S.take(data)
    if out["codebook_words"] > 0:
        out["histograms"] = a
    else:
        out["features"] = _split(a, S.np().asarray(out["keypoints_per_view"]))
    return out


def clock_distance(A, B):
    """clock_distance(A: object, B: object) -> float

The clock-matching distance of two descriptors: A, B (66, W) histograms
(view_descriptor() with one codebook). The minimum over the 24 rotations of the
cube of the summed view distances; 0 for equal descriptors."""
    a, b = S.matrix_in(A, "A"), S.matrix_in(B, "B")
    d = ctypes.c_double()
    with S.Call() as call:
        call.done(S.lib().canonform_clock_distance(S.ptr(a, ctypes.c_double), a.shape[0], a.shape[1],
                                                   S.ptr(b, ctypes.c_double), b.shape[0], b.shape[1], ctypes.byref(d)))
    return d.value


def distance_matrix(descriptors, *, threads=0, progress=None):
    """distance_matrix(descriptors: Iterable, *, threads: int = 0, progress: object = None) -> numpy.ndarray[numpy.float32]

The N x N clock-matching distance matrix of a list of N (66, W) histograms
(`canonform distance`): float32 (N, N), symmetric, zero diagonal. threads: 0 =
every core; progress and Ctrl-C as canonical_form()."""
    numpy = S.np()
    threads = S.index(threads, -(2**31), 2**31 - 1)
    call = S.Call(progress)
    models = [S.matrix_in(d, f"descriptor {k}") for k, d in enumerate(descriptors)]
    n = len(models)
    pointers = (S.L.P_double * n)(*[S.ptr(m, ctypes.c_double) for m in models])
    views = numpy.array([m.shape[0] for m in models], numpy.int64)
    words = numpy.array([m.shape[1] for m in models], numpy.int64)
    D = numpy.zeros((n, n), numpy.float32)
    with call:
        call.done(S.lib().canonform_distance_matrix(pointers, S.ptr(views, ctypes.c_int64), S.ptr(words, ctypes.c_int64), n,
                                                    threads, call.progress, None, S.ptr(D, ctypes.c_float)))
    return D
