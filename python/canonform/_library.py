# SPDX-License-Identifier: GPL-3.0-or-later
"""Finding and loading canonform's shared library, the C API (src/canonform/c_api/canonform.h).

The package reaches the library through ctypes, not through a CPython extension: one wheel then
serves every CPython 3 (and PyPy) on a platform, and ctypes releases the GIL around each foreign
call. The library is found by name, in this order:

  1. CANONFORM_LIBRARY, when set: the path of the library file itself;
  2. the package's own lib/ folder (the wheel, and a build tree's BUILD/python/canonform/lib/).

Its file name is the platform's: libcanonform.so (Linux and other ELF systems), canonform.dll
(Windows: its folder is also added to the DLL search path, for the DLLs beside it), and
libcanonform.dylib (macOS). It is loaded on the first call that needs it, not at import.
"""
import ctypes
import os
import sys
import threading

# The C API version this package is written for (CANONFORM_C_API_VERSION of canonform.h).
API_VERSION = 1


def library_name(platform=None):
    """The library's file name on `platform` (a sys.platform value; default: this one)."""
    platform = sys.platform if platform is None else platform
    if platform in ("win32", "cygwin", "msys"):
        return "canonform.dll"
    if platform == "darwin":
        return "libcanonform.dylib"
    return "libcanonform.so"


def candidates(package_dir, platform=None, environ=None):
    """The paths tried, in order (see the module's docstring)."""
    environ = os.environ if environ is None else environ
    out = []
    given = environ.get("CANONFORM_LIBRARY")
    if given:
        out.append(given)
    out.append(os.path.join(package_dir, "lib", library_name(platform)))
    return out


_lock = threading.Lock()
_lib = None


def load():
    """The loaded library (ctypes.CDLL), its functions declared; loaded once."""
    global _lib
    if _lib is not None:
        return _lib
    with _lock:
        if _lib is None:
            _lib = _open()
    return _lib


def _open():
    here = os.path.dirname(os.path.abspath(__file__))
    tried = []
    for path in candidates(here):
        if not os.path.isfile(path):
            tried.append(f"{path} (no such file)")
            continue
        if sys.platform == "win32" and hasattr(os, "add_dll_directory"):
            os.add_dll_directory(os.path.dirname(os.path.abspath(path)))  # the DLLs beside it
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append(f"{path} ({e})")
            continue
        _declare(lib)
        version = lib.canonform_api_version()
        if version != API_VERSION:
            raise ImportError(f"canonform: {path} has C API version {version}, this package needs {API_VERSION}: "
                              "the package and its library come from different builds")
        from ._version import __version__
        built = lib.canonform_version().decode()
        if built != __version__:
            raise ImportError(f"canonform: {path} is version {built}, this package {__version__}: the package and its "
                              "library come from different builds")
        return lib
    raise ImportError("canonform: its shared library was not found or could not be loaded; tried:\n  " + "\n  ".join(tried))


# ---- the functions of canonform.h --------------------------------------------------------------
c_int, c_int64, c_double, c_char_p, c_void_p = ctypes.c_int, ctypes.c_int64, ctypes.c_double, ctypes.c_char_p, ctypes.c_void_p
P_double = ctypes.POINTER(ctypes.c_double)
P_float = ctypes.POINTER(ctypes.c_float)
P_int32 = ctypes.POINTER(ctypes.c_int32)
P_int64 = ctypes.POINTER(ctypes.c_int64)


class Array(ctypes.Structure):
    """struct canonform_array."""
    _fields_ = [("type", c_int), ("ndim", c_int), ("shape", c_int64 * 2), ("data", c_void_p)]


P_Array = ctypes.POINTER(Array)
PP_Array = ctypes.POINTER(P_Array)
PP_char = ctypes.POINTER(c_void_p)  # char** outputs, kept as addresses so that canonform_free can free them
PROGRESS = ctypes.CFUNCTYPE(c_int, c_void_p, c_double, c_char_p)
LOG = ctypes.CFUNCTYPE(c_int, c_void_p, c_char_p)


class RetrieveOptions(ctypes.Structure):
    """struct canonform_retrieve_options."""
    _fields_ = [("dataset", c_char_p), ("out", c_char_p), ("labels", c_char_p), ("methods", c_char_p),
                ("words", c_int64), ("codebook", c_char_p), ("codebook_sample", c_int64), ("simplify", c_int64),
                ("noise", c_double), ("seed", c_int64), ("sift", c_char_p), ("repair", c_int), ("threads", c_int)]


MESH = [P_double, c_int64, P_int32, c_int64]
SIGNATURES = {
    "canonform_version": (c_char_p, []),
    "canonform_api_version": (c_int, []),
    "canonform_last_error": (c_char_p, []),
    "canonform_free": (None, [c_void_p]),
    "canonform_array_free": (None, [P_Array]),
    "canonform_read_mesh": (c_int, [c_char_p, PP_Array, PP_Array, PP_Array]),
    "canonform_write_mesh": (c_int, [c_char_p] + MESH + [P_double]),
    "canonform_repair_mesh": (c_int, MESH + [PP_Array, PP_Array, PP_char]),
    "canonform_simplify": (c_int, MESH + [c_int64, PP_Array, PP_Array]),
    "canonform_figure": (c_int, [c_int64, c_int64, c_char_p, PP_Array, PP_Array]),
    "canonform_methods_json": (c_int, [PP_char]),
    "canonform_canonical_form": (c_int, MESH + [c_char_p, ctypes.POINTER(c_char_p), ctypes.POINTER(c_char_p), c_int64,
                                                c_int, PROGRESS, c_void_p, P_double, PP_Array, PP_char]),
    "canonform_conformal_factor": (c_int, MESH + [c_int, PROGRESS, c_void_p, P_double]),
    "canonform_feature_points": (c_int, MESH + [c_int64, c_char_p, c_int64, PROGRESS, c_void_p, PP_Array]),
    "canonform_time_canonical_form": (c_int, MESH + [c_char_p, P_double]),
    "canonform_sift_backends": (c_char_p, []),
    "canonform_sift_backend_available": (c_int, [c_char_p]),
    "canonform_default_sift": (c_char_p, []),
    "canonform_codebook_methods": (c_char_p, []),
    "canonform_view_descriptor": (c_int, MESH + [P_float, c_int64, c_char_p, c_char_p, c_int64, c_int64, PP_Array,
                                                 PP_Array]),
    "canonform_train_codebook": (c_int, [P_float, c_int64, c_int64, c_int64, c_int64, c_char_p, PP_Array]),
    "canonform_save_codebook": (c_int, [c_char_p, P_float, c_int64]),
    "canonform_load_codebook": (c_int, [c_char_p, PP_Array]),
    "canonform_read_descriptor": (c_int, [c_char_p, PP_char, PP_Array]),
    "canonform_clock_distance": (c_int, [P_double, c_int64, c_int64, P_double, c_int64, c_int64, P_double]),
    "canonform_distance_matrix": (c_int, [ctypes.POINTER(P_double), P_int64, P_int64, c_int64, c_int, PROGRESS,
                                          c_void_p, P_float]),
    "canonform_evaluate": (c_int, [P_double, c_int64, c_int64, c_char_p, ctypes.POINTER(c_char_p), c_int64, c_char_p,
                                   PP_char]),
    "canonform_read_distance_matrix": (c_int, [c_char_p, PP_Array]),
    "canonform_read_labels": (c_int, [c_char_p, PP_char]),
    "canonform_retrieve_options_init": (None, [ctypes.POINTER(RetrieveOptions)]),
    "canonform_retrieve": (c_int, [ctypes.POINTER(RetrieveOptions), PROGRESS, c_void_p, LOG, c_void_p, PP_char]),
}


def _declare(lib):
    for name, (restype, argtypes) in SIGNATURES.items():
        f = getattr(lib, name)
        f.restype = restype
        f.argtypes = argtypes
