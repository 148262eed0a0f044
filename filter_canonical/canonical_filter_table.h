// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the filter table of the filter_canonical plugin (plain C++; the types and the
// conventions are in canonform/meshlab/filter_table.h).
#pragma once

#include "canonform/meshlab/filter_table.h"

namespace canonform::meshlab {

/// The table of all filters of filter_canonical, in menu order (built once; the two canonical-form
/// filters list the registry's methods of their family and those methods' parameters).
const std::vector<FilterSpec>& filter_table();
/// The table built anew from the registry as it is now (tests of a method added at run time).
std::vector<FilterSpec> make_filter_table();

}  // namespace canonform::meshlab
