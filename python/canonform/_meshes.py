# SPDX-License-Identifier: GPL-3.0-or-later
"""Meshes: files, conformal factor, feature points, canonical forms (any method of the registry),
simplification, repair, procedural figures. Each docstring's first line is the signature (types
by the stubs' names; python/make_stubs.py checks it against the function's own)."""
import ctypes
import time

from . import _support as S


def _parameter_text(name, v):
    """A parameter value as the text the tool and method specs use: int as written, a float so that
    strtod gives the same double back (17 significant digits), str as is."""
    import operator
    if isinstance(v, bool):
        return "True" if v else "False"  # refused by the registry's check
    if isinstance(v, str):
        return v
    try:
        return str(operator.index(v))
    except TypeError:
        pass
    if isinstance(v, float) or hasattr(v, "__float__"):
        return "%.17g" % float(v)
    raise S.InputError(f"{name} must be a number or a word, got {type(v).__name__}")


def read_mesh(path, *, quality=False):
    """read_mesh(path: object, *, quality: bool = False) -> object

Reads a mesh file: OFF, PLY (ASCII or binary), OBJ or STL, by extension.

Returns (V, F): V float64 (#V, 3), F int32 (#F, 3) (0-based; (0, 3) for a point
cloud). With quality=True, (V, F, q): q float64 (#V,) the PLY's vertex quality, or
(0,) when the file has none. Raises InputError naming the file and the cause
(missing, a folder, empty, unsupported format, a face index out of range, a
header that claims more than the file holds, malformed data)."""
    p = S.path_in(path)
    v, f, q = S.arrays(3)
    with S.Call() as call:
        call.done(S.lib().canonform_read_mesh(p, ctypes.byref(v), ctypes.byref(f), ctypes.byref(q) if quality else None))
    V, F, Q = S.take(v), S.take(f), S.take(q)
    return (V, F, Q) if quality else (V, F)


def write_mesh(path, V, F, quality=None):
    """write_mesh(path: object, V: object, F: object, quality: object = None) -> None

Writes a mesh in the format its file name names: .ply (binary, with quality),
.off, .obj, .stl; no extension: PLY. Atomic: a failure leaves no file.

V: float32/float64 (#V, 3); F: integer (#F, 3), or None / (0, 3) for a point
cloud (not STL); quality: None or (#V,) floats, PLY only. Raises InputError for
another extension, an STL point cloud or a face index outside [0, #V)."""
    p = S.path_in(path)
    v, f = S.vertices_in(V), S.faces_in(F, "F", True)
    q = None
    if quality is not None:
        q = S.vector_in(quality, "quality")
        if len(q) != len(v):
            raise S.InputError(f"quality has {len(q)} values for {len(v)} vertices")
    with S.Call() as call:
        call.done(S.lib().canonform_write_mesh(p, S.ptr(v, ctypes.c_double), len(v), S.ptr(f, ctypes.c_int32), len(f),
                                               S.ptr(q, ctypes.c_double)))


def conformal_factor(V, F, normalize=True, *, progress=None):
    """conformal_factor(V: object, F: object, normalize: bool = True, *, progress: object = None) -> numpy.ndarray[numpy.float64]

The discrete conformal factor (Pickup et al. 2015, eqs. 7-9).

V: float32/float64 (#V, 3); F: integer (#F, 3), one closed or open manifold
component. Returns phi float64 (#V,): in [0, 1] if normalize (as `canonform
conformal` stores it), else raw with area-weighted mean zero (`--raw`). Raises
InputError on a mesh the library refuses (README, "Bad input"), NumericalError if
the solve fails."""
    v, f, mesh = S.mesh_args(V, F)
    phi = S.np().empty(len(v))
    with S.Call(progress) as call:
        call.done(S.lib().canonform_conformal_factor(*mesh, 1 if normalize else 0, call.progress, None,
                                                     S.ptr(phi, ctypes.c_double)))
    return phi


def feature_points(V, F, ring=2, fill="none", seed=0):
    """feature_points(V: object, F: object, ring: int = 2, fill: str = 'none', seed: int = 0) -> numpy.ndarray[numpy.int64]

Feature points: vertices that are strict maxima of the conformal factor over
their ring-ring, largest first, up to ceil(sqrt(#V)) (`canonform features`).

fill="random" tops them up to ceil(sqrt(#V)) with seeded random vertices (variant
A). Returns int64 (k,) vertex indices."""
    ring, seed = S.index(ring), S.index(seed)
    v, f, mesh = S.mesh_args(V, F)
    (out,) = S.arrays(1)
    with S.Call() as call:
        call.done(S.lib().canonform_feature_points(*mesh, ring, S.utf8(fill), seed, call.progress, None, ctypes.byref(out)))
    return S.take(out)


def canonical_form(V, F, method="euclidean-N", *, threads=0, progress=None, **params):
    """canonical_form(V: object, F: object, method: str = 'euclidean-N', *, threads: int = 0, progress: object = None, **params) -> tuple[numpy.ndarray[numpy.float64], dict]

The canonical form of a mesh by any method of the registry (canonical_methods()):
"euclidean-N" (default), "euclidean-A", "geodesic-ls", "geodesic-classical",
"geodesic-fast", "none".

V: float32/float64 (#V, 3); F: integer (#F, 3). **params are the method's
parameters by name (canonical_methods() lists them with defaults and ranges;
e.g. beta=65, tolerance=1e-6, acceleration="none"), checked by the registry: an
unknown name or a value out of range raises InputError naming it. threads: the
method's parallel loops (0: every core). progress: None or
callable(fraction, stage) -> bool|None; returning False raises Cancelled. Ctrl-C
stops the computation (KeyboardInterrupt).

Returns (Y, info): Y float64 (#V, 3), the form in input units, same vertex order
and faces as V; info the dict `canonform canonical --json` prints (vertices,
faces, the method's summary: iterations, stresses, timings...; total_seconds of
this call in place of the tool's read/write/total seconds). The same doubles as
`canonform canonical` on the same mesh with the same parameters."""
    t0 = time.perf_counter()
    keys = [k.encode("utf-8") for k in params]
    values = [_parameter_text(k, v).encode("utf-8") for k, v in params.items()]
    threads = S.index(threads, -(2**31), 2**31 - 1)
    call = S.Call(progress)  # checks the callable before any conversion
    v, f, mesh = S.mesh_args(V, F)
    Y = S.np().empty((len(v), 3))
    info = ctypes.c_void_p()
    n = len(keys)
    with call:
        call.done(S.lib().canonform_canonical_form(*mesh, S.utf8(method), (ctypes.c_char_p * n)(*keys) if n else None,
                                                   (ctypes.c_char_p * n)(*values) if n else None, n, threads,
                                                   call.progress, None, S.ptr(Y, ctypes.c_double), None,
                                                   ctypes.byref(info)))
    summary = S.take_json(info)
    summary["total_seconds"] = time.perf_counter() - t0
    return Y, summary


def canonical_methods():
    """canonical_methods() -> list[dict]

The registry of canonical-form methods: a list of dicts
{name, family, help, parameters: [{name, default, help, min, max, integer,
choices, zero_means_default}]}, in the order the tool lists them."""
    out = ctypes.c_void_p()
    S.check(S.lib().canonform_methods_json(ctypes.byref(out)))
    return S.take_json(out)


def _cpp_call_seconds(V, F, method="euclidean-N"):
    """_cpp_call_seconds(V: object, F: object, method: str = 'euclidean-N') -> float

For bench/python_bench.py: seconds of the bare C++ call canonical_form() makes (one thread)."""
    v, f, mesh = S.mesh_args(V, F)
    seconds = ctypes.c_double()
    S.check(S.lib().canonform_time_canonical_form(*mesh, S.utf8(method), ctypes.byref(seconds)))
    return seconds.value


def simplify(V, F, vertices):
    """simplify(V: object, F: object, vertices: int) -> tuple[numpy.ndarray[numpy.float64], numpy.ndarray[numpy.int32]]

Quadric edge collapse to about `vertices` vertices (MeshLab's filter, its
defaults; `canonform simplify`). Returns (V float64 (n, 3), F int32 (m, 3))."""
    vertices = S.index(vertices)
    v, f, mesh = S.mesh_args(V, F)
    a, b = S.arrays(2)
    with S.Call() as call:
        call.done(S.lib().canonform_simplify(*mesh, vertices, ctypes.byref(a), ctypes.byref(b)))
    return S.take(a), S.take(b)


def repair_mesh(V, F):
    """repair_mesh(V: object, F: object) -> tuple[numpy.ndarray[numpy.float64], numpy.ndarray[numpy.int32], str]

The tool's --repair: merges duplicate vertices, removes zero-area and duplicate
faces, keeps the largest component, drops unreferenced vertices. Returns
(V float64, F int32, summary str), the summary saying what changed."""
    v, f, mesh = S.mesh_args(V, F)
    a, b = S.arrays(2)
    summary = ctypes.c_void_p()
    with S.Call() as call:
        call.done(S.lib().canonform_repair_mesh(*mesh, ctypes.byref(a), ctypes.byref(b), ctypes.byref(summary)))
    return S.take(a), S.take(b), S.take_text(summary)


def figure(vertices=5000, pose=0, body="standard"):
    """figure(vertices: int = 5000, pose: int = 0, body: str = 'standard') -> tuple[numpy.ndarray[numpy.float64], numpy.ndarray[numpy.int32]]

A procedural articulated figure, as `canonform generate OUT --vertices N --pose P
--class BODY` writes it (coordinates rounded to float32). pose 0-5: named poses,
others seeded random ones; body: standard, long-arms, short-legs, long-tail,
stocky, long-neck. Returns (V float64 (#V, 3), F int32 (#F, 3))."""
    a, b = S.arrays(2)
    with S.Call() as call:
        call.done(S.lib().canonform_figure(S.index(vertices), S.index(pose), S.utf8(body), ctypes.byref(a), ctypes.byref(b)))
    return S.take(a), S.take(b)
