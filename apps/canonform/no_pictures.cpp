// SPDX-License-Identifier: GPL-3.0-or-later
// canonform tool built without pictures (CANONFORM_TOOL_PICTURES=OFF: no Qt 5, as in the Python
// wheel): the commands that draw - picture, grid, views, pr - say so, and `retrieve` writes its
// report without pictures; everything else is the same.
#include "grid.h"
#include "picture.h"
#include "pr_plot.h"

#include "canonform/common/errors.h"

namespace canonform {

namespace {

[[noreturn]] void no_pictures() {
    throw InputError(
        "this canonform tool draws no pictures (built without Qt 5, as the Python wheel's is): "
        "picture, grid, views and pr need the tool built from source (docs/install.md)");
}

}  // namespace

void check_drawable(const std::string&, const Mesh&, const Eigen::VectorXd&) {
    no_pictures();
}
void check_points(const std::string&, const Eigen::MatrixXd&) {
    no_pictures();
}
void write_picture(const std::string&, const PictureInputs&, int) {
    no_pictures();
}
void write_view_images(const std::string&, const views::ViewSet&) {
    no_pictures();
}

namespace cli {
int write_grid(const std::string&, const GridOptions&) {
    no_pictures();
}
std::vector<PrCurve> read_pr_curves(const std::string&, const std::string&) {
    no_pictures();
}
void write_pr_plot(const std::string&, const std::vector<PrCurve>&, const std::string&) {
    no_pictures();
}
}  // namespace cli

}  // namespace canonform
