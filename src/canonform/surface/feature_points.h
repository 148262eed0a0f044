// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: feature points from the conformal factor.
//
// Reference: Pickup et al., Pattern Recognition 2015, Section 4: "we sample the sqrt(N) vertices
// which have the largest conformal factors and also satisfy the requirement that they are local
// maxima", a local maximum being a vertex whose conformal factor is greater than that of every
// vertex in its k-ring (k = 2 in the paper; 1 and 3 also studied). Variant A of the canonical form
// tops the set up to exactly sqrt(N) points with randomly selected vertices.
//
// Conventions and departures:
// - The target count is ceil(sqrt(N)).
// - "Greater than" is strict: a vertex tied with a neighbour on a plateau is not a maximum.
// - Random fill draws, with a seeded std::mt19937_64 and our own unbiased bounded draw (so the
//   choice is the same on every platform), from the remaining vertices listed in order of
//   increasing conformal factor (ties by index). Listing by conformal factor instead of by vertex
//   index makes the choice independent of the vertex order and of the pose, which the paper's
//   "randomly selected" leaves open and a pose-invariant canonical form needs.
#pragma once

#include "canonform/common/parameters.h"
#include "canonform/surface/mesh_topology.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace canonform::surface {

/// How to reach the target count when there are fewer local maxima than sqrt(N).
enum class FeatureFill {
    None,    ///< keep only the local maxima (variant N)
    Random,  ///< add seeded random vertices up to the target (variant A)
};

/// Options of feature_points().
struct FeaturePointOptions {
    int ring = 2;  ///< k of the k-ring neighbourhood (the paper: 2; 1 and 3 also studied)
    FeatureFill fill = FeatureFill::None;
    std::uint64_t seed = 0;  ///< seed of the random fill
    int count = -1;          ///< target count; -1 means ceil(sqrt(#V)); more than #V is refused
};

/// The parameters of FeaturePointOptions a user sets - ring, fill, seed - with their defaults from
/// `defaults` (common/parameters.h).
ParameterSet<FeaturePointOptions> feature_point_parameters(const FeaturePointOptions& defaults = {});

/// Result of feature_points().
struct FeaturePoints {
    std::vector<int> indices;  ///< selected vertices: maxima by decreasing phi, then random fill
    int num_maxima = 0;        ///< how many of `indices` are local maxima (the first ones)
    int num_random = 0;        ///< how many were added by the random fill
    int total_maxima = 0;      ///< all local maxima found (may exceed the target count)
};

/// Vertices that are strict maxima of `phi` (#V) over their k-ring in the graph `adjacency`.
std::vector<int> local_maxima(const numerics::VertexAdjacency& adjacency, const Eigen::VectorXd& phi,
                              int ring);

/// Feature points of a mesh with vertex adjacency `adjacency` and conformal factor `phi` (#V).
FeaturePoints feature_points(const numerics::VertexAdjacency& adjacency, const Eigen::VectorXd& phi,
                             const FeaturePointOptions& options = {});

/// Convenience overload building the adjacency from the faces F (#F x 3).
FeaturePoints feature_points(const Eigen::MatrixXi& F, const Eigen::VectorXd& phi,
                             const FeaturePointOptions& options = {});

/// ceil(sqrt(n)), computed exactly in integers.
int sqrt_count(int n);

}  // namespace canonform::surface
