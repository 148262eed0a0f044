// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/view_parameters.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace canonform::views {

std::string sift_backend_help(const std::string& name) {
    static const std::map<std::string, std::string> help = {
        {"canonform",
         "the project's own SIFT (Lowe 2004) at the view's resolution with an approximate finer octave"},
        {"opencv", "OpenCV's cv::SIFT on the 8-bit view (the canonform tool and Python module only)"},
    };
    const auto it = help.find(name);
    return it == help.end() ? std::string() : it->second;
}

ParameterSet<ViewDescriptorOptions> view_descriptor_parameters(const ViewDescriptorOptions& defaults,
                                                               const std::vector<std::string>& sift_choices) {
    const std::vector<std::string>& all = sift_backend_names();
    if (sift_choices.empty() || sift_choices.size() > all.size() ||
        !std::equal(sift_choices.begin(), sift_choices.end(), all.begin()))
        throw std::logic_error(
            "view_descriptor_parameters: the SIFT choices must be a leading part of sift_backend_names()");
    using O = ViewDescriptorOptions;
    ParameterSet<O> s(defaults);
    s.add(Parameter::integer("image_size", 32, 2048)
              .label("Image size (pixels)")
              .help("side of each depth view, in pixels")
              .alias("size"),
          &O::image_size);
    s.add(Parameter::integer("seed", 0, 2147483647)
              .label("Random seed")
              .help("seed of the rectilinearity restarts of the pose"),
          [](O& o) -> std::uint64_t& { return o.pose.seed; });
    std::string help;
    for (const std::string& name : sift_choices)
        help += (help.empty() ? "" : "; ") + name + ": " + sift_backend_help(name);
    for (std::size_t k = sift_choices.size(); k < all.size(); ++k)  // the others, which need another library
        help += (k == sift_choices.size() ? " (the canonform tool also offers " : ", ") + all[k] +
                (k + 1 == all.size() ? ")" : "");
    s.add(Parameter::choice("sift", sift_choices)
              .label("SIFT extractor")
              .help(help + ". A codebook must come from the same extractor"),
          [](O& o) -> SiftBackend& { return o.sift.backend; });
    return s;
}

}  // namespace canonform::views
