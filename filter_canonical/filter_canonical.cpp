// SPDX-License-Identifier: GPL-3.0-or-later
#include "filter_canonical.h"

#include "filter_actions.h"

FilterCanonicalPlugin::FilterCanonicalPlugin()
    : TableFilterPlugin("FilterCanonical", canonform::meshlab::filter_table(),
                        &canonform::meshlab::apply_filter_action) {}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterCanonicalPlugin)

// The class's moc output, in this translation unit (cmake/MeshLabPlugin.cmake: PLUGIN_CLASS).
#include "moc_filter_canonical.cpp"
