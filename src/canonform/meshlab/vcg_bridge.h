// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: conversion between a vcglib triangle mesh and the core's Eigen matrices.
//
// Templated on the vcg mesh type so that the MeshLab plugins (CMeshO, float) and the canonform
// tool (its own double mesh) share it. Deleted vertices and faces are skipped; `vertices` keeps,
// for each row of V, the vcg vertex it came from, so results can be written back in place.
#pragma once

#include "canonform/common/mesh.h"

#include <Eigen/Core>

#include <vector>

namespace canonform::meshlab {

/// The live part of a vcg mesh as a Mesh, and where each row of V came from.
template <class MeshT>
struct BridgedMesh : Mesh {
    std::vector<typename MeshT::VertexPointer> vertices;  ///< row k of V <- vertices[k]
};

/// Copies the live vertices and faces of `m` into V and F (compact 0-based indices).
template <class MeshT>
BridgedMesh<MeshT> to_eigen(MeshT& m) {
    BridgedMesh<MeshT> b;
    std::vector<int> index(m.vert.size(), -1);
    b.vertices.reserve(static_cast<size_t>(m.vn));
    for (size_t k = 0; k < m.vert.size(); ++k) {
        if (m.vert[k].IsD()) continue;
        index[k] = static_cast<int>(b.vertices.size());
        b.vertices.push_back(&m.vert[k]);
    }
    b.V.resize(static_cast<Eigen::Index>(b.vertices.size()), 3);
    for (size_t k = 0; k < b.vertices.size(); ++k)
        for (int c = 0; c < 3; ++c)
            b.V(static_cast<Eigen::Index>(k), c) = static_cast<double>(b.vertices[k]->P()[c]);
    int nf = 0;
    for (const auto& f : m.face) nf += f.IsD() ? 0 : 1;
    b.F.resize(nf, 3);
    int r = 0;
    for (auto& f : m.face) {
        if (f.IsD()) continue;
        for (int c = 0; c < 3; ++c) b.F(r, c) = index[static_cast<size_t>(f.V(c) - &m.vert[0])];
        ++r;
    }
    return b;
}

/// Writes X (#V x 3) into the positions of the bridged vertices.
template <class MeshT>
void write_positions(const BridgedMesh<MeshT>& b, const Eigen::MatrixXd& X) {
    using S = typename MeshT::ScalarType;
    for (size_t k = 0; k < b.vertices.size(); ++k)
        for (int c = 0; c < 3; ++c)
            b.vertices[k]->P()[c] = static_cast<S>(X(static_cast<Eigen::Index>(k), c));
}

/// Writes q (#V) into the quality of the bridged vertices (the mesh must have vertex quality).
template <class MeshT>
void write_quality(const BridgedMesh<MeshT>& b, const Eigen::VectorXd& q) {
    for (size_t k = 0; k < b.vertices.size(); ++k)
        b.vertices[k]->Q() =
            static_cast<typename MeshT::VertexType::QualityType>(q(static_cast<Eigen::Index>(k)));
}

}  // namespace canonform::meshlab
