// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the table-driven adapter of the MeshLab API being built, as TableFilterPlugin, and
// CANONFORM_PLUGIN_INTERFACES, the Qt plugin metadata and interface a plugin class of that API
// declares (after Q_OBJECT). The plugin classes (filter_canonical.h, filter_viewdescriptor.h) are
// one source for every API; the build defines CANONFORM_MESHLAB_API (cmake/MeshLabPlugin.cmake):
// 2020 for MeshLab 2020.09's MeshFilterInterface, 2022 and 2025 for the FilterPlugin API of MeshLab
// 2022.02 and 2025.07 (and of pymeshlab 2022.2 and 2025.7).
#pragma once

#if defined(CANONFORM_MESHLAB_API) && CANONFORM_MESHLAB_API >= 2022
#include "canonform/meshlab/meshlab2022_adapter.h"
using TableFilterPlugin = TableFilterPlugin2022;
#define CANONFORM_PLUGIN_INTERFACES MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID) Q_INTERFACES(FilterPlugin)
#else
#include "canonform/meshlab/meshlab2020_adapter.h"
using TableFilterPlugin = TableFilterPlugin2020;
#define CANONFORM_PLUGIN_INTERFACES \
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID) Q_INTERFACES(MeshFilterInterface)
#endif
