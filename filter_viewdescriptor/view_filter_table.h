// canonform: the filter table of the filter_viewdescriptor plugin (plain C++, see
// filter_canonical/filter_table.h for the types and the conventions).
#pragma once

#include "filter_table.h"

namespace canonform::plugin {

namespace param {
inline constexpr const char* output_file = "output_file";
inline constexpr const char* codebook_file = "codebook_file";
inline constexpr const char* image_size = "image_size";
inline constexpr const char* views_folder = "views_folder";
}  // namespace param

enum class ViewFilterId : int { DepthViewDescriptor = 100 };

/// The filters of filter_viewdescriptor, in menu order.
const std::vector<FilterSpec>& view_filter_table();

}  // namespace canonform::plugin
