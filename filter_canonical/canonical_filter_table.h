// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the filter table of the filter_canonical plugin (plain C++; the types and the
// conventions are in canonform/meshlab/filter_table.h).
#pragma once

#include "canonform/meshlab/filter_table.h"

namespace canonform::meshlab {

enum class FilterId : int {
    ConformalFactor = 0,
    surface::FeaturePoints = 1,
    EuclideanCanonicalForm = 2,
    GeodesicCanonicalForm = 3,
};

/// The table of all filters of filter_canonical, in menu order (built once; the method enums of
/// the two canonical-form filters list the registry's methods of their family).
const std::vector<FilterSpec>& filter_table();
/// The table built anew from the registry as it is now (tests of a method added at run time).
std::vector<FilterSpec> make_filter_table();

}  // namespace canonform::meshlab
