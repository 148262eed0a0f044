# SPDX-License-Identifier: GPL-3.0-or-later
"""canonform: Euclidean canonical forms of non-rigid triangle meshes (Pickup et al. 2015) and
view-based 3D shape retrieval, with numpy arrays in and out.

    import canonform
    V, F = canonform.read_mesh("cat0.off")          # float64 (#V, 3), int32 (#F, 3)
    Y, info = canonform.canonical_form(V, F)         # euclidean-N, the tool's defaults

Every function is documented (help(canonform.canonical_form)); docs/python.md is the guide.
Errors: InputError (a ValueError) names bad input, NumericalError (a RuntimeError) a failed
solve, Cancelled a progress callable that returned False; Ctrl-C raises KeyboardInterrupt.
"""
from ._canonform import *  # noqa: F401,F403
from ._canonform import __version__  # noqa: F401
from . import _canonform as _ext

__all__ = [n for n in dir(_ext) if not n.startswith("_")]
