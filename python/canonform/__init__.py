# SPDX-License-Identifier: GPL-3.0-or-later
"""canonform: Euclidean canonical forms of non-rigid triangle meshes (Pickup et al. 2015) and
view-based 3D shape retrieval, with numpy arrays in and out.

    import canonform
    V, F = canonform.read_mesh("cat0.off")          # float64 (#V, 3), int32 (#F, 3)
    Y, info = canonform.canonical_form(V, F)         # euclidean-N, the tool's defaults

Every function is documented (help(canonform.canonical_form)); docs/python.md is the guide.
Errors: InputError (a ValueError) names bad input, NumericalError (a RuntimeError) a failed
solve, Cancelled a progress callable that returned False; Ctrl-C raises KeyboardInterrupt.
canonform.pymeshlab.load() loads the MeshLab filters into the installed pymeshlab.

The functions call the library's C API (libcanonform.so, canonform.dll) through ctypes: no part
of the package is compiled against CPython, and the GIL is released while the library computes.
"""
from ._version import __version__  # noqa: F401
from ._support import Cancelled, InputError, NumericalError
from ._meshes import (_cpp_call_seconds, canonical_form, canonical_methods, conformal_factor, feature_points,  # noqa: F401
                      figure, read_mesh, repair_mesh, simplify, write_mesh)
from ._views import (clock_distance, codebook_methods, default_sift, distance_matrix, load_codebook, read_descriptor,
                     save_codebook, sift_backend_available, sift_backends, train_codebook, view_descriptor)
from ._retrieval import evaluate, read_distance_matrix, read_labels, retrieve
from . import pymeshlab  # noqa: F401  (canonform.pymeshlab.load())

__all__ = ["Cancelled", "InputError", "NumericalError", "canonical_form", "canonical_methods", "clock_distance",
           "codebook_methods", "conformal_factor", "default_sift", "distance_matrix", "evaluate", "feature_points",
           "figure", "load_codebook", "read_descriptor", "read_distance_matrix", "read_labels", "read_mesh",
           "repair_mesh", "retrieve", "save_codebook", "sift_backend_available", "sift_backends", "simplify",
           "train_codebook", "view_descriptor", "write_mesh"]
