// SPDX-License-Identifier: GPL-3.0-or-later
#include "filter_viewdescriptor.h"

#include "view_actions.h"

FilterViewDescriptorPlugin::FilterViewDescriptorPlugin()
    : TableFilterPlugin("FilterViewDescriptor", canonform::plugin::view_filter_table(),
                        &canonform::plugin::apply_view_action) {}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterViewDescriptorPlugin)
