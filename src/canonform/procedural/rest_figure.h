// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the figure's rest mesh at a vertex target (private to procedural/): extracted from the
// body's signed distance by surface nets, projected, coarsened to the exact target with one vertex
// pinned on each limb tip, relaxed and checked (on failure the grid is shifted and the extraction
// retried), with linear-blend skinning weights per vertex.
#pragma once

#include "canonform/procedural/body_model.h"

#include <array>
#include <memory>
#include <vector>

namespace canonform::procedural {
namespace detail {

constexpr int kInfluences = 4;             // bones per vertex
constexpr double kWeightSmoothing = 0.09;  // radius of the ball the sharp weights are averaged over

struct RestFigure {
    std::vector<Vector3d> V;
    std::vector<Face> F;
    std::vector<std::array<int, kInfluences>> bone;  ///< per vertex: bones, largest weight first
    std::vector<std::array<double, kInfluences>> weight;
    std::vector<int> tip_vertex;
};

/// The rest figure of `target` vertices, built once and cached for the last few targets (thread-safe).
std::shared_ptr<const RestFigure> rest_figure(int target);

}  // namespace detail
}  // namespace canonform::procedural
