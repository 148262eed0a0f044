#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The wheel as a Python user meets it, inside one root filesystem (tools/host.sh RELEASE-python:
# Debian's Python, numpy, matplotlib and pytest, no compiler), run by tests/e2e/wheel_venv_test.sh:
# a fresh venv (--system-site-packages: the release's numpy), `pip install --no-index WHEEL`, then
# import, the console command, the examples, the package's smoke tests, and the outputs the
# releases must agree on, bit for bit, in OUT/results/.
#   wheel_inside.sh SOURCE_DIR WHEEL OUT_DIR
set -u
src=$1 wheel=$2 out=$3
. "$src/tests/e2e/lib.sh"
rm -rf "$out"; mkdir -p "$out/results" "$out/tmp"; cd "$out" || exit 1
export XDG_CACHE_HOME=$out/cache MPLCONFIGDIR=$out/matplotlib PIP_NO_CACHE_DIR=1 PIP_DISABLE_PIP_VERSION_CHECK=1 \
  PYTHONDONTWRITEBYTECODE=1 MPLBACKEND=Agg TMPDIR=$out/tmp
. /etc/os-release
echo "  $PRETTY_NAME, $(python3 --version), numpy $(python3 -c 'import numpy; print(numpy.__version__)'), glibc $(ldd --version | head -n 1 | awk '{print $NF}')"
compilers=$(for c in cc gcc g++ c++ clang; do command -v "$c"; done)
check "no compiler (${compilers:-none found}) and no Python headers" \
  bash -c "[ -z '$compilers' ] && ! ls /usr/include/python3*/Python.h >/dev/null 2>&1"

python3 -m venv --system-site-packages venv
check "pip install --no-index $(basename "$wheel") into a fresh venv" \
  bash -c "venv/bin/python -m pip install --no-index --quiet '$wheel' > pip.log 2>&1"
py=$out/venv/bin/python
export PATH=$out/venv/bin:$PATH
check "import canonform: the venv's copy, its library loaded" \
  bash -c "$py -c 'import canonform, sys; assert canonform.__file__.startswith(sys.prefix); canonform.figure(500)'"
check "the console command: canonform --version" bash -c "canonform --version > results/version.txt && grep -q '^canonform [0-9]' results/version.txt"
check "pymeshlab flavours in the wheel: 2022.2, 2023.12, 2025.7" \
  bash -c "$py -c 'import canonform.pymeshlab as p; assert p.supported() == [\"2022.2\", \"2023.12\", \"2025.7\"], p.supported()'"

# The outputs: the tool's and the module's, on the same figure
canonform generate fig.ply --vertices 2000 --pose 3 2> /dev/null
check "canonform canonical (the console command)" canonform canonical fig.ply results/form_tool.ply --quiet
canonform descriptor fig.ply results/raw_tool.cfvd 2> /dev/null
"$py" - > results/module.txt 2> module.err <<'PY'
import hashlib, json
import numpy as np
import canonform
V, F = canonform.read_mesh("fig.ply")
out = {}
Y, info = canonform.canonical_form(V, F)
out["form"] = Y
out["form_A"] = canonform.canonical_form(V, F, "euclidean-A", beta=65)[0]
out["form_geodesic"] = canonform.canonical_form(*canonform.simplify(V, F, 600), "geodesic-classical")[0]
out["phi"] = canonform.conformal_factor(V, F)
feats = canonform.view_descriptor(V, F)
out["sift"] = np.concatenate(feats)
words = canonform.train_codebook(feats, words=30, method="lloyd")
H = [canonform.view_descriptor(*canonform.figure(1000, pose=p), words) for p in range(3)]
out["histograms"] = np.stack(H)
out["distances"] = canonform.distance_matrix(H)
tool = canonform.read_mesh("results/form_tool.ply")[0]
print("form equals the tool's:", np.array_equal(Y.view(np.uint64), tool.view(np.uint64)))
raw = canonform.read_descriptor("results/raw_tool.cfvd")["features"]
print("features equal the tool's:", all(np.array_equal(a, b) for a, b in zip(feats, raw)))
for k, a in out.items():
    np.ascontiguousarray(a).tofile(f"results/{k}.{a.dtype}.bin")  # raw bytes: no file format of numpy's own
    print(k, a.dtype, a.shape, hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()[:16])
PY
check "the module's outputs written" test -s results/distances.float32.bin
check "... its form is the tool's, to the bit" grep -q "form equals the tool's: True" results/module.txt
check "... its raw SIFT features are the tool's descriptor file's" grep -q "features equal the tool's: True" results/module.txt

# examples/python, as a user runs them
check "examples/python/canonical_form.py" bash -c "$py '$src/examples/python/canonical_form.py' fig.ply example.png > example.txt 2>&1 && test -s example.png"
check "examples/python/retrieval.py" bash -c "$py '$src/examples/python/retrieval.py' retrieval > retrieval.txt 2>&1"
cp retrieval/run/euclidean-N/distances.bin results/retrieval_distances.bin 2> /dev/null
grep -E "NN .*1-tier" retrieval.txt > results/retrieval_measures.txt

# the package's smoke tests: tests/python against the wheel's own tool
smoke=(test_module.py test_library.py test_arrays.py "test_canonical.py::test_given_parameters_equal_the_tools_options"
       "test_views.py::test_raw_features_equal_the_tools_descriptor" "test_bad_input.py::test_unreadable_mesh_files"
       "test_interrupt.py::test_progress_is_reported_and_a_false_cancels")
args=(); for t in "${smoke[@]}"; do args+=("$src/tests/python/$t"); done
# (the exports check reads the library with objdump, which a user's system need not have)
check "the smoke tests (tests/python: ${#smoke[@]} files or tests)" bash -c "cd '$out' && CANONFORM_TOOL='$out/venv/bin/canonform' \
  CANONFORM_SOURCE_DIR='$src' '$py' -m pytest -p no:cacheprovider --basetemp='$out/pytest' -q -k 'not exports' ${args[*]} > pytest.log 2>&1"
tail -n 1 pytest.log | sed 's/^/    /'
finish
