// canonform: reading and writing meshes through vcglib (OFF, PLY, OBJ, STL in; PLY out).
//
// Files are written atomically: to a temporary file in the same folder, renamed over the target
// only when complete, so a failure never leaves a half-written output.
#pragma once

#include "canonform/common/mesh.h"
#include "canonform/io/files.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::io {

/// Reads OFF, PLY, OBJ or STL (by extension; OFF, PLY and STL through vcglib, OBJ with our own
/// reader). STL's per-face vertices are merged. Throws
/// canonform::InputError naming the file and the reason if it cannot be read.
Mesh read_mesh(const std::string& path);

/// Writes a PLY (binary) with optional per-vertex quality (#V, or empty) and per-vertex colours
/// (#V x 3 in [0, 255], or empty). Faces may be empty (a point cloud). Atomic.
void write_ply(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
               const Eigen::VectorXd& quality = Eigen::VectorXd(),
               const Eigen::MatrixXi& colors = Eigen::MatrixXi());

/// Reads the per-vertex quality of a PLY file (empty if it has none).
Eigen::VectorXd read_ply_quality(const std::string& path);

}  // namespace canonform::io
