# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs the pymeshlab examples of the README and the docs as written, as far as the pymeshlab harness
can show.

usage: readme_pymeshlab_test.py DOC[,DOC...] WORKDIR CANONFORM [--release 2022.2|2023.12|2025.7 HARNESS PLUGIN_DIR]...

Each ```python block of each DOC (README.md, docs/pymeshlab.md, docs/install.md) whose first line is
"# pymeshlab 2022.2" (or "# pymeshlab 2023.12", "# pymeshlab 2025.7") is executed by Python as written, with a stand-in for the `pymeshlab` module
of that release:
- it has exactly the module functions and MeshSet methods of that release (their names as that
  release's bindings define them, below); any other name raises AttributeError, as pymeshlab would;
- load_plugin, MeshSet.load_new_mesh, number_meshes / mesh_number, set_current_mesh and
  apply_filter are answered by the harness of that release (tests/pymeshlab_harness.cpp --serve:
  MeshLab's own meshlab-common of that release in double precision, as pymeshlab is), returned
  vectors arriving as 1-D numpy arrays as both releases convert them; a failure raises
  pymeshlab.PyMeshLabException with MeshLab's message;
- the other methods raise NotImplementedError, and the test says so.
Then every filter is applied once per release, and the keys of the dict it returns must be those of
its row in the docs' table of what the filters return (docs/pymeshlab.md).
What it cannot show: pymeshlab's own IO plugins (load_new_mesh reads the PLY with canonform's
reader) and its Python packaging. The example's plugin folder '/path/to/canonform/build/...' is
replaced by the build's; figure.ply and codebook.bin are generated in WORKDIR. A PLUGIN_DIR that is a
portable archive (canonform-plugins-*.tar.gz, tools/package.sh --portable) is extracted into
WORKDIR, where docs/install.md's examples name its folder as a user who extracted it there would.
"""
import contextlib
import io
import json
import os
import re
import subprocess
import sys

import numpy

# MeshSet methods and module functions, as the bindings of each release define them
# (src/pymeshlab/bindings/pymeshset.cpp and pymodule_functions.cpp of PyMeshLab v2022.2.post2, v2025.7).
MESHSET_2022 = ["number_meshes", "number_rasters", "set_current_mesh", "current_mesh", "current_mesh_id",
                "mesh_id_exists", "mesh", "set_current_mesh_visibility", "set_mesh_visibility",
                "is_current_mesh_visible", "is_mesh_visible", "load_new_mesh", "save_current_mesh",
                "load_new_raster", "add_mesh", "clear", "load_project", "save_project", "apply_filter",
                "load_filter_script", "save_filter_script", "clear_filter_script", "apply_filter_script",
                "print_status", "filter_parameter_values", "print_filter_script", "set_verbosity",
                "set_parameter_verbosity"]
METHODS = {"2022.2": MESHSET_2022, "2023.12": MESHSET_2022 + ["mesh_number", "raster_number"],
           "2025.7": MESHSET_2022 + ["mesh_number", "raster_number"]}
MODULE_FUNCTIONS = ["load_default_plugins", "print_pymeshlab_version", "filter_list", "number_plugins",
                    "print_plugin_list", "print_plugin_filter_list", "print_filter_list",
                    "print_filter_parameter_list", "search", "load_plugin"]


class Harness:
    def __init__(self, path):
        self.p = subprocess.Popen([path, "--serve"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=subprocess.DEVNULL, text=True)

    def ask(self, exception, **request):
        self.p.stdin.write(json.dumps(request) + "\n")
        self.p.stdin.flush()
        answer = json.loads(self.p.stdout.readline())
        if "error" in answer:
            raise exception(answer["error"])
        return answer.get("value")

    def close(self):
        self.p.stdin.close()
        self.p.wait()


def stand_in(release, harness):
    """A module object with the names of that pymeshlab release."""
    class PyMeshLabException(Exception):
        pass

    def unavailable(name):
        def f(*args, **kwargs):
            raise NotImplementedError(f"pymeshlab.{name}: not answered by the harness")
        return f

    def to_python(value):
        if isinstance(value, dict):
            return {k: numpy.array(v) if isinstance(v, list) else v for k, v in value.items()}
        return value

    served = {
        "load_new_mesh": lambda self, path: harness.ask(PyMeshLabException, op="load_new_mesh",
                                                        path=os.path.abspath(path)),
        "number_meshes": lambda self: harness.ask(PyMeshLabException, op="mesh_number"),
        "mesh_number": lambda self: harness.ask(PyMeshLabException, op="mesh_number"),
        "set_current_mesh": lambda self, new_curr_id: harness.ask(PyMeshLabException, op="set_current_mesh",
                                                                  id=new_curr_id),
        "apply_filter": lambda self, filter_name, **kwargs: to_python(harness.ask(
            PyMeshLabException, op="apply_filter", name=filter_name, kwargs=kwargs)),
    }
    meshset = type("MeshSet", (), {m: served.get(m, unavailable("MeshSet." + m)) for m in METHODS[release]})
    module = type(sys)("pymeshlab")
    module.MeshSet = meshset
    module.PyMeshLabException = PyMeshLabException
    for f in MODULE_FUNCTIONS:
        setattr(module, f, unavailable(f))
    module.load_plugin = lambda filename: harness.ask(PyMeshLabException, op="load_plugin", path=filename)
    return module


def main():
    docs, work, canonform = [os.path.abspath(d) for d in sys.argv[1].split(",")], sys.argv[2], sys.argv[3]
    releases, args = {}, sys.argv[4:]
    while args:
        assert args[0] == "--release", args
        releases[args[1]] = (args[2], args[3].rstrip("/") + "/")
        args = args[4:]
    os.makedirs(work, exist_ok=True)
    for release, (harness_path, plugins) in list(releases.items()):
        if plugins.endswith(".tar.gz/"):
            subprocess.run(["tar", "-xzf", plugins.rstrip("/"), "-C", work], check=True)
            releases[release] = (harness_path, os.path.join(
                os.path.abspath(work), os.path.basename(plugins.rstrip("/"))[: -len(".tar.gz")]) + "/")
    os.chdir(work)
    subprocess.run([canonform, "generate", "figure.ply", "--vertices", "2500", "--pose", "4"], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run([canonform, "codebook", "codebook.bin", "figure.ply", "--words", "100"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    blocks = [(code, release, os.path.basename(doc)) for doc in docs
              for code, release in re.findall(r"```python\n(# pymeshlab (\d{4}\.\d+)\n.*?)```", open(doc).read(), re.S)]
    failures, seen = 0, set()
    for code, release, where in blocks:
        if release not in releases:
            print(f"  FAIL a {where} example for pymeshlab {release}, which this build has no harness of")
            failures += 1
            continue
        seen.add(release)
        harness_path, plugins = releases[release]
        code = re.sub(r"'/path/to/canonform/build/pymeshlab\d+/plugins/'", repr(plugins), code)
        if "canonform-plugins-" in code and \
                not re.search(r"canonform-plugins-[^']*-pymeshlab" + re.escape(release) + "-linux-x86_64/", code):
            print(f"  FAIL the {where} pymeshlab {release} example names another release's archive")
            failures += 1
        harness = Harness(harness_path)
        sys.modules["pymeshlab"] = stand_in(release, harness)
        out = io.StringIO()
        try:
            with contextlib.redirect_stdout(out):
                exec(compile(code, f"{where} (pymeshlab {release})", "exec"), {})
            print(f"  ok   the {where} pymeshlab {release} example runs as written; it printed:")
            for line in out.getvalue().splitlines():
                print(f"         {line}")
        except Exception as e:  # the example's own failure, as a user would see it
            print(f"  FAIL the {where} pymeshlab {release} example: {type(e).__name__}: {e}")
            print(out.getvalue())
            failures += 1
        finally:
            harness.close()
            del sys.modules["pymeshlab"]
    # the table of what each filter returns (docs/pymeshlab.md): every filter applied once per
    # release, its dict's keys against the table's row
    table = {}
    for doc in docs:
        for name, cell in re.findall(r"^\| `([a-z_]+)` \| (.*) \|$", open(doc).read(), re.M):
            keys = re.findall(r"`([a-z_]+)`", cell)
            if name.startswith(("compute_", "generate_")) and keys:
                table[name] = set(keys)
    for release, (harness_path, plugins) in sorted(releases.items()):
        if not table:
            print("  FAIL no table of what the filters return")
            failures += 1
            break
        harness = Harness(harness_path)
        try:
            for plugin in ("libfilter_canonical.so", "libfilter_viewdescriptor.so"):
                harness.ask(RuntimeError, op="load_plugin", path=plugins + plugin)
            for name, documented in sorted(table.items()):
                harness.ask(RuntimeError, op="load_new_mesh", path=os.path.abspath("figure.ply"))
                n = harness.ask(RuntimeError, op="mesh_number")
                harness.ask(RuntimeError, op="set_current_mesh", id=n - 1)
                kwargs = {"codebook_file": "codebook.bin", "output_file": ""} if "descriptor" in name else {}
                got = set(harness.ask(RuntimeError, op="apply_filter", name=name, kwargs=kwargs) or {})
                ok = got == documented
                print(f"  {'ok  ' if ok else 'FAIL'} pymeshlab {release}: {name} returns the documented keys"
                      + ("" if ok else f": missing from the table {sorted(got - documented)}, "
                                       f"not returned {sorted(documented - got)}"))
                failures += not ok
        except RuntimeError as e:
            print(f"  FAIL pymeshlab {release}: applying every filter: {e}")
            failures += 1
        finally:
            harness.close()
    for release in sorted(set(releases) - seen):
        print(f"  FAIL no example for pymeshlab {release} in {', '.join(os.path.basename(d) for d in docs)}")
        failures += 1
    print(f"{len(blocks)} examples and {len(table)} filters' outputs checked, {failures} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":  # (tests/wheel_pymeshlab_test.py imports the stand-in)
    main()
