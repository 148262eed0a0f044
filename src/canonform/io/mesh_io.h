// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: reading and writing mesh files - OFF, PLY (ASCII and binary), OBJ and STL (ASCII and
// binary) in and out, by file extension.
//
// Our own readers, one validation path for the four formats, because the importers of the vcglib
// in MeshLab 2020.09 trust the file: the OFF importer uses an out-of-range face index as a
// pointer (a crash), the PLY and OFF importers allocate whatever count the header claims before
// reading any data (a 959-byte file can ask for gigabytes), the OBJ importer drops every face that
// uses vertex 1. Here every reader
//   - checks the counts a header claims against the size of the file before allocating anything
//     (an InputError saying that the header lies, with both figures);
//   - checks every face index against the vertex count (negative, or >= #V) as it reads it,
//     before any use;
//   - names the file, the line (text) or the offset (binary) and the cause of any other problem.
// Coordinates are read as written (NaN or infinite ones too: validate_mesh() names them).
//
// Writers are atomic (a temporary file in the same folder, renamed over the target when complete,
// so a failure never leaves a half-written output) and write the format the output's extension
// names: .ply (binary, with quality and colours), .off, .obj, .stl (binary; no point clouds); a
// name without extension gets PLY; any other extension is refused. Only the file name's extension
// counts ("/data/v1.2/D" has none).
#pragma once

#include "canonform/common/mesh.h"
#include "canonform/io/files.h"

#include <Eigen/Core>

#include <string>

namespace canonform::io {

/// The mesh formats.
enum class MeshFormat { Ply, Off, Obj, Stl };

/// The format an input mesh file name names by its extension (InputError for an unsupported or
/// missing one).
MeshFormat input_mesh_format(const std::string& path);

/// The format an output mesh file name names: PLY without extension; InputError naming the
/// supported ones for any other extension. Commands call it before any work.
MeshFormat output_mesh_format(const std::string& path);

/// A mesh file's content: the mesh and, where the file has it (PLY "quality"), per-vertex quality.
struct MeshFile {
    Mesh mesh;
    Eigen::VectorXd quality;      ///< #V, or empty
    long long dropped_faces = 0;  ///< faces (polygons) dropped for an index out of range (drop_bad_faces)
    std::string first_dropped;    ///< why the first of them was dropped (the error it would have been)
};

/// How the readers treat a file.
struct ReadOptions {
    /// A face (polygon) that names a vertex the file does not have is dropped, counted and the
    /// first one named in MeshFile, instead of refusing the file. For `canonform check --repair`:
    /// MeshLab's own OFF importer crashes on such a file. Every other problem is still an error.
    bool drop_bad_faces = false;
};

/// Parses the bytes of a mesh file of format `format`; `name` (the file's path) starts every
/// message. Throws InputError naming the cause (see above). STL's per-face vertices are merged
/// where their coordinates are equal; polygons are fan-triangulated.
MeshFile parse_mesh(const std::string& bytes, MeshFormat format, const std::string& name,
                    const ReadOptions& options = {});

/// Reads OFF, PLY, OBJ or STL (by extension). InputError naming the file and the cause (missing,
/// a folder, empty, unsupported format, or anything parse_mesh() refuses).
Mesh read_mesh(const std::string& path);

/// The mesh and the per-vertex quality of a mesh file (empty quality if the file has none).
MeshFile read_mesh_file(const std::string& path, const ReadOptions& options = {});

/// Reads the per-vertex quality of a mesh file (empty if it has none).
Eigen::VectorXd read_ply_quality(const std::string& path);

/// Writes a mesh in the format its extension names (output_mesh_format()). `quality` (#V, or
/// empty) and `colors` (#V x 3 in [0, 255], or empty) go into PLY only. Faces may be empty (a
/// point cloud; not in STL). Atomic. InputError for an unsupported extension, an STL point cloud,
/// or a face index outside [0, #V).
void write_mesh(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                const Eigen::VectorXd& quality = Eigen::VectorXd(),
                const Eigen::MatrixXi& colors = Eigen::MatrixXi());

/// Writes a binary PLY (PLY whatever the name, unless the name's extension is another mesh
/// format: then InputError, never PLY under a .off/.obj/.stl name). Atomic.
void write_ply(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
               const Eigen::VectorXd& quality = Eigen::VectorXd(),
               const Eigen::MatrixXi& colors = Eigen::MatrixXi());

/// The bytes of a mesh file of format `format` (what write_mesh() writes).
std::string format_mesh(MeshFormat format, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                        const Eigen::VectorXd& quality = Eigen::VectorXd(),
                        const Eigen::MatrixXi& colors = Eigen::MatrixXi(), const std::string& name = "mesh");

}  // namespace canonform::io
