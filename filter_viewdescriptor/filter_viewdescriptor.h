// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the filter_viewdescriptor plugin ("Depth view descriptor"): view_filter_table.h and
// view_actions.h behind the shared table-driven adapter of the API being built
// (meshlab_adapter.h: MeshLab 2020.09, or the FilterPlugin API of MeshLab 2022.02 and 2025.07).
#pragma once

#include "canonform/meshlab/meshlab_adapter.h"

class FilterViewDescriptorPlugin : public TableFilterPlugin {
    Q_OBJECT CANONFORM_PLUGIN_INTERFACES public : FilterViewDescriptorPlugin();
};
