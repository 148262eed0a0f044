// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: what the filters of filter_canonical do to a MeshLab document, independent of the
// plugin API (2020.09's MeshFilterInterface or 2022.02's FilterPlugin). An API adapter reads the
// parameters into ParamValues, calls apply_filter_action(), and turns exceptions into its own
// error reporting. Each action converts the current mesh with vcg_bridge.h, calls the core and
// writes the result back (quality, colour, selection, new layer).
#pragma once

#include "canonform/common/errors.h"
#include "canonical_filter_table.h"

class MeshDocument;

namespace canonform::meshlab {

/// Applies filter `id` to the current mesh of `md`. Throws canonform::InputError,
/// NumericalError or Cancelled with a message meant for the user; on throw the document is
/// unchanged.
ActionOutputs apply_filter_action(int id, MeshDocument& md, const ParamValues& params,
                                  const ActionContext& context);

}  // namespace canonform::meshlab
