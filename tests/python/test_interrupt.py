# SPDX-License-Identifier: GPL-3.0-or-later
"""Long calls stop on Ctrl-C (KeyboardInterrupt, through the library's cancellation) and report
progress to a callable, which can cancel them."""
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import canonform

CHILD = textwrap.dedent("""
    import os, signal, sys, threading, time
    import numpy as np
    import canonform
    what = sys.argv[1]
    V, F = canonform.figure(3000)
    if what == "smacof":  # SMACOF to an iteration cap it would take minutes to reach
        call = lambda: canonform.canonical_form(V, F, tolerance=0, max_iterations=10000000, acceleration="none")
    elif what == "geodesic":  # fast marching from every vertex, then SMACOF on all pairs: tens of seconds
        V, F = canonform.figure(6000)
        call = lambda: canonform.canonical_form(V, F, "geodesic-ls", tolerance=0, max_iterations=100000)
    elif what == "retrieve":  # a retrieval run over 30 meshes: stops between meshes
        os.makedirs("coll", exist_ok=True)
        rows = ["path,class"]
        for body in ("standard", "long-arms", "short-legs", "stocky", "long-neck"):
            for pose in range(6):
                canonform.write_mesh(f"coll/{body}_{pose}.ply", *canonform.figure(800, pose=pose, body=body))
                rows.append(f"{body}_{pose}.ply,{body}")
        open("coll/labels.csv", "w").write("\\n".join(rows) + "\\n")
        call = lambda: canonform.retrieve("coll", "run", ["euclidean-N", "euclidean-A"], words=50)
    else:  # clock matching of 1500 random descriptors: minutes
        rng = np.random.default_rng(1)
        H = [(rng.random((66, 300)) < 0.1).astype(np.float32) * 3 for _ in range(1500)]
        call = lambda: canonform.distance_matrix(H)
    threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    t0 = time.perf_counter()
    try:
        call()
        print("finished", time.perf_counter() - t0)
    except KeyboardInterrupt:
        print("interrupted", time.perf_counter() - t0)
""")


@pytest.mark.parametrize("what", ["smacof", "geodesic", "distances", "retrieve"])
def test_ctrl_c_stops_a_long_call(what, tmp_path):
    (tmp_path / "child.py").write_text(CHILD)
    r = subprocess.run([sys.executable, str(tmp_path / "child.py"), what], capture_output=True, text=True, timeout=300,
                       cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    word, seconds = r.stdout.split()
    assert word == "interrupted", r.stdout
    assert float(seconds) < 10, f"{what}: stopped {float(seconds) - 1:.1f} s after Ctrl-C"


def test_progress_is_reported_and_a_false_cancels():
    V, F = canonform.figure(2000)
    seen = []
    Y, _ = canonform.canonical_form(V, F, progress=lambda f, stage: seen.append((f, stage)))
    fractions = [f for f, _ in seen]
    assert len(seen) >= 5 and fractions == sorted(fractions) and fractions[-1] == 1.0 and fractions[0] >= 0
    assert any("SMACOF" in s for _, s in seen) and any("conformal" in s for _, s in seen)
    assert np.array_equal(Y, canonform.canonical_form(V, F)[0])  # progress changes nothing

    def stop_at_smacof(f, stage):
        return "SMACOF" not in stage

    with pytest.raises(canonform.Cancelled, match="cancelled by the user"):
        canonform.canonical_form(V, F, progress=stop_at_smacof)

    class Mine(Exception):
        pass

    def fail(f, stage):
        raise Mine("from the callable")

    with pytest.raises(Mine, match="from the callable"):
        canonform.conformal_factor(V, F, progress=fail)
    with pytest.raises(ValueError, match="progress must be a callable"):
        canonform.canonical_form(V, F, progress=3)
