#include "canonform/io/mesh_io.h"

#include "canonform/common/errors.h"

#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/clean.h>
#include <wrap/io_trimesh/export_ply.h>
#include <wrap/io_trimesh/import.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <sys/stat.h>

namespace canonform::io {

namespace {

class IoVertex;
class IoFace;
struct IoTypes : public vcg::UsedTypes<vcg::Use<IoVertex>::AsVertexType, vcg::Use<IoFace>::AsFaceType> {};
class IoVertex : public vcg::Vertex<IoTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::vertex::Qualityd,
                                    vcg::vertex::Color4b, vcg::vertex::BitFlags> {};
class IoFace : public vcg::Face<IoTypes, vcg::face::VertexRef, vcg::face::Normal3d, vcg::face::BitFlags> {};
class IoMesh : public vcg::tri::TriMesh<std::vector<IoVertex>, std::vector<IoFace>> {};

/// Wavefront OBJ: 'v x y z' and 'f a b c ...' lines (a, b, c as i, i/t, i//n or i/t/n, 1-based or
/// negative), polygons fan-triangulated; everything else ignored. Our own reader because the
/// OBJ importer of the vcglib in MeshLab 2020.09 drops every face that uses vertex 1.
Mesh read_obj(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read '" + path + "': cannot open the file");
    std::vector<double> v;
    std::vector<int> f;
    std::string line;
    long lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            double x, y, z;
            if (!(ls >> x >> y >> z))
                throw InputError("cannot read '" + path + "': bad vertex on line " + std::to_string(lineno));
            v.insert(v.end(), {x, y, z});
        } else if (tag == "f") {
            std::vector<int> poly;
            std::string tok;
            const long nv = static_cast<long>(v.size() / 3);
            while (ls >> tok) {
                long idx = 0;
                try {
                    idx = std::stol(tok.substr(0, tok.find('/')));
                } catch (const std::exception&) {
                    throw InputError("cannot read '" + path + "': bad face on line " + std::to_string(lineno));
                }
                if (idx < 0) idx += nv + 1;
                if (idx < 1 || idx > nv)
                    throw InputError("cannot read '" + path + "': face index out of range on line " +
                                     std::to_string(lineno));
                poly.push_back(static_cast<int>(idx - 1));
            }
            if (poly.size() < 3)
                throw InputError("cannot read '" + path + "': a face with fewer than 3 vertices on line " +
                                 std::to_string(lineno));
            for (size_t k = 1; k + 1 < poly.size(); ++k) f.insert(f.end(), {poly[0], poly[k], poly[k + 1]});
        }
    }
    if (v.empty()) throw InputError("cannot read '" + path + "': no vertices (is it an OBJ file?)");
    Mesh d;
    d.V = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(v.data(), long(v.size() / 3), 3);
    d.F = Eigen::Map<Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(f.data(), long(f.size() / 3), 3);
    return d;
}

}  // namespace

Mesh read_mesh(const std::string& path) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0) throw InputError("cannot read '" + path + "': no such file");
    if (!S_ISREG(st.st_mode)) throw InputError("cannot read '" + path + "': not a regular file");
    if (access(path.c_str(), R_OK) != 0) throw InputError("cannot read '" + path + "': permission denied");
    if (st.st_size == 0) throw InputError("cannot read '" + path + "': the file is empty");
    const std::string ext = lower_extension(path);
    if (ext != "ply" && ext != "off" && ext != "obj" && ext != "stl")
        throw InputError("cannot read '" + path + "': unsupported format '" + ext + "' (OFF, PLY, OBJ or STL)");
    if (ext == "obj") return read_obj(path);
    IoMesh m;
    int mask = 0;
    const int err = vcg::tri::io::Importer<IoMesh>::Open(m, path.c_str(), mask);
    if (err != 0 && vcg::tri::io::Importer<IoMesh>::ErrorCritical(err))
        throw InputError("cannot read '" + path + "': " + vcg::tri::io::Importer<IoMesh>::ErrorMsg(err));
    if (ext == "stl") {
        vcg::tri::Clean<IoMesh>::RemoveDuplicateVertex(m);
        vcg::tri::Allocator<IoMesh>::CompactEveryVector(m);
    }
    Mesh d;
    std::vector<int> index(m.vert.size(), -1);
    int nv = 0;
    for (size_t k = 0; k < m.vert.size(); ++k)
        if (!m.vert[k].IsD()) index[k] = nv++;
    d.V.resize(nv, 3);
    for (size_t k = 0; k < m.vert.size(); ++k)
        if (index[k] >= 0)
            for (int c = 0; c < 3; ++c) d.V(index[k], c) = m.vert[k].P()[c];
    int nf = 0;
    for (const auto& f : m.face) nf += f.IsD() ? 0 : 1;
    d.F.resize(nf, 3);
    int r = 0;
    for (const auto& f : m.face) {
        if (f.IsD()) continue;
        for (int c = 0; c < 3; ++c) d.F(r, c) = index[static_cast<size_t>(f.cV(c) - &m.vert[0])];
        ++r;
    }
    return d;
}

void write_ply(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
               const Eigen::VectorXd& quality, const Eigen::MatrixXi& colors) {
    IoMesh m;
    auto vi = vcg::tri::Allocator<IoMesh>::AddVertices(m, static_cast<size_t>(V.rows()));
    for (Eigen::Index k = 0; k < V.rows(); ++k, ++vi) {
        vi->P() = vcg::Point3d(V(k, 0), V(k, 1), V(k, 2));
        vi->Q() = quality.size() ? quality(k) : 0.0;
        if (colors.rows())
            vi->C() = vcg::Color4b(static_cast<unsigned char>(colors(k, 0)), static_cast<unsigned char>(colors(k, 1)),
                                   static_cast<unsigned char>(colors(k, 2)), 255);
    }
    auto fi = vcg::tri::Allocator<IoMesh>::AddFaces(m, static_cast<size_t>(F.rows()));
    for (Eigen::Index f = 0; f < F.rows(); ++f, ++fi)
        for (int c = 0; c < 3; ++c) fi->V(c) = &m.vert[static_cast<size_t>(F(f, c))];
    int mask = 0;
    if (quality.size()) mask |= vcg::tri::io::Mask::IOM_VERTQUALITY;
    if (colors.rows()) mask |= vcg::tri::io::Mask::IOM_VERTCOLOR;
    const std::string tmp = temporary_path_for(path);
    const int err = vcg::tri::io::ExporterPLY<IoMesh>::Save(m, tmp.c_str(), mask, true);
    if (err != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path + "': " + vcg::tri::io::ExporterPLY<IoMesh>::ErrorMsg(err));
    }
    commit_file(tmp, path);
}

Eigen::VectorXd read_ply_quality(const std::string& path) {
    IoMesh m;
    int mask = 0;
    const int err = vcg::tri::io::Importer<IoMesh>::Open(m, path.c_str(), mask);
    if (err != 0 && vcg::tri::io::Importer<IoMesh>::ErrorCritical(err))
        throw InputError("cannot read '" + path + "': " + vcg::tri::io::Importer<IoMesh>::ErrorMsg(err));
    if (!(mask & vcg::tri::io::Mask::IOM_VERTQUALITY)) return {};
    Eigen::VectorXd q(m.vn);
    int k = 0;
    for (const auto& v : m.vert)
        if (!v.IsD()) q(k++) = v.cQ();
    return q;
}

}  // namespace canonform::io
