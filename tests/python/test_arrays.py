# SPDX-License-Identifier: GPL-3.0-or-later
"""Arrays in and out: dtypes, memory orders, strides; results are new arrays owning their memory;
the GIL is released while the library computes."""
import threading
import time

import numpy as np
import pytest

import canonform


def same(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a.view(np.uint8), b.view(np.uint8))


def test_every_float_dtype_and_memory_order_gives_the_same_form(mesh):
    V, F = mesh  # float32-representable coordinates (canonform generate rounds them)
    Y, _ = canonform.canonical_form(V, F)
    inputs = [
        (V.astype(np.float32), F),
        (np.asfortranarray(V), np.asfortranarray(F)),
        (np.asfortranarray(V.astype(np.float32)), F.astype(np.int64)),
        (np.repeat(V, 2, axis=1)[:, ::2], F.astype(np.uint32)),  # a strided view (every other column)
        (V, F.astype(np.int16)),
        (V.tolist(), F.tolist()),  # anything numpy can read as an array
    ]
    for v, f in inputs:
        Z, _ = canonform.canonical_form(v, f)
        assert same(Y, Z)


def test_results_are_new_c_ordered_arrays_owning_their_memory(mesh):
    V, F = mesh
    V0, F0 = V.copy(), F.copy()
    for method in ("none", "euclidean-N"):
        Y, _ = canonform.canonical_form(V, F, method)
        assert Y.flags.owndata and Y.flags.c_contiguous and Y.dtype == np.float64 and Y.shape == V.shape
        assert not np.shares_memory(Y, V)
    assert np.array_equal(V, V0) and np.array_equal(F, F0)  # inputs untouched
    phi = canonform.conformal_factor(V, F)
    idx = canonform.feature_points(V, F)
    for a, dtype in ((phi, np.float64), (idx, np.int64)):
        assert a.flags.owndata and a.dtype == dtype
    # method "none" returns the mesh, as a copy: changing it leaves V alone
    Y, _ = canonform.canonical_form(V, F, "none")
    Y[:] = 0
    assert np.array_equal(V, V0)


def test_read_mesh_gives_float64_and_int32(figure_file):
    V, F = canonform.read_mesh(figure_file)
    assert V.dtype == np.float64 and F.dtype == np.int32 and V.shape[1] == 3 and F.shape[1] == 3
    assert V.flags.owndata and F.flags.owndata
    V2, F2, q = canonform.read_mesh(figure_file, quality=True)
    assert same(V, V2) and same(F, F2) and q.shape == (0,)


@pytest.mark.parametrize("V, F, pattern", [
    (np.zeros((10, 2)), np.zeros((4, 3), int), r"V must have shape \(n, 3\), got shape \(10, 2\)"),
    (np.zeros(30), np.zeros((4, 3), int), r"V must have shape \(n, 3\), got shape \(30,\)"),
    (np.zeros((10, 3), np.int64), np.zeros((4, 3), int), "V must be float32 or float64, got dtype int64"),
    (np.zeros((10, 3), np.float16), np.zeros((4, 3), int), "V must be float32 or float64, got dtype float16"),
    (np.zeros((10, 3)), np.zeros((4, 3)), "F must be an integer array"),
    (np.zeros((10, 3)), np.full((4, 3), 2**40), "face index 1099511627776 .* out of range"),
    (None, np.zeros((4, 3), int), "V is None"),
    (np.array([["a", "b", "c"]], dtype=object), np.zeros((4, 3), int), "Python objects"),
])
def test_bad_arrays_are_value_errors_naming_the_cause(V, F, pattern):
    with pytest.raises(ValueError, match=pattern):
        canonform.canonical_form(V, F)


def test_the_gil_is_released_during_a_computation(mesh):
    V, F = mesh
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.02)
    start = time.perf_counter()
    _, info = canonform.canonical_form(V, F, "geodesic-ls")  # about a second
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    # a thread that needs the GIL kept running while the library worked
    assert end - start > 0.05 and len(during) >= 0.1 * (end - start) / 0.002, (len(during), end - start)
