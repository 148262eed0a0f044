#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""canonform.pymeshlab.load() from the wheel, with the harness's stand-in for each pymeshlab release.

usage: wheel_pymeshlab_test.py WHEEL WORKDIR --release 2022.2|2023.12|2025.7 HARNESS [...]

The wheel is unpacked as pip would (its files under WORKDIR/site) and imported from there. For each
release, `pymeshlab` is the stand-in of tests/readme_pymeshlab_test.py: that release's module and
MeshSet names, load_plugin and apply_filter answered by the pymeshlab harness of that release
(tests/pymeshlab_harness.cpp --serve: MeshLab's own meshlab-common in double precision, whose
plugin manager checks a plugin's version and precision as pymeshlab's does), with a
__version__ as that release's wheels report it. load() must load both plugins of the matching
flavour (and the harness must accept them and run a filter of each); the flavour of another
release must be refused by the harness (so the choice matters); a pymeshlab release with no
flavour, or no __version__, must be a RuntimeError naming the version and the supported ones.
"""
import os
import stat
import sys
import zipfile

sys.dont_write_bytecode = True  # no __pycache__ written into the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_report import Report  # noqa: E402
from readme_pymeshlab_test import Harness, stand_in  # noqa: E402

VERSIONS = {"2022.2": "2022.2.post4", "2023.12": "2023.12.post3", "2025.7": "2025.7.post1"}


def main(argv):
    wheel, work = argv[0], os.path.abspath(argv[1])
    releases, args = {}, argv[2:]
    while args:
        assert args[0] == "--release", args
        releases[args[1]] = args[2]
        args = args[3:]
    report = Report()
    site = os.path.join(work, "site")
    os.makedirs(site, exist_ok=True)
    with zipfile.ZipFile(wheel) as z:
        for info in z.infolist():
            path = z.extract(info, site)
            mode = info.external_attr >> 16
            if mode & stat.S_IXUSR:
                os.chmod(path, 0o755)
    sys.path.insert(0, site)
    import canonform
    import canonform.pymeshlab as cp

    report.check(os.path.dirname(canonform.__file__) == os.path.join(site, "canonform"), "canonform imported from the wheel")
    os.chdir(work)
    canonform.write_mesh("figure.ply", *canonform.figure(2000, pose=4))
    V, F = canonform.read_mesh("figure.ply")
    canonform.save_codebook("codebook.bin", canonform.train_codebook(canonform.view_descriptor(V, F), words=50,
                                                                      method="lloyd"))
    for release, harness_path in releases.items():
        harness = Harness(harness_path)
        module = stand_in(release, harness)
        module.__version__ = VERSIONS[release]
        sys.modules["pymeshlab"] = module
        try:
            loaded = cp.load()
            report.check([os.path.relpath(p, site) for p in loaded] ==
                         [f"canonform/plugins/{cp.FLAVOURS[release]}/{p}" for p in cp.PLUGINS],
                         f"pymeshlab {VERSIONS[release]}: load() loads both plugins of {cp.FLAVOURS[release]}")
            ms = module.MeshSet()
            ms.load_new_mesh("figure.ply")
            out = ms.apply_filter("generate_euclidean_canonical_form", variant="N", new_layer=True)
            d = ms.apply_filter("compute_depth_view_descriptor", output_file="", codebook_file="codebook.bin")
            report.check(isinstance(out, dict) and isinstance(d, dict) and ms.number_meshes() == 2,
                         f"pymeshlab {release}: both plugins' filters run (a canonical form, a descriptor)")
        except Exception as e:  # noqa: BLE001
            report.check(False, f"pymeshlab {release}: load() and the filters", f"{type(e).__name__}: {e}")
        finally:
            harness.close()
        # another release's flavour: refused by this release's plugin manager
        other = next(r for r in cp.FLAVOURS if r != release)
        harness = Harness(harness_path)
        module = stand_in(release, harness)
        try:
            module.load_plugin(os.path.join(cp.plugin_dir(other), cp.PLUGINS[0]))
            report.check(False, f"pymeshlab {release} refuses the {other} flavour")
        except module.PyMeshLabException as e:
            report.check("version" in str(e), f"pymeshlab {release} refuses the {other} flavour", str(e))
        finally:
            harness.close()

    for version in ("2024.1", "2021.10", None):
        module = type(sys)("pymeshlab")
        module.load_plugin = lambda path: None
        if version is not None:
            module.__version__ = version
        try:
            cp.load(module)
            report.check(False, f"pymeshlab {version}: refused")
        except RuntimeError as e:
            report.check(str(version) in str(e) and "2022.2.x, 2023.12.x, 2025.7.x" in str(e),
                         f"pymeshlab {version}: RuntimeError naming it and the supported releases", str(e))
    report.check([cp.release_of(v) for v in ("2022.2.post2", "2023.12", "2025.07.post1", "2025.7", "x")] ==
                 ["2022.2", "2023.12", "2025.7", "2025.7", None], "release_of() reads pymeshlab's version strings")
    return report.exit_code()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
