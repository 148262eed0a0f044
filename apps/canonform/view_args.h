// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool: the options the view commands share (views, codebook, descriptor) - the view
// descriptor's parameters (--sift, --image-size or --size, --seed: views/view_parameters.h) and
// --repair - and the 66 views of an input mesh with them.
#pragma once

#include "cli.h"

#include "canonform/views/view_descriptor.h"
#include "canonform/views/view_parameters.h"

#include <string>

namespace canonform::cli {

/// Options the view commands share.
struct ViewArgs {
    ParameterArgs view;  // --sift, --image-size (--size), --seed: views/view_parameters.h
    bool repair = false;

    void add(CLI::App* c) {
        add_parameters(c, views::view_descriptor_parameters(), view);
        add_repair_flag(c, repair);
    }
    views::ViewDescriptorOptions options() const {
        return read_parameters(views::view_descriptor_parameters(), view);
    }
    views::ViewSet views_of(const std::string& path, bool images = false) const {
        const Mesh m = read_input_mesh(path, repair, true, false);  // compute_views() validates
        views::ViewDescriptorOptions o = options();
        o.keep_images = images;
        return on_input(path, [&] { return views::compute_views(m.V, m.F, o); });
    }
};

}  // namespace canonform::cli
