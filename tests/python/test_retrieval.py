# SPDX-License-Identifier: GPL-3.0-or-later
"""evaluate() against `canonform evaluate --json`; retrieve() against `canonform retrieve` on the
same collection."""
import json

import numpy as np
import pytest

import canonform


def test_evaluate_equals_the_tools_json(tmp_path, run_tool):
    rng = np.random.default_rng(5)
    labels = ["cat"] * 4 + ["dog"] * 5 + ["horse"] * 3 + ["lone"] * 2
    n = len(labels)
    D = rng.random((n, n)).astype(np.float32)
    D = (D + D.T) / 2
    np.fill_diagonal(D, 0)
    D.tofile(tmp_path / "D.bin")
    (tmp_path / "labels.csv").write_text("path,class\n" + "".join(f"m{k}.off,{c}\n" for k, c in enumerate(labels)))
    ref = json.loads(run_tool("evaluate", tmp_path / "D.bin", "--labels", tmp_path / "labels.csv", "--json"))
    for d, l in ((D, labels), (tmp_path / "D.bin", tmp_path / "labels.csv"), (D.astype(np.float64), np.array(labels))):
        e = canonform.evaluate(d, l)
        for key in ("micro", "macro", "classes", "precision"):
            assert e[key] == ref[key], key
        assert e["nn"] == ref["micro"]["nn"] and e["dcg"] == ref["micro"]["dcg"]
        assert len(e["recall"]) == len(e["precision"]) == 20 and e["recall"][-1] == pytest.approx(1.0)
        assert e["skipped_classes"] == ["lone"]


def test_evaluate_refuses_bad_input():
    with pytest.raises(ValueError, match="square|labels"):
        canonform.evaluate(np.zeros((3, 4)), ["a", "a", "a"])
    with pytest.raises(ValueError):
        canonform.evaluate(np.zeros((3, 3)), ["a", "a"])
    D = np.ones((3, 3))
    D[0, 1] = np.nan
    with pytest.raises(ValueError, match="finite|NaN"):
        canonform.evaluate(D, ["a", "a", "a"])


@pytest.fixture(scope="module")
def collection(tmp_path_factory, run_tool):
    d = tmp_path_factory.mktemp("retrieve")
    run_tool("generate", "--collection", d / "coll", "--vertices", 600, "--poses", 3, "--classes", "standard,long-arms")
    return d


def test_retrieve_equals_the_tools_run(collection, run_tool):
    d = collection
    run_tool("retrieve", "--dataset", d / "coll", "--out", d / "run_tool", "--method", "none,euclidean-N",
             "--words", 30)
    lines, fractions = [], []
    r = canonform.retrieve(d / "coll", d / "run_py", ["none", "euclidean-N"], words=30, log=lines.append,
                           progress=lambda f, stage: fractions.append((f, stage)))
    assert set(r["methods"]) == {"none", "euclidean-N"}
    for m in ("none", "euclidean-N"):
        tool_dir, py_dir = d / "run_tool" / m, d / "run_py" / m
        for f in ("distances.bin", "metrics.json", "pr.csv", "models.csv", "codebook.bin"):
            assert (py_dir / f).read_bytes() == (tool_dir / f).read_bytes(), f"{m}/{f}"
        metrics = json.loads((tool_dir / "metrics.json").read_text())
        got = r["methods"][m]
        assert got["measures"]["micro"] == metrics["micro"] and got["measures"]["macro"] == metrics["macro"]
        assert got["meshes"] == 6 and got["failed"] == 0
        assert np.array_equal(canonform.read_distance_matrix(py_dir / "distances.bin"),
                              canonform.read_distance_matrix(tool_dir / "distances.bin"))
    assert (d / "run_py" / "report.md").read_text() == r["report"] and "| euclidean-N |" in r["report"]
    assert any("[euclidean-N] 6 meshes" in line for line in lines)
    assert fractions and all(0 <= f <= 1 for f, _ in fractions) and any("euclidean-N" in s for _, s in fractions)
    # a second run reads everything from the cache and gives the same measures
    again = canonform.retrieve(d / "coll", d / "run_py", "none,euclidean-N", words=30)
    assert again["methods"]["euclidean-N"]["cached"] == 6
    assert again["methods"]["euclidean-N"]["measures"] == r["methods"]["euclidean-N"]["measures"]


def test_retrieve_refuses_bad_options_before_any_work(collection, tmp_path):
    d = collection
    for kwargs, pattern in (({"noise": float("inf")}, "noise must be a finite number"), ({"threads": -1}, "threads"),
                            ({"words": 0}, "words"), ({"methods": ["euclidean-N:beta=nan"]}, "beta"),
                            ({"methods": ["nope"]}, "unknown method 'nope'"), ({"sift": "surf"}, "surf"),
                            ({"labels": tmp_path / "missing.csv"}, "missing.csv")):
        args = {"methods": ["none"], **kwargs}
        with pytest.raises(ValueError, match=pattern):
            canonform.retrieve(d / "coll", tmp_path / "run", **args)
    assert not (tmp_path / "run" / "none").exists()


def test_retrieve_bad_collections(collection, tmp_path):
    coll = collection / "coll"
    rows = (coll / "labels.csv").read_text().splitlines()
    # a row naming a missing mesh: a listed failure, the run goes on
    (coll / "labels_missing.csv").write_text("\n".join(rows + ["meshes/gone.ply,standard"]) + "\n")
    lines = []
    r = canonform.retrieve(coll, tmp_path / "run", ["none"], labels=coll / "labels_missing.csv", words=20,
                           log=lines.append)
    assert r["methods"]["none"]["failed"] == 1 and r["methods"]["none"]["meshes"] == 6
    assert "gone" in (tmp_path / "run" / "none" / "failures.txt").read_text()
    # a corrupt cache entry is recomputed, with a log line, and changes nothing
    entry = sorted((tmp_path / "run" / "cache").glob("*.cfvd"))[0]
    entry.write_bytes(b"garbage")
    lines.clear()
    again = canonform.retrieve(coll, tmp_path / "run", ["none"], labels=coll / "labels_missing.csv", words=20,
                               log=lines.append)
    assert again["methods"]["none"]["measures"] == r["methods"]["none"]["measures"]
    assert again["methods"]["none"]["cached"] == 5 and any("corrupt cache entry recomputed" in l for l in lines), lines
    # two models of one name, fewer than three models: refused before any work, naming them
    (coll / "labels_twice.csv").write_text("\n".join(rows + [rows[1]]) + "\n")
    with pytest.raises(ValueError, match="two models are named 'standard_0'"):
        canonform.retrieve(coll, tmp_path / "run2", ["none"], labels=coll / "labels_twice.csv")
    (coll / "labels_two.csv").write_text("\n".join(rows[:3]) + "\n")
    with pytest.raises(ValueError, match="at least three meshes"):
        canonform.retrieve(coll, tmp_path / "run3", ["none"], labels=coll / "labels_two.csv")
    assert not (tmp_path / "run2" / "none").exists() and not (tmp_path / "run3" / "none").exists()
    # classes of two models or fewer: evaluate refuses when no class has three
    with pytest.raises(ValueError, match="no class has more than two models"):
        canonform.evaluate(np.ones((4, 4)) - np.eye(4), ["a", "a", "b", "b"])
