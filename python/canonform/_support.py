# SPDX-License-Identifier: GPL-3.0-or-later
"""What every function of the package shares: numpy arrays in and out, the library's errors as
Python exceptions, paths, and calls that stop on Ctrl-C and report progress.

Arrays in: V any float32/float64 array of shape (#V, 3), F any integer array of shape (#F, 3), any
memory order or strides; each is handed to the library as a C-ordered float64 / int32 array (no
copy when it is one already). Arrays out: new C-ordered numpy arrays owning their memory
(flags.owndata), filled from the library's arrays, which are then freed.

Errors: the library's status codes become canonform.InputError (a ValueError), NumericalError (a
RuntimeError), Cancelled (a RuntimeError), MemoryError or RuntimeError, with the library's message
(invalid UTF-8 bytes, e.g. of a file name, replaced by U+FFFD).

Calls: ctypes releases the GIL for the whole foreign call. Long calls take a progress function
(Call.progress): the library calls it from time to time, on the calling thread and on its worker
threads; it calls the user's callable, and returns 0 (cancel) when that returned False or raised,
or when Ctrl-C was pressed. For Ctrl-C, the outermost call on the main thread replaces Python's
default SIGINT handler (when it is the one installed) by one that only notes the signal; Python
runs it in the main thread when the progress function runs there, and the call then stops and
raises KeyboardInterrupt. The previous handler is back when the call returns.
"""
import ctypes
import json
import os
import signal
import threading

from . import _library as L

_np = None


def np():
    """numpy, imported on first use (`import canonform` stays fast without it)."""
    global _np
    if _np is None:
        import numpy
        _np = numpy
    return _np


class InputError(ValueError):
    """The input cannot be processed (a bad mesh, file, array or parameter); the message names the cause. A ValueError."""


class NumericalError(RuntimeError):
    """A numerical step failed (factorisation, non-finite values, residual above tolerance). A RuntimeError."""


class Cancelled(RuntimeError):
    """The progress callable returned False. A RuntimeError."""


for _cls in (InputError, NumericalError, Cancelled):
    _cls.__module__ = "canonform"

OK, INPUT, NUMERICAL, CANCELLED, MEMORY, UNSUPPORTED, INTERNAL = range(7)


def lib():
    return L.load()


def text(b):
    """A str from UTF-8 bytes (invalid bytes as U+FFFD)."""
    return b.decode("utf-8", "replace") if b is not None else ""


def raise_status(status, cause=None):
    """Raises the exception of a non-zero status (or `cause`, the Python exception that made the
    library stop, for CANCELLED)."""
    if status == OK:
        return
    message = text(lib().canonform_last_error())
    if status == CANCELLED and cause is not None:
        raise cause
    if status in (INPUT, UNSUPPORTED):
        raise InputError(message)
    if status == NUMERICAL:
        raise NumericalError(message)
    if status == CANCELLED:
        raise Cancelled(message)
    if status == MEMORY:
        raise MemoryError(message)
    raise RuntimeError(message)


def check(status):
    raise_status(status)


# ---- arrays in -------------------------------------------------------------------------------------
def as_array(obj, name):
    if obj is None:
        raise InputError(f"{name} is None: an array is needed")
    try:
        a = np().asarray(obj)
    except Exception:
        raise InputError(f"{name} cannot be read as a numpy array") from None
    if a.dtype.kind == "O":
        raise InputError(f"{name} is an array of Python objects: numbers are needed")
    return a


def shape_of(a):
    return "(" + ", ".join(str(s) for s in a.shape) + ("," if a.ndim == 1 else "") + ")"


def check_2d(a, name, cols=None):
    if a.ndim != 2 or (cols is not None and a.shape[1] != cols):
        raise InputError(f"{name} must have shape (n, {cols if cols is not None else 'k'}), got shape {shape_of(a)}")


def floats(a, name, integers_too, dtype):
    kind, size = a.dtype.kind, a.dtype.itemsize
    if (kind == "f" and size in (4, 8)) or (integers_too and kind in "iu"):
        return np().ascontiguousarray(a, dtype=dtype)
    raise InputError(f"{name} must be float32 or float64, got dtype {a.dtype}")


def vertices_in(V, name="V"):
    a = as_array(V, name)
    check_2d(a, name, 3)
    return floats(a, name, False, np().float64)


def faces_in(F, name="F", allow_none=False):
    numpy = np()
    if allow_none and F is None:
        return numpy.zeros((0, 3), numpy.int32)
    a = as_array(F, name)
    check_2d(a, name, 3)
    if a.dtype.kind not in "iu":
        raise InputError(f"{name} must be an integer array (face indices), got dtype {a.dtype}")
    if a.dtype != numpy.int32 and a.size:
        lo, hi = numpy.iinfo(numpy.int32).min, numpy.iinfo(numpy.int32).max
        bad = (a < lo) | (a > hi) if a.dtype.kind == "i" else (a > hi)
        if bad.any():
            i, j = (int(x) for x in numpy.argwhere(bad)[0])
            raise InputError(f"face index {int(a[i, j])} ({name}[{i}, {j}]) is out of range")
    return numpy.ascontiguousarray(a, dtype=numpy.int32)


def matrix_in(A, name, cols=None):
    a = as_array(A, name)
    check_2d(a, name, cols)
    return floats(a, name, True, np().float64)


def vector_in(v, name):
    a = as_array(v, name)
    if a.ndim != 1:
        raise InputError(f"{name} must be one-dimensional, got shape {shape_of(a)}")
    return floats(a, name, True, np().float64)


def descriptors_in(X, name):
    a = as_array(X, name)
    check_2d(a, name, 128)
    return floats(a, name, False, np().float32)


def ptr(a, ctype):
    """A pointer to the data of a C-ordered array (NULL for an empty one)."""
    if a is None or a.size == 0:
        return None
    return a.ctypes.data_as(ctypes.POINTER(ctype))


def mesh_args(V, F):
    """(V float64, F int32) checked, and the four mesh arguments of the C API."""
    v, f = vertices_in(V), faces_in(F)
    return v, f, [ptr(v, ctypes.c_double), len(v), ptr(f, ctypes.c_int32), len(f)]


def index(value, lo=-(2**63), hi=2**63 - 1):
    """An integer argument (numpy integers too), clamped into the C type's range: the library's
    range check then names it with the value."""
    import operator
    return max(lo, min(hi, operator.index(value)))


# ---- arrays, texts out -------------------------------------------------------------------------------
_TYPES = {1: ("float64", ctypes.c_double), 2: ("float32", ctypes.c_float), 3: ("int32", ctypes.c_int32),
          4: ("int64", ctypes.c_int64)}


def take(p):
    """A library array (canonform_array*) as a new numpy array; the library's is freed."""
    if not p:
        return None
    try:
        a = p.contents
        dtype, ctype = _TYPES[a.type]
        shape = (a.shape[0],) if a.ndim == 1 else (a.shape[0], a.shape[1])
        count = shape[0] * (shape[1] if len(shape) > 1 else 1)
        out = np().empty(shape, dtype=dtype)
        if count:
            ctypes.memmove(out.ctypes.data, a.data, count * ctypes.sizeof(ctype))
        return out
    finally:
        lib().canonform_array_free(p)


def take_text(address):
    """A library text (char*) as str; the library's is freed."""
    if not address.value:
        return None
    try:
        return text(ctypes.string_at(address.value))
    finally:
        lib().canonform_free(address.value)


def take_json(address):
    return json.loads(take_text(address))


def arrays(n):
    return [L.P_Array() for _ in range(n)]


def path_in(p):
    """A path argument (str, bytes or os.PathLike) as the file system's bytes."""
    if p is None:
        raise InputError("a path is needed, got None")
    b = os.fsencode(p)
    if b"\0" in b:
        raise InputError(f"the path {b!r} contains a NUL byte")
    return b


def is_path(o):
    return isinstance(o, (str, bytes, os.PathLike))


def utf8(s):
    return None if s is None else str(s).encode("utf-8")


# ---- calls -------------------------------------------------------------------------------------------
class _Sigint:
    """The SIGINT handler of the outermost call on the main thread (see the module's docstring)."""

    def __init__(self):
        self.depth = 0
        self.previous = None
        self.pending = False
        self.calls = []  # the Calls running on the main thread

    def handler(self, signum, frame):
        self.pending = True
        for c in self.calls:
            c.interrupted = True

    def enter(self, call):
        if threading.current_thread() is not threading.main_thread():
            return False
        if self.depth == 0:
            if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
                return False  # someone else's handler: theirs runs (in the progress function)
            self.previous = signal.signal(signal.SIGINT, self.handler)
            self.pending = False
        self.depth += 1
        self.calls.append(call)
        return True

    def leave(self, call, raising):
        """Back to the previous handler after the outermost call; KeyboardInterrupt if Ctrl-C came
        (unless the call is raising one already)."""
        self.calls.remove(call)
        self.depth -= 1
        if self.depth == 0:
            signal.signal(signal.SIGINT, self.previous)
            self.previous = None
            if self.pending:
                self.pending = False
                if not raising:
                    raise KeyboardInterrupt


_sigint = _Sigint()


class Call:
    """One library call: `with Call(progress) as c: status = f(..., c.progress, None, ...)`, then
    c.done(status) raises what made it fail (the callable's own exception, KeyboardInterrupt,
    Cancelled, ...)."""

    def __init__(self, progress=None, log=None):
        if progress is not None and not callable(progress):
            raise InputError("progress must be a callable(fraction, stage) or None")
        if log is not None and not callable(log):
            raise InputError("log must be a callable(line) or None")
        self.user_progress, self.user_log = progress, log
        self.cause = None
        self.interrupted = False
        self.progress = L.PROGRESS(self._progress)
        self.log = L.LOG(self._log)
        self._watching = False

    def __enter__(self):
        self._watching = _sigint.enter(self)
        return self

    def __exit__(self, kind, value, tb):
        if self._watching:
            self._watching = False
            _sigint.leave(self, kind is not None and issubclass(kind, KeyboardInterrupt))
        return False

    def _go_on(self):
        if self.interrupted and self.cause is None:
            self.cause = KeyboardInterrupt()
        return self.cause is None

    def _progress(self, user, fraction, stage):
        try:
            if not self._go_on():
                return 0
            if self.user_progress is not None and self.user_progress(fraction, text(stage)) is False:
                return 0
            return 1
        except BaseException as e:  # the callable's exception stops the call, and is raised after it
            if self.cause is None:
                self.cause = e
            return 0

    def _log(self, user, line):
        try:
            if not self._go_on():
                return 0
            if self.user_log is not None:
                self.user_log(text(line))
            return 1
        except BaseException as e:
            if self.cause is None:
                self.cause = e
            return 0

    def done(self, status):
        if status == OK:
            return
        if self.interrupted and self.cause is None:
            self.cause = KeyboardInterrupt()
        raise_status(status, self.cause)
