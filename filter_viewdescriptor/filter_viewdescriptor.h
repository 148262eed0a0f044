// canonform: the filter_viewdescriptor plugin for MeshLab 2020.09 ("Depth view descriptor"):
// view_filter_table.h and view_actions.h behind the shared table-driven adapter.
#pragma once

#include "meshlab2020_adapter.h"

class FilterViewDescriptorPlugin : public TableFilterPlugin2020 {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    FilterViewDescriptorPlugin();
};
