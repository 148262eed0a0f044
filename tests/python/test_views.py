# SPDX-License-Identifier: GPL-3.0-or-later
"""The view descriptor, codebooks and clock-matching distances against the tool's
`descriptor`, `codebook` and `distance` on the same files."""
import numpy as np
import pytest

import canonform


@pytest.fixture(scope="module")
def figures(tmp_path_factory, run_tool):
    """Four figures (two body types, two poses each) as files."""
    d = tmp_path_factory.mktemp("views")
    paths = []
    for body in ("standard", "long-arms"):
        for pose in (0, 3):
            p = d / f"{body}_{pose}.ply"
            run_tool("generate", p, "--vertices", 800, "--pose", pose, "--class", body)
            paths.append(p)
    return d, paths


def test_raw_features_equal_the_tools_descriptor(figures, run_tool):
    d, paths = figures
    run_tool("descriptor", paths[0], d / "raw.cfvd")
    ref = canonform.read_descriptor(d / "raw.cfvd")
    got = canonform.view_descriptor(*canonform.read_mesh(paths[0]))  # the tool's defaults, SIFT included
    assert ref["codebook_words"] == 0 and ref["views"] == len(got) == 66
    assert [len(f) for f in got] == ref["keypoints_per_view"]
    assert sum(ref["keypoints_per_view"]) > 100
    for a, b in zip(got, ref["features"]):
        assert a.dtype == np.float32 and a.shape[1] == 128 and np.array_equal(a, b)


def test_codebook_histograms_and_distances_equal_the_tools(figures, run_tool):
    d, paths = figures
    run_tool("codebook", d / "cb.bin", *paths, "--words", 40)
    meshes = [canonform.read_mesh(p) for p in paths]
    features = [canonform.view_descriptor(V, F) for V, F in meshes]
    words = canonform.train_codebook(features, words=40)
    assert words.shape == (40, 128) and words.dtype == np.float32
    assert np.array_equal(words, canonform.load_codebook(d / "cb.bin"))
    canonform.save_codebook(d / "cb_py.bin", words)
    assert (d / "cb_py.bin").read_bytes() == (d / "cb.bin").read_bytes()

    hists = []
    for p, (V, F) in zip(paths, meshes):
        run_tool("descriptor", p, d / (p.stem + ".cfvd"), "--codebook", d / "cb.bin")
        ref = canonform.read_descriptor(d / (p.stem + ".cfvd"))
        # the words, or the codebook file (as a path or a str) for the first mesh
        for codebook in (words,) if hists else (words, d / "cb.bin", str(d / "cb.bin")):
            h = canonform.view_descriptor(V, F, codebook)
            assert h.shape == (66, 40) and h.dtype == np.float32
            assert np.array_equal(h, ref["histograms"])
            assert np.array_equal(h.sum(axis=1), ref["keypoints_per_view"])
        hists.append(h)

    run_tool("distance", d / "D.bin", *[d / (p.stem + ".cfvd") for p in paths])
    ref = canonform.read_distance_matrix(d / "D.bin")
    D = canonform.distance_matrix(hists)
    assert D.dtype == np.float32 and D.shape == (4, 4) and np.array_equal(D, ref)
    assert np.array_equal(D, D.T) and not D.diagonal().any() and (D[np.triu_indices(4, 1)] > 0).all()
    for i in range(4):
        for j in range(4):
            assert canonform.clock_distance(hists[i], hists[j]) == pytest.approx(D[i, j], rel=1e-6)


def test_the_descriptor_is_invariant_to_a_rotation_of_the_mesh(figures):
    d, paths = figures
    V, F = canonform.read_mesh(paths[1])
    words = canonform.load_codebook(d / "cb.bin") if (d / "cb.bin").exists() else canonform.train_codebook(
        canonform.view_descriptor(V, F), words=40)
    a = canonform.view_descriptor(V, F, words)
    c, s = np.cos(0.7), np.sin(0.7)
    b = canonform.view_descriptor(V @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T + 3.0, F, words)
    other = canonform.view_descriptor(*canonform.read_mesh(paths[2]), words)
    assert canonform.clock_distance(a, b) < 0.5 * canonform.clock_distance(a, other)


def test_bad_descriptors_are_value_errors():
    h = np.zeros((66, 10), np.float32)
    with pytest.raises(ValueError, match="different view counts"):
        canonform.clock_distance(h, h[:65])
    bad = h.copy()
    bad[3, 2] = -1
    with pytest.raises(ValueError, match="non-positive"):
        canonform.clock_distance(bad, h)
    with pytest.raises(ValueError, match="NaN"):
        canonform.clock_distance(h + np.nan, h)
    with pytest.raises(ValueError, match="descriptor 1 has 11 words"):
        canonform.distance_matrix([h, np.zeros((66, 11))])
    with pytest.raises(ValueError, match="must be one of|opencv"):
        canonform.view_descriptor(*canonform.figure(500), sift="surf")
    with pytest.raises(ValueError, match="image_size must be between 32 and 2048"):
        canonform.view_descriptor(*canonform.figure(500), image_size=8)
    with pytest.raises(ValueError, match=r"shape \(n, 128\)"):
        canonform.train_codebook(np.zeros((10, 64), np.float32))
    with pytest.raises(ValueError, match="words must be between"):
        canonform.train_codebook(np.zeros((10, 128), np.float32), words=0)


def test_a_codebook_larger_than_its_training_set_is_refused():
    with pytest.raises(ValueError, match="words"):
        canonform.train_codebook(np.ones((30, 128), np.float32) * np.arange(30)[:, None], words=40)
