// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: what the filter_viewdescriptor filters do to a MeshLab document, independent of the
// plugin API: the adapters of canonform/meshlab call apply_view_action() with the parameter values.
#pragma once

#include "view_filter_table.h"

class MeshDocument;

namespace canonform::meshlab {

/// Applies filter `id` of view_filter_table() to the current mesh (throws on failure; the
/// document is never changed, files are written atomically).
ActionOutputs apply_view_action(int id, MeshDocument& md, const ParamValues& params,
                                const ActionContext& context);

}  // namespace canonform::meshlab
