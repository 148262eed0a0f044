// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the filter_canonical plugin: the filter table of canonical_filter_table.h and the actions of
// filter_actions.h behind the table-driven adapter of the API being built (meshlab_adapter.h):
// MeshLab 2020.09's MeshFilterInterface, or the FilterPlugin API of MeshLab 2022.02 and 2025.07
// (and of pymeshlab 2022.2 and 2025.7).
#pragma once

#include "canonform/meshlab/meshlab_adapter.h"

class FilterCanonicalPlugin : public TableFilterPlugin {
    Q_OBJECT CANONFORM_PLUGIN_INTERFACES public : FilterCanonicalPlugin();
};
