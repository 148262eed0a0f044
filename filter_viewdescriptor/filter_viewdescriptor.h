// canonform: the filter_viewdescriptor plugin ("Depth view descriptor"): view_filter_table.h and
// view_actions.h behind the shared table-driven adapter of the API being built
// (meshlab_adapter.h: MeshLab 2020.09, or MeshLab 2022.02 for pymeshlab 2022.2).
#pragma once

#include "canonform/meshlab/meshlab_adapter.h"

class FilterViewDescriptorPlugin : public TableFilterPlugin {
    Q_OBJECT
#if defined(CANONFORM_MESHLAB_API) && CANONFORM_MESHLAB_API == 2022
    MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
    Q_INTERFACES(FilterPlugin)
#else
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)
#endif

public:
    FilterViewDescriptorPlugin();
};
