# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python module's costs, measured side by side in one run (docs/python.md, "Speed and import
time"): the call overhead of canonform.canonical_form() against the same C++ call, and the time
`import canonform` takes.

    /usr/bin/python3 bench/python_bench.py BUILD_DIR [--vertices 10000] [--method euclidean-N]
                                           [--repeats 15] [--rounds 3] [--out bench/results/python.jsonl]
                                           [--package DIR] [--wheel WHEEL]

Overhead, call by call in one process: canonical_form() on the arrays read_mesh() gives (arrays
converted in and out, validation, the GIL released, the progress function that watches for Ctrl-C;
wall time around the Python call), and the bare C++ call it makes (_cpp_call_seconds(): the
registry's run() with validation, timed in C++ by the C API's canonform_time_canonical_form, no
progress function), alternating
(which goes first alternates too), --repeats x --rounds pairs, one thread. Reported: the median of
the per-pair ratios minus 1, and both medians; the same from the calling thread's CPU time
(time.thread_time(): steadier than wall time on a loaded machine). As a cross-check, canonform_bench_canonical
(bench/bench_canonical_form.cpp, the same run() in a C++ program) on the same file, median of
--repeats calls per round. And the overhead in seconds on method "none" (where the call is short,
so load hardly blurs it), as a fraction of the C++ call's median. Import: wall time of `import canonform`
in a fresh interpreter (median of 11 processes), alone and after numpy (which the module loads on
its first array, not at import; the library is loaded on the first call). The package is
BUILD_DIR/python's, or the one under --package DIR (e.g. the portable wheel unpacked there, whose
size --wheel records too).
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--vertices", type=int, default=10000)
    ap.add_argument("--method", default="euclidean-N")
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default=None)
    ap.add_argument("--package", default=None)
    ap.add_argument("--wheel", default=None)
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    package = os.path.abspath(a.package) if a.package else os.path.join(build, "python")
    sys.path.insert(0, package)
    import canonform

    work = os.path.join(build, "bench_python")
    os.makedirs(work, exist_ok=True)
    mesh = os.path.join(work, f"figure_{a.vertices}.ply")
    subprocess.run([os.path.join(build, "apps", "canonform"), "generate", mesh, "--vertices", str(a.vertices)],
                   check=True)
    V, F = canonform.read_mesh(mesh)

    cpp, py, ratios, process = [], [], [], []
    cpp_cpu, py_cpu, cpu_ratios = [], [], []  # the calling thread's CPU seconds (steadier on a loaded machine)
    canonform.canonical_form(V, F, a.method, threads=1)  # warm: first-touch of the libraries
    for r in range(a.rounds):
        out = subprocess.run([os.path.join(build, "bench", "canonform_bench_canonical"), mesh, "--method", a.method,
                              "--repeats", str(a.repeats), "--threads", "1"], check=True, capture_output=True,
                             text=True).stdout
        process.append(json.loads(out)["median_s"])
        for k in range(a.repeats):
            for first in ((True, False) if (k + r) % 2 == 0 else (False, True)):
                if first:
                    c0, t0 = time.thread_time(), time.perf_counter()
                    canonform.canonical_form(V, F, a.method, threads=1)
                    py.append(time.perf_counter() - t0)
                    py_cpu.append(time.thread_time() - c0)
                else:
                    c0 = time.thread_time()
                    cpp.append(canonform._cpp_call_seconds(V, F, a.method))
                    cpp_cpu.append(time.thread_time() - c0)
            ratios.append(py[-1] / cpp[-1])
            cpu_ratios.append(py_cpu[-1] / cpp_cpu[-1])

    # The overhead in seconds, where load noise is small: method "none" (validation and a copy of V)
    # in Python and in C++, 200 pairs; the same conversion, GIL and wrapper costs as any method's.
    extra = []
    for k in range(200):
        t0 = time.perf_counter()
        canonform.canonical_form(V, F, "none", threads=1)
        t_py = time.perf_counter() - t0
        extra.append(t_py - canonform._cpp_call_seconds(V, F, "none"))

    def import_seconds(pre, load=False, cpu=False):
        clock = "process_time" if cpu else "perf_counter"
        code = f"import time{'; import numpy' if pre else ''}; t = time.{clock}(); import canonform; " \
               f"{'canonform.sift_backends(); ' if load else ''}print(time.{clock}() - t)"
        env = dict(os.environ, PYTHONPATH=package)
        return statistics.median(float(subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                                      capture_output=True, text=True).stdout) for _ in range(11))

    row = {
        "bench": "python", "vertices": int(len(V)), "method": a.method, "pairs": len(ratios),
        "overhead": statistics.median(ratios) - 1,
        "overhead_quartiles": [q - 1 for q in statistics.quantiles(ratios, n=4)],
        "cpp_median_s": statistics.median(cpp), "python_median_s": statistics.median(py),
        "cpp_program_round_medians_s": process,
        "overhead_none_s": statistics.median(extra), "overhead_none_fraction": statistics.median(extra) / statistics.median(cpp),
        "import_s": import_seconds(False), "import_after_numpy_s": import_seconds(True),
        "import_and_library_s": import_seconds(False, True),
        "cpu_overhead": statistics.median(cpu_ratios) - 1,
        "cpu_overhead_quartiles": [q - 1 for q in statistics.quantiles(cpu_ratios, n=4)],
        "cpp_cpu_median_s": statistics.median(cpp_cpu), "python_cpu_median_s": statistics.median(py_cpu),
        "import_cpu_s": import_seconds(False, cpu=True), "import_and_library_cpu_s": import_seconds(False, True, True),
        "package": "wheel" if a.wheel else "build" if not a.package else "package",
        "python": platform.python_version(), "load": os.getloadavg()[0],
        "commit": subprocess.run(["git", "-C", os.path.dirname(os.path.abspath(__file__)), "rev-parse", "--short",
                                  "HEAD"], capture_output=True, text=True).stdout.strip(),
    }
    if a.wheel:
        row["wheel"] = os.path.basename(a.wheel)
        row["wheel_bytes"] = os.path.getsize(a.wheel)
    line = json.dumps(row)
    print(line)
    if a.out:
        with open(a.out, "a") as f:
            f.write(line + "\n")


if __name__ == "__main__":
    main()
