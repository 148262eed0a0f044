# SPDX-License-Identifier: GPL-3.0-or-later
"""The installed package: where it is imported from, its stubs, its errors, its registry."""
import ast
import os
import sys

import canonform


def test_imported_from_the_installed_wheel_not_the_source_tree():
    here = os.path.realpath(canonform.__file__)
    source = os.environ.get("CANONFORM_SOURCE_DIR")
    assert source, "CANONFORM_SOURCE_DIR must name the repository"
    # the venv's copy (the venv may sit in a build folder inside the clone), not the source package
    assert here.startswith(os.path.realpath(sys.prefix) + os.sep), (here, sys.prefix)
    assert not here.startswith(os.path.realpath(os.path.join(source, "python")) + os.sep), here
    assert sys.prefix != sys.base_prefix, "the tests run in a venv"
    assert not any(os.path.realpath(p or ".") in (os.path.realpath(source), os.path.realpath(os.path.join(source, "python")))
                   for p in sys.path), sys.path


def test_stubs_declare_every_function_with_its_docstring():
    stub = os.path.join(os.path.dirname(canonform.__file__), "__init__.pyi")
    tree = ast.parse(open(stub, encoding="utf-8").read())
    functions = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    classes = {n.name for n in tree.body if isinstance(n, ast.ClassDef)}
    public = [n for n in canonform.__all__ if callable(getattr(canonform, n))]
    assert len(public) >= 20
    for name in public:
        obj = getattr(canonform, name)
        if isinstance(obj, type):
            assert name in classes, name
            continue
        assert name in functions, f"{name} missing from the stubs"
        assert ast.get_docstring(functions[name]), f"{name}: no docstring in the stubs"
        # the stub's parameters are the runtime signature's (the docstring's first line)
        params = [a.arg for a in functions[name].args.args + functions[name].args.kwonlyargs]
        signature = obj.__doc__.splitlines()[0]
        for p in params:
            assert f"{p}:" in signature, (name, p, signature)
    assert os.path.isfile(os.path.join(os.path.dirname(canonform.__file__), "py.typed"))


def test_errors_are_value_and_runtime_errors():
    assert issubclass(canonform.InputError, ValueError)
    assert issubclass(canonform.NumericalError, RuntimeError)
    assert issubclass(canonform.Cancelled, RuntimeError)


def test_registry_lists_methods_with_parameters():
    methods = canonform.canonical_methods()
    names = [m["name"] for m in methods]
    assert "euclidean-N" in names and "none" in names and len(set(names)) == len(names)
    for m in methods:
        for p in m["parameters"]:
            assert p["name"] and isinstance(p["default"], str)


def test_sift_default_is_a_backend():
    assert canonform.default_sift() in canonform.sift_backends()
    assert canonform.__version__.count(".") == 2


def test_the_library_exports_only_the_c_api():
    """The shared library under the package (the C API, reached through ctypes) exports its C
    functions and nothing else: the static libraries' symbols (Eigen, vcglib, OpenCV glue) stay
    inside, so none can bind to another module's copies in the same process (pymeshlab's), nor
    theirs to ours; and the package has no CPython extension."""
    import glob
    import shutil
    import subprocess

    from canonform import _library

    here = os.path.dirname(canonform.__file__)
    lib = os.path.join(here, "lib", _library.library_name())
    assert os.path.isfile(lib), lib
    assert not glob.glob(os.path.join(here, "*.so")) and not glob.glob(os.path.join(here, "*.pyd"))
    objdump = shutil.which("objdump")
    assert objdump, "objdump (binutils) is needed"
    table = subprocess.run([objdump, "-T", lib], capture_output=True, text=True, check=True).stdout
    defined = [l.split()[-1] for l in table.splitlines()
               if " g " in l and "*UND*" not in l and (" DF " in l or " DO " in l)]
    assert len(defined) >= 30 and all(d.startswith("canonform_") for d in defined), defined
    assert {"canonform_canonical_form", "canonform_version", "canonform_last_error"} <= set(defined)
