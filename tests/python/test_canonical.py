# SPDX-License-Identifier: GPL-3.0-or-later
"""canonical_form(): every method of the registry against `canonform canonical` on the same file,
to the bit; parameters checked by the registry; invariance to rigid motion and vertex order."""
import json
import math

import numpy as np
import pytest

import canonform
from conftest import aligned_rms

METHODS = [m["name"] for m in canonform.canonical_methods()]  # the registry, not a list of ours


def bits(a):
    return np.ascontiguousarray(a).view(np.uint64)


@pytest.mark.parametrize("method", METHODS)
def test_every_method_equals_the_tool_to_the_bit(method, figure_file, mesh, run_tool, tmp_path):
    out = tmp_path / "form.ply"
    summary = json.loads(run_tool("canonical", figure_file, out, "--method", method, "--json"))
    Z, G = canonform.read_mesh(out)
    V, F = mesh
    Y, info = canonform.canonical_form(V, F, method)
    assert np.array_equal(bits(Y), bits(Z)), f"{method}: max difference {np.abs(Y - Z).max()}"
    assert np.array_equal(G, F)
    # info is the tool's --json summary (timings aside: they differ from run to run)
    timing = {k for k in summary if k.endswith("seconds")}
    assert {k: v for k, v in info.items() if k not in timing} == {k: v for k, v in summary.items() if k not in timing}
    assert list(info)[:2] == ["vertices", "faces"] and info["total_seconds"] > 0


def test_given_parameters_equal_the_tools_options(figure_file, mesh, run_tool, tmp_path):
    out = tmp_path / "form.ply"
    run_tool("canonical", figure_file, out, "--method", "euclidean-A", "--beta", 65, "--tolerance", 1e-6,
             "--acceleration", "none", "--seed", 7, "--quiet")
    Y, info = canonform.canonical_form(*mesh, "euclidean-A", beta=65, tolerance=1e-6, acceleration="none", seed=7)
    assert np.array_equal(bits(Y), bits(canonform.read_mesh(out)[0]))
    assert info["beta"] == 65 and info["acceleration"] == "none"
    # numpy scalars and a float given for an integer parameter (7.0 is whole) work as well
    Y2, _ = canonform.canonical_form(*mesh, "euclidean-A", beta=np.float32(65), tolerance=np.float64(1e-6),
                                     acceleration="none", seed=7.0)
    assert np.array_equal(bits(Y), bits(Y2))


def bad_values(p):
    """Values the registry must refuse for parameter p."""
    if p["choices"]:
        return ["bogus", 3]
    bad = [math.nan, math.inf, "ten"]
    if p["min"] != 0 or p["max"] != 0:
        bad += [p["max"] * 10 + 1, -1e300]
    if p["integer"]:
        bad.append(float(int(p["default"]) if p["default"].isdigit() else 1) + 0.5)
    return bad


@pytest.mark.parametrize("method", METHODS)
def test_every_parameter_is_checked_by_name_and_range(method, mesh):
    V, F = mesh
    m = next(x for x in canonform.canonical_methods() if x["name"] == method)
    for p in m["parameters"]:
        for value in bad_values(p):
            with pytest.raises(ValueError, match=p["name"]):
                canonform.canonical_form(V, F, method, **{p["name"]: value})
    with pytest.raises(ValueError, match="has no parameter 'no_such_parameter'"):
        canonform.canonical_form(V, F, method, no_such_parameter=1)
    others = {q["name"] for x in canonform.canonical_methods() for q in x["parameters"]} - {q["name"] for q in m["parameters"]}
    for name in others:  # another method's parameter: refused, naming who takes it
        with pytest.raises(ValueError, match=f"has no parameter '{name}': only .* take {name}"):
            canonform.canonical_form(V, F, method, **{name: 1})


def test_unknown_method_lists_the_methods(mesh):
    with pytest.raises(ValueError, match="unknown method 'euclidean-Q' .*euclidean-N"):
        canonform.canonical_form(*mesh, "euclidean-Q")


def rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


@pytest.mark.parametrize("method", ["euclidean-N", "euclidean-A"])
def test_invariant_to_rigid_motion_and_vertex_order(method):
    V, F = canonform.figure(1500, pose=2)
    Y, info = canonform.canonical_form(V, F, method, tolerance=1e-6)
    size = np.sqrt(np.mean(np.sum((Y - Y.mean(0)) ** 2, axis=1)))
    # rotated and translated
    R = rotation(9)
    Y2, info2 = canonform.canonical_form(V @ R.T + [4.0, 5.0, -6.0], F, method, tolerance=1e-6)
    assert aligned_rms(Y2, Y) < 1e-4 * size
    assert info2["feature_points"] == info["feature_points"]
    # vertices re-ordered (and the faces renumbered)
    perm = np.random.default_rng(21).permutation(len(V))  # new vertex k is old vertex perm[k]
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    Y3, _ = canonform.canonical_form(V[perm], inverse[F], method, tolerance=1e-6)
    assert aligned_rms(Y3[inverse], Y) < 1e-4 * size
    # the form really changed the mesh (a pose was removed), so the checks above can fail
    assert aligned_rms(Y, V) > 1e-2 * size
