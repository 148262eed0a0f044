// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/view_parameters.h"

#include <map>

namespace canonform::views {

std::string sift_backend_help(const std::string& name) {
    static const std::map<std::string, std::string> help = {
        {"opencv", "OpenCV's SIFT on the 8-bit view"},
        {"opencv-half", "the same with its first octave at the view's resolution (faster)"},
        {"vlfeat", "VLFeat's SIFT at its defaults on the float depth"},
        {"opencv-fast", "opencv-half's keypoints with descriptors of the full view"},
        {"opencv-octave0", "opencv's keypoints from octave 0 up, found without its doubled image"},
        {"opencv-octave0-fine", "opencv-octave0 plus an approximate octave -1 on the view itself"},
    };
    const auto it = help.find(name);
    return it == help.end() ? std::string() : it->second;
}

ParameterSet<ViewDescriptorOptions> view_descriptor_parameters(const ViewDescriptorOptions& defaults) {
    using O = ViewDescriptorOptions;
    ParameterSet<O> s(defaults);
    s.add(Parameter::integer("image_size", 32, 2048).label("Image size (pixels)").help("side of each depth view, in pixels").alias("size"),
          &O::image_size);
    s.add(Parameter::integer("seed", 0, 2147483647).label("Random seed").help("seed of the rectilinearity restarts of the pose"),
          [](O& o) -> std::uint64_t& { return o.pose.seed; });
    std::string help;
    for (const std::string& name : sift_backend_names())
        help += (help.empty() ? "" : "; ") + name + ": " + sift_backend_help(name);
    s.add(Parameter::choice("sift", sift_backend_names())
              .label("SIFT extractor")
              .help(help + ". A codebook must come from the same extractor"),
          [](O& o) -> SiftBackend& { return o.sift.backend; });
    return s;
}

}  // namespace canonform::views
