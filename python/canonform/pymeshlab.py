# SPDX-License-Identifier: GPL-3.0-or-later
"""canonform's filters in pymeshlab, in one line:

    import pymeshlab, canonform.pymeshlab
    canonform.pymeshlab.load()          # both plugins of the flavour of the installed pymeshlab
    ms = pymeshlab.MeshSet(); ms.load_new_mesh("cat0.off")
    ms.apply_filter("generate_euclidean_canonical_form")

The wheel carries the two plugins (libfilter_canonical.so, libfilter_viewdescriptor.so) once per
pymeshlab release series whose plugin interface they must match, in canonform/plugins/FLAVOUR/:
pymeshlab2022.2 (pymeshlab 2022.2.x), pymeshlab2023.12 (2023.12.x) and pymeshlab2025.7 (2025.7.x).
MeshLab's plugin manager accepts a plugin only if its version string starts like pymeshlab's own
MeshLab (first six characters: "2022.0", "2023.1", "2025.0") and its precision (double) is the same.
"""
import os
import re

# pymeshlab's release series -> the wheel's plugin folder
FLAVOURS = {"2022.2": "pymeshlab2022.2", "2023.12": "pymeshlab2023.12", "2025.7": "pymeshlab2025.7"}
PLUGINS = ("libfilter_canonical.so", "libfilter_viewdescriptor.so")


def release_of(version):
    """The release series of a pymeshlab version string: "2023.12.post3" -> "2023.12", "2025.7" ->
    "2025.7"; None if it is not of that form."""
    m = re.match(r"^(\d{4})\.0*(\d+)(?:[.+-]|$)", str(version).strip())
    return f"{m.group(1)}.{m.group(2)}" if m else None


def installed_version(module):
    """pymeshlab's version string: pymeshlab.__version__, or that of its extension module
    (pymeshlab.pmeshlab.__version__, which `from .pmeshlab import *` does not re-export); None if
    neither has one."""
    version = getattr(module, "__version__", None)
    if version is None:
        version = getattr(getattr(module, "pmeshlab", None), "__version__", None)
    return version


def plugin_dir(release):
    """The folder of the plugins for a release series (FLAVOURS' keys)."""
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "plugins", FLAVOURS[release])


def supported():
    """The pymeshlab release series this install has plugins for."""
    return [r for r in FLAVOURS if all(os.path.isfile(os.path.join(plugin_dir(r), p)) for p in PLUGINS)]


def load(module=None):
    """Loads canonform's two plugins of the flavour that matches the installed pymeshlab
    (installed_version()) into it, with pymeshlab.load_plugin; returns the paths it loaded.

    module: the pymeshlab module (default: import pymeshlab). Raises RuntimeError naming the
    installed version and the supported ones for a pymeshlab release with no flavour (or an
    install without plugins), and pymeshlab's own exception if it refuses a plugin."""
    if module is None:
        import pymeshlab as module
    version = installed_version(module)
    release = release_of(version) if version is not None else None
    have = supported()
    if release not in FLAVOURS or release not in have:
        series = ", ".join(f"{r}.x" for r in have) or "none: this install of canonform has no plugins"
        raise RuntimeError(f"canonform.pymeshlab.load(): pymeshlab {version} is installed; canonform's plugins are "
                           f"built for pymeshlab {series} (pip install 'pymeshlab=={have[-1] if have else '2025.7'}.*')")
    paths = [os.path.join(plugin_dir(release), p) for p in PLUGINS]
    for p in paths:
        module.load_plugin(p)
    return paths
