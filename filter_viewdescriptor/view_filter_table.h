// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the filter table of the filter_viewdescriptor plugin (plain C++; the types and the
// conventions are in canonform/meshlab/filter_table.h).
#pragma once

#include "canonform/meshlab/filter_table.h"

namespace canonform::meshlab {

/// The filters of filter_viewdescriptor, in menu order.
const std::vector<FilterSpec>& view_filter_table();

}  // namespace canonform::meshlab
