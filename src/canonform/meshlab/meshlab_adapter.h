// canonform: the table-driven adapter of the MeshLab API being built, as TableFilterPlugin, and
// CANONFORM_MESHLAB2022 (1 for MeshLab 2022.02's FilterPlugin, 0 for 2020.09's
// MeshFilterInterface). The plugin classes (filter_canonical.h, filter_viewdescriptor.h) are one
// source for both APIs; the build defines CANONFORM_MESHLAB_API (cmake/MeshLabPlugin.cmake: 2020,
// cmake/MeshLab2022.cmake: 2022).
#pragma once

#if defined(CANONFORM_MESHLAB_API) && CANONFORM_MESHLAB_API == 2022
#include "canonform/meshlab/meshlab2022_adapter.h"
using TableFilterPlugin = TableFilterPlugin2022;
/// The plugin interface a plugin class declares (after Q_OBJECT), for the API being built.
#define CANONFORM_PLUGIN_INTERFACES MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID) Q_INTERFACES(FilterPlugin)
#else
#include "canonform/meshlab/meshlab2020_adapter.h"
using TableFilterPlugin = TableFilterPlugin2020;
#define CANONFORM_PLUGIN_INTERFACES \
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID) Q_INTERFACES(MeshFilterInterface)
#endif
