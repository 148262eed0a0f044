// canonform: the filter table of the filter_viewdescriptor plugin (plain C++; the types and the
// conventions are in canonform/meshlab/filter_table.h).
#pragma once

#include "canonform/meshlab/filter_table.h"

namespace canonform::plugin {

/// Parameter names of this plugin (lower snake_case, as pymeshlab derives its keywords).
namespace view_param {
inline constexpr const char* output_file = "output_file";
inline constexpr const char* codebook_file = "codebook_file";
inline constexpr const char* image_size = "image_size";
inline constexpr const char* views_folder = "views_folder";
inline constexpr const char* seed = "seed";
}  // namespace view_param

enum class ViewFilterId : int { DepthViewDescriptor = 100 };

/// The filters of filter_viewdescriptor, in menu order.
const std::vector<FilterSpec>& view_filter_table();

}  // namespace canonform::plugin
