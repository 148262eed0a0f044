// canonform: the filter table of the filter_canonical plugin (plain C++; the types and the
// conventions are in canonform/meshlab/filter_table.h).
#pragma once

#include "canonform/meshlab/filter_table.h"

namespace canonform::plugin {

/// Parameter names: lower snake_case (pymeshlab derives its Python keyword names from them).
namespace param {
inline constexpr const char* normalize = "normalize";
inline constexpr const char* colorize = "colorize";
inline constexpr const char* ring = "ring";
inline constexpr const char* fill = "fill";
inline constexpr const char* seed = "seed";
inline constexpr const char* add_layer = "add_layer";
inline constexpr const char* variant = "variant";
inline constexpr const char* alpha = "alpha";
inline constexpr const char* beta = "beta";
inline constexpr const char* tolerance = "tolerance";
inline constexpr const char* max_iterations = "max_iterations";
inline constexpr const char* new_layer = "new_layer";
inline constexpr const char* method = "method";
inline constexpr const char* max_memory_gib = "max_memory_gib";
inline constexpr const char* max_seconds = "max_seconds";
}  // namespace param

enum class FilterId : int {
    ConformalFactor = 0,
    FeaturePoints = 1,
    EuclideanCanonicalForm = 2,
    GeodesicCanonicalForm = 3,
};

/// The table of all filters of filter_canonical, in menu order (built once; the method enums of
/// the two canonical-form filters list the registry's methods of their family).
const std::vector<FilterSpec>& filter_table();
/// The table built anew from the registry as it is now (tests of a method added at run time).
std::vector<FilterSpec> make_filter_table();

}  // namespace canonform::plugin
