// SPDX-License-Identifier: GPL-3.0-or-later
#include "filter_viewdescriptor.h"

#include "view_actions.h"

FilterViewDescriptorPlugin::FilterViewDescriptorPlugin()
    : TableFilterPlugin("FilterViewDescriptor", canonform::meshlab::view_filter_table(),
                        &canonform::meshlab::apply_view_action) {}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterViewDescriptorPlugin)

// The class's moc output, in this translation unit (cmake/MeshLabPlugin.cmake: PLUGIN_CLASS).
#include "moc_filter_viewdescriptor.cpp"
