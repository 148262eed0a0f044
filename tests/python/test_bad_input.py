# SPDX-License-Identifier: GPL-3.0-or-later
"""The README's bad-input table through the module: each row raises ValueError (InputError) or
RuntimeError with the library's message naming the cause, never crashes the interpreter, and
writes nothing."""
import math
import os

import numpy as np
import pytest

import canonform

FIG_V, FIG_F = canonform.figure(1200, pose=1)


def off(path, V, F):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        f.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in V)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in F)


def small_off(face):
    """The tool's test mesh: 12 vertices and 11 faces, the first face replaced."""
    lines = ["OFF", "12 12 0"] + [f"{k} {k * k % 7} {k % 4}" for k in range(12)] + [face]
    lines += [f"3 {k} {(k + 1) % 12} {(k + 2) % 12}" for k in range(1, 12)]
    return "\n".join(lines) + "\n"


@pytest.fixture
def work(tmp_path):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    yield tmp_path
    os.chdir(cwd)
    leftovers = [p.name for p in tmp_path.iterdir() if p.name.startswith(("out", ".out"))]
    assert not leftovers, f"half-written outputs left: {leftovers}"


# --- files ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("content, name, pattern", [
    (None, "missing.off", "no such file"),
    ("", "empty.off", "the file is empty"),
    ("hello", "image.png", "unsupported .*'.png'"),
    ("ply\nformat ascii 1.0\n", "fake.off", "not an OFF file: it starts like a PLY file"),
    (small_off("3 0 100000000 10"), "huge.off", "face index 100000000 on line 15 is out of range: the file has 12 vertices"),
    (small_off("3 0 12 10"), "n.off", "face index 12 on line 15 is out of range"),
    (small_off("3 0 -1 10"), "neg.off", "face index -1 on line 15 is out of range"),
    (small_off("3 0 1 2").replace("12 12 0", "40000000 12 0"), "lies.off", "claims 40000000 vertices.*the header lies"),
    (small_off("3 0 1 2").replace("12 12 0", "2000000000 12 0"), "lies2.off", "claims 2000000000 vertices.*the header lies"),
    (small_off("3 0 1 2")[:60], "cut.off", "can hold at most 8: the header lies \\(a truncated or corrupt file\\)"),
    ("OFF\n4 1 0\n0 0 0\n1 x 0\n0 1 0\n0 0 1\n3 0 1 2\n", "bad.off", "bad vertex on line 4"),
])
def test_unreadable_mesh_files(work, content, name, pattern):
    if content is not None:
        (work / name).write_text(content)
    with pytest.raises(ValueError, match=pattern):
        canonform.read_mesh(work / name)


def test_a_folder_as_a_mesh_codebook_descriptor_matrix_or_labels(work):
    for name in ("folder.off", "folder.bin", "folder.cfvd", "folder.csv"):
        (work / name).mkdir()
    with pytest.raises(ValueError, match="is a folder"):
        canonform.read_mesh(work / "folder.off")
    with pytest.raises(ValueError, match="is a folder"):
        canonform.load_codebook(work / "folder.bin")
    with pytest.raises(ValueError, match="is a folder"):
        canonform.view_descriptor(FIG_V, FIG_F, work / "folder.bin")
    with pytest.raises(ValueError, match="is a folder"):
        canonform.read_descriptor(work / "folder.cfvd")
    with pytest.raises(ValueError, match="is a folder"):
        canonform.evaluate(work / "folder.bin", ["a", "a", "a"])
    with pytest.raises(ValueError, match="is a folder"):
        canonform.evaluate(np.zeros((3, 3)), work / "folder.csv")


def test_broken_codebook_descriptor_matrix_and_labels_files(work):
    (work / "bad.bin").write_bytes(b"not a matrix")
    with pytest.raises(ValueError, match="not a square float32 matrix"):
        canonform.evaluate(work / "bad.bin", ["a"] * 3)
    with pytest.raises(ValueError, match="magic"):
        canonform.load_codebook(work / "bad.bin")
    with pytest.raises(ValueError, match="magic"):
        canonform.read_descriptor(work / "bad.bin")
    (work / "noclass.csv").write_text("path,class\na,x\nb,\nc,y\n")
    with pytest.raises(ValueError, match="row 3 has no class"):
        canonform.evaluate(np.zeros((3, 3)), work / "noclass.csv")


def test_class_names_with_quotes_and_invalid_utf8(work):
    (work / "labels.csv").write_bytes(b'path,class\na,cl"ass\nb,cl"ass\nc,cl"ass\nd,\xff\xfe\ne,\xff\xfe\nf,\xff\xfe\n')
    D = np.full((6, 6), 2.0)
    D[:3, :3] = D[3:, 3:] = 1.0
    np.fill_diagonal(D, 0)
    e = canonform.evaluate(D, work / "labels.csv")
    assert 'cl"ass' in e["classes"] and "\ufffd\ufffd" in e["classes"] and e["nn"] == 1


# --- meshes the library refuses ---------------------------------------------------------------------

def meshes():
    V, F = FIG_V, FIG_F
    nan = V.copy()
    nan[0, 0] = np.nan
    inf = V.copy()
    inf[5, 2] = np.inf
    huge = V * 1e251 / np.abs(V).max()
    tiny_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    tiny_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    # two copies side by side: two components
    two_V = np.vstack([V, V + [10.0, 0, 0]])
    two_F = np.vstack([F, F + len(V)])
    # a duplicated face, an unreferenced vertex, a repeated-vertex face
    dup_F = np.vstack([F, F[:1]])
    unref_V = np.vstack([V, [[9.0, 9.0, 9.0]]])
    rep_F = F.copy()
    rep_F[0] = [rep_F[0, 0], rep_F[0, 0], rep_F[0, 1]]
    # a non-manifold edge: a third face on edge (F[0,0], F[0,1]) to a new vertex
    nm_V = np.vstack([V, [[0.0, 0.0, 5.0]]])
    nm_F = np.vstack([F, [[F[0, 0], F[0, 1], len(V)]]])
    return [
        ("no vertices", np.zeros((0, 3)), np.zeros((0, 3), int), "empty"),
        ("a point cloud", V, np.zeros((0, 3), int), "no faces"),
        ("NaN coordinates", nan, F, "NaN or infinite"),
        ("infinite coordinates", inf, F, "NaN or infinite"),
        ("fewer than 10 vertices", tiny_V, tiny_F, "vertices"),
        ("all vertices at one point", np.ones_like(V), F, "one point"),
        ("coordinates beyond 1e250", huge, F, "1e\\+?250"),
        ("several components", two_V, two_F, "component"),
        ("a duplicate face", V, dup_F, "non-manifold edges"),  # three faces on each of its edges
        ("an unreferenced vertex", unref_V, F, "1 vertices that belong to no face"),
        ("a repeated-vertex face", V, rep_F, "degenerate|repeated"),
        ("a non-manifold edge", nm_V, nm_F, "non-manifold"),
        ("a face index out of range", V, np.vstack([F, [[0, 1, len(V)]]]), "out of range"),
        ("a negative face index", V, np.vstack([F, [[0, 1, -1]]]), "out of range"),
    ]


@pytest.mark.parametrize("what, V, F, pattern", meshes(), ids=[m[0] for m in meshes()])
def test_meshes_the_library_refuses(what, V, F, pattern):
    for call in (lambda: canonform.canonical_form(V, F), lambda: canonform.canonical_form(V, F, "geodesic-fast"),
                 lambda: canonform.conformal_factor(V, F), lambda: canonform.feature_points(V, F),
                 lambda: canonform.simplify(V, F, 500)):
        with pytest.raises(ValueError, match=pattern):
            call()


def test_repair_lets_fixable_meshes_through():
    V, F = FIG_V, FIG_F
    dup_F = np.vstack([F, F[:1]])
    with pytest.raises(ValueError, match="non-manifold"):
        canonform.canonical_form(V, dup_F)
    V2, F2, summary = canonform.repair_mesh(V, dup_F)
    assert "1 duplicate face" in summary and len(F2) == len(F), summary
    assert np.array_equal(canonform.canonical_form(V2, F2)[0], canonform.canonical_form(V, F)[0])
    with pytest.raises(ValueError, match="NaN"):  # repair invents no geometry
        nan = V.copy()
        nan[0] = np.nan
        canonform.canonical_form(*canonform.repair_mesh(nan, F)[:2])


@pytest.mark.parametrize("scale", [1e200, 1e-200])
def test_coordinates_of_1e200_and_1e_200_are_accepted(scale):
    Y, info = canonform.canonical_form(FIG_V, FIG_F)
    Ys, infos = canonform.canonical_form(FIG_V * scale, FIG_F)
    assert infos["feature_points"] == info["feature_points"] and abs(infos["iterations"] - info["iterations"]) <= 2
    assert abs(infos["final_stress"] - info["final_stress"]) <= 1e-6 * info["final_stress"]
    assert np.isfinite(Ys).all()


# --- options ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, pattern", [
    (lambda: canonform.canonical_form(FIG_V, FIG_F, beta=math.nan), "beta must be a positive number.*'nan'"),
    (lambda: canonform.canonical_form(FIG_V, FIG_F, beta=-1), "beta must be a positive number.*'-1'"),
    (lambda: canonform.canonical_form(FIG_V, FIG_F, "geodesic-ls", max_memory_gib=math.nan), "max_memory_gib.*'nan'"),
    (lambda: canonform.canonical_form(FIG_V, FIG_F, threads=-1), "threads"),
    (lambda: canonform.feature_points(FIG_V, FIG_F, ring=0), "ring"),
    (lambda: canonform.feature_points(FIG_V, FIG_F, ring=11), "ring"),
    (lambda: canonform.feature_points(FIG_V, FIG_F, seed=-1), "seed"),
    (lambda: canonform.feature_points(FIG_V, FIG_F, fill="some"), "fill"),
    (lambda: canonform.simplify(FIG_V, FIG_F, 5000), "target|vertices"),
    (lambda: canonform.figure(10), "vertices must be between"),
    (lambda: canonform.figure(body="octopus"), "octopus"),
    (lambda: canonform.distance_matrix([], threads=-1), "threads"),
])
def test_option_values_out_of_range(call, pattern):
    with pytest.raises(ValueError, match=pattern):
        call()


# --- outputs --------------------------------------------------------------------------------------------

def test_outputs_in_the_format_their_name_says_or_refused(work):
    for ext, magic in (("off", b"OFF"), ("obj", b"# c"), ("stl", b"can"), ("ply", b"ply")):
        canonform.write_mesh(work / f"form.{ext}", FIG_V, FIG_F)
        assert (work / f"form.{ext}").read_bytes()[:3] == magic
        assert np.allclose(canonform.read_mesh(work / f"form.{ext}")[0].shape, FIG_V.shape) or ext == "stl"
    with pytest.raises(ValueError, match="unsupported mesh format '.xyz'"):
        canonform.write_mesh(work / "out.xyz", FIG_V, FIG_F)
    with pytest.raises(ValueError, match="cannot hold a point cloud"):
        canonform.write_mesh(work / "out.stl", FIG_V, None)
    with pytest.raises(ValueError, match="out of range|face index"):
        canonform.write_mesh(work / "out.ply", FIG_V, np.array([[0, 1, len(FIG_V)]]))
    with pytest.raises(ValueError, match="quality has 3 values"):
        canonform.write_mesh(work / "out.ply", FIG_V, FIG_F, quality=[1.0, 2.0, 3.0])
    (work / "v1.2").mkdir()
    canonform.write_mesh(work / "v1.2" / "G", FIG_V, FIG_F)  # no extension in a dotted folder: PLY
    assert (work / "v1.2" / "G").read_bytes()[:3] == b"ply"
    q = np.linspace(0, 1, len(FIG_V))
    canonform.write_mesh(work / "q.ply", FIG_V, FIG_F, quality=q)
    assert np.array_equal(canonform.read_mesh(work / "q.ply", quality=True)[2], q)
