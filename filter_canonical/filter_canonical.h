// canonform: the filter_canonical plugin for MeshLab 2020.09: the filter table of filter_table.h
// and the actions of filter_actions.h behind the table-driven adapter (meshlab2020_adapter.h).
#pragma once

#include "meshlab2020_adapter.h"

class FilterCanonicalPlugin : public TableFilterPlugin2020 {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    FilterCanonicalPlugin();
};
