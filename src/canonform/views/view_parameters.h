// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the parameters of the view descriptor a user sets (common/parameters.h), defined
// once for the view filter (image_size, seed, sift), the tool's view commands (--image-size or
// --size, --seed, --sift) and `retrieve --sift`.
#pragma once

#include "canonform/common/parameters.h"
#include "canonform/views/view_descriptor.h"

namespace canonform::views {

/// image_size, seed (of the pose's rectilinearity restarts) and sift, with their defaults from
/// `defaults`. sift's choices are `sift_choices`: a leading part of sift_backend_names() (the
/// enumerators' order), e.g. builtin_sift_backend_names() for the view filter, which carries only
/// the extractors built into this library.
ParameterSet<ViewDescriptorOptions> view_descriptor_parameters(
    const ViewDescriptorOptions& defaults = {},
    const std::vector<std::string>& sift_choices = sift_backend_names());

/// One line on each SIFT extractor of sift_backend_names() ("" for one without a description:
/// tests/test_filter_table.cpp asks for one).
std::string sift_backend_help(const std::string& name);

}  // namespace canonform::views
