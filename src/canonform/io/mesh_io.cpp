// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/io/mesh_io.h"

#include "canonform/common/errors.h"
#include "canonform/io/byte_order.h"
#include "canonform/io/mesh_io_detail.h"

#include <Eigen/Geometry>

#include <charconv>
#include <clocale>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string_view>
#include <vector>

namespace canonform::io {
namespace detail {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
    throw InputError("cannot read '" + name + "': " + what);
}

std::string quoted(std::string_view text) {
    std::string s(text.substr(0, 60));
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    return "'" + s + (text.size() > 60 ? "...'" : "'");
}

void check_claim(const std::string& name, u64 count, const std::string& what, u64 min_bytes, u64 available) {
    if (min_bytes > 0 && count > available / min_bytes) {
        std::ostringstream m;
        m << "the header claims " << count << " " << what << ", but the " << available
          << " bytes of data in the file can hold at most " << available / min_bytes
          << ": the header lies (a truncated or corrupt file)";
        fail(name, m.str());
    }
}

void check_index_range(const std::string& name, u64 count, const char* what) {
    if (count > static_cast<u64>(std::numeric_limits<int>::max()))
        fail(name, "the header claims " + std::to_string(count) + " " + what +
                       ", more than this program handles (" +
                       std::to_string(std::numeric_limits<int>::max()) + ")");
}

// --- text -------------------------------------------------------------------------------------------

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

bool next_statement(Lines& lines, std::string_view* line, Tokens* rest, std::string_view* keyword) {
    while (lines.next(line)) {
        *rest = Tokens(*line);
        if (rest->next(keyword)) return true;
    }
    return false;
}

bool parse_double(std::string_view t, double* v) {
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    if (t.empty()) return false;
#ifndef __cpp_lib_to_chars
    // libstdc++ before GCC 11 (Debian bullseye's GCC 10: the portable plugins' build) has no
    // floating-point from_chars. strtod_l in the "C" locale reads the same decimal and inf/nan forms
    // to the same correctly rounded double, whatever locale the host process set; hexadecimal
    // floats, which from_chars' general format refuses, are refused here too.
    static const locale_t c_locale = newlocale(LC_ALL_MASK, "C", locale_t(0));
    if (t.find_first_of("xX") != std::string_view::npos) return false;
    const std::string s(t);
    char* end = nullptr;
    *v = strtod_l(s.c_str(), &end, c_locale);
    return end == s.c_str() + s.size();
#else
    const auto r = std::from_chars(t.data(), t.data() + t.size(), *v);
    if (r.ptr != t.data() + t.size()) return false;
    if (r.ec == std::errc::result_out_of_range) {  // overflow or underflow: what strtod makes of it
        const std::string s(t);
        *v = std::strtod(s.c_str(), nullptr);
        return true;
    }
    return r.ec == std::errc();
#endif
}

bool parse_integer(std::string_view t, long long* v) {
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    if (t.empty()) return false;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), *v);
    return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

std::string out_of_range(long long index, long long vertices, const std::string& where) {
    return "face index " + std::to_string(index) + " " + where + " is out of range: the file has " +
           std::to_string(vertices) + " vertices (indices 0 to " + std::to_string(vertices - 1) + ")";
}

void add_polygon(std::vector<int>& F, const std::vector<int>& poly) {
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) F.insert(F.end(), {poly[0], poly[k], poly[k + 1]});
}

MeshFile assemble(std::vector<double>& v, std::vector<int>& f) {
    MeshFile r;
    const auto nv = static_cast<Eigen::Index>(v.size() / 3), nf = static_cast<Eigen::Index>(f.size() / 3);
    r.mesh.V = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(v.data(), nv, 3);
    r.mesh.F = Eigen::Map<Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(f.data(), nf, 3);
    return r;
}

// --- OFF ---------------------------------------------------------------------------------------------

namespace {

/// The next line with content (comments '#...' and blank lines skipped), trimmed.
bool content_line(Lines& lines, std::string_view* line) {
    while (lines.next(line)) {
        const std::size_t hash = line->find('#');
        if (hash != std::string_view::npos) *line = line->substr(0, hash);
        while (!line->empty() && is_space(line->front())) line->remove_prefix(1);
        while (!line->empty() && is_space(line->back())) line->remove_suffix(1);
        if (!line->empty()) return true;
    }
    return false;
}

}  // namespace

MeshFile parse_off(const std::string& bytes, const std::string& name, const ReadOptions& options) {
    Lines lines(bytes);
    std::string_view line, token;
    if (!content_line(lines, &line)) fail(name, "no OFF header (only blank lines or comments)");
    Tokens header(line);
    header.next(&token);
    const bool keyword = token.size() >= 3 && token.substr(token.size() - 3) == "OFF";
    if (!keyword) {
        if (token == "ply") fail(name, "not an OFF file: it starts like a PLY file (name it .ply)");
        fail(name, "not an OFF file: the first line is " + quoted(line) + " (an OFF file starts with 'OFF')");
    }
    const std::string_view prefix = token.substr(0, token.size() - 3);
    if (prefix.find_first_of("4n") != std::string_view::npos)
        fail(name, "a " + std::string(token) +
                       " file (4D or n-dimensional vertices) is not supported: 3D OFF only");
    if (prefix.find_first_not_of("STCN") != std::string_view::npos)
        fail(name, "not an OFF file: unknown header keyword " + quoted(token));
    std::vector<std::string_view> counts;
    while (header.next(&token)) counts.push_back(token);
    if (!counts.empty() && counts[0] == "BINARY") fail(name, "binary OFF is not supported (ASCII OFF only)");
    if (counts.empty()) {
        if (!content_line(lines, &line))
            fail(name, "truncated: no vertex and face counts after the OFF keyword");
        Tokens t(line);
        while (t.next(&token)) counts.push_back(token);
    }
    long long nv = 0, nf = 0;
    if (counts.size() < 2 || !parse_integer(counts[0], &nv) || !parse_integer(counts[1], &nf) || nv < 0 ||
        nf < 0)
        fail(name, "bad counts line " + std::to_string(lines.number()) + ": " + quoted(line) +
                       " (expected: vertices faces edges)");
    // At least "0 0 0\n" per vertex and "3 0 1 2\n" per face.
    const u64 available = lines.remaining() + 1;
    check_claim(name, static_cast<u64>(nv), "vertices", 6, available);
    check_claim(name, static_cast<u64>(nf), "faces", 8, available - 6 * static_cast<u64>(nv));
    check_index_range(name, static_cast<u64>(nv), "vertices");

    std::vector<double> V;
    V.reserve(3 * static_cast<std::size_t>(nv));
    for (long long k = 0; k < nv; ++k) {
        if (!content_line(lines, &line))
            fail(name, "truncated: the header claims " + std::to_string(nv) +
                           " vertices, the file ends after " + std::to_string(k));
        Tokens t(line);
        double x[3];
        for (double& c : x)
            if (!t.next(&token) || !parse_double(token, &c))
                fail(name, "bad vertex on line " + std::to_string(lines.number()) + ": " + quoted(line));
        V.insert(V.end(), {x[0], x[1], x[2]});
    }
    FaceList F(name, options);
    F.reserve(3 * static_cast<std::size_t>(nf));
    for (long long k = 0; k < nf; ++k) {
        if (!content_line(lines, &line))
            fail(name, "truncated: the header claims " + std::to_string(nf) + " faces, the file ends after " +
                           std::to_string(k));
        const auto where = [&lines] { return lines.where(); };  // (made only for a message)
        Tokens t(line);
        long long n = 0;
        if (!t.next(&token) || !parse_integer(token, &n))
            fail(name, "bad face " + where() + ": " + quoted(line));
        if (n < 3) fail(name, "a face of " + std::to_string(n) + " vertices " + where() + " (at least 3)");
        F.start();
        for (long long c = 0; c < n; ++c) {
            long long index = 0;
            if (!t.next(&token))
                fail(name, "the face " + where() + " lists fewer than its " + std::to_string(n) +
                               " vertex indices");
            if (!parse_integer(token, &index))
                fail(name, "bad face index " + quoted(token) + " " + where() + " (a whole number is needed)");
            F.index(index, nv, [&] { return out_of_range(index, nv, where()); });
        }
        F.finish();
    }
    return F.assemble(V);
}

// --- OBJ ---------------------------------------------------------------------------------------------

/// Wavefront OBJ: 'v x y z' and 'f a b c ...' lines (a, b, c as i, i/t, i//n or i/t/n, 1-based or
/// negative = relative to the last vertex), polygons fan-triangulated; everything else ignored.
MeshFile parse_obj(const std::string& bytes, const std::string& name, const ReadOptions& options) {
    Lines lines(bytes);
    std::vector<double> V;
    FaceList F(name, options);
    std::string_view line, token;
    Tokens t(line);
    while (next_statement(lines, &line, &t, &token)) {
        const auto where = [&lines] { return lines.where(); };  // (made only for a message)
        if (token == "v") {
            double x[3];
            for (double& c : x)
                if (!t.next(&token) || !parse_double(token, &c))
                    fail(name, "bad vertex " + where() + ": " + quoted(line));
            V.insert(V.end(), {x[0], x[1], x[2]});
        } else if (token == "f") {
            F.start();
            const auto nv = static_cast<long long>(V.size() / 3);
            while (t.next(&token)) {
                long long index = 0;
                if (!parse_integer(token.substr(0, token.find('/')), &index))
                    fail(name, "bad face index " + quoted(token) + " " + where());
                if (index == 0) fail(name, "face index 0 " + where() + ": OBJ indices start at 1");
                F.index(index < 0 ? nv + index : index - 1, nv, [&] {
                    return "face index " + std::to_string(index) + " " + where() +
                           " is out of range: " + std::to_string(nv) + " vertices are defined before it";
                });
            }
            if (F.size() < 3)
                fail(name,
                     "a face of " + std::to_string(F.size()) + " vertices " + where() + " (at least 3)");
            F.finish();
        }
        if (V.size() / 3 > static_cast<std::size_t>(std::numeric_limits<int>::max()))
            fail(name, "more vertices than this program handles");
    }
    if (V.empty()) fail(name, "no vertices ('v' lines): is it an OBJ file?");
    return F.assemble(V);
}

}  // namespace detail

namespace {

// --- writers -----------------------------------------------------------------------------------------

void put(std::string& out, const void* p, std::size_t n) {
    out.append(static_cast<const char*>(p), n);
}

std::string number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

const char* format_name(MeshFormat f) {
    switch (f) {
        case MeshFormat::Ply:
            return "PLY";
        case MeshFormat::Off:
            return "OFF";
        case MeshFormat::Obj:
            return "OBJ";
        case MeshFormat::Stl:
            return "STL";
    }
    return "?";
}

bool mesh_extension(const std::string& ext, MeshFormat* f) {
    if (ext == "ply")
        *f = MeshFormat::Ply;
    else if (ext == "off")
        *f = MeshFormat::Off;
    else if (ext == "obj")
        *f = MeshFormat::Obj;
    else if (ext == "stl")
        *f = MeshFormat::Stl;
    else
        return false;
    return true;
}

}  // namespace

MeshFormat input_mesh_format(const std::string& path) {
    MeshFormat f;
    const std::string ext = lower_extension(path);
    if (!mesh_extension(ext, &f))
        throw InputError(
            "cannot read '" + path +
            "': " + (ext.empty() ? std::string("no file extension") : "unsupported format '." + ext + "'") +
            " (a mesh file is .off, .ply, .obj or .stl)");
    return f;
}

MeshFormat output_mesh_format(const std::string& path) {
    MeshFormat f = MeshFormat::Ply;
    const std::string ext = lower_extension(path);
    if (!ext.empty() && !mesh_extension(ext, &f))
        throw InputError("cannot write '" + path + "': unsupported mesh format '." + ext +
                         "' (name the output .ply, .off, .obj or .stl; without an extension it is PLY)");
    return f;
}

MeshFile parse_mesh(const std::string& bytes, MeshFormat format, const std::string& name,
                    const ReadOptions& options) {
    if (bytes.empty()) detail::fail(name, "the file is empty");
    switch (format) {
        case MeshFormat::Off:
            return detail::parse_off(bytes, name, options);
        case MeshFormat::Ply:
            return detail::parse_ply(bytes, name, options);
        case MeshFormat::Obj:
            return detail::parse_obj(bytes, name, options);
        case MeshFormat::Stl:
            return detail::parse_stl(bytes, name);  // no indices in STL
    }
    detail::fail(name, "unknown format");
}

MeshFile read_mesh_file(const std::string& path, const ReadOptions& options) {
    const std::string bytes = read_file(path);
    return parse_mesh(bytes, input_mesh_format(path), path, options);
}

Mesh read_mesh(const std::string& path) {
    return read_mesh_file(path).mesh;
}

Eigen::VectorXd read_ply_quality(const std::string& path) {
    return read_mesh_file(path).quality;
}

std::string format_mesh(MeshFormat format, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                        const Eigen::VectorXd& quality, const Eigen::MatrixXi& colors,
                        const std::string& name) {
    auto refuse = [&](const std::string& why) { throw InputError("cannot write '" + name + "': " + why); };
    if (V.cols() != 3 || (F.size() && F.cols() != 3)) refuse("a mesh needs #V x 3 vertices and #F x 3 faces");
    if (F.size() && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())) refuse("a face index is out of range");
    if (quality.size() && quality.size() != V.rows()) refuse("the quality must have one value per vertex");
    if (colors.size() && (colors.rows() != V.rows() || colors.cols() != 3)) refuse("colours must be #V x 3");
    const Eigen::Index nf = F.size() ? F.rows() : 0;
    std::string out;
    switch (format) {
        case MeshFormat::Ply: {
            std::ostringstream h;
            h << "ply\nformat binary_little_endian 1.0\ncomment canonform\nelement vertex " << V.rows()
              << "\nproperty double x\nproperty double y\nproperty double z\n";
            if (quality.size()) h << "property double quality\n";
            if (colors.size())
                h << "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
            h << "element face " << nf << "\nproperty list uchar int vertex_indices\nend_header\n";
            out = h.str();
            out.reserve(out.size() + static_cast<std::size_t>(V.rows()) * 36 +
                        static_cast<std::size_t>(nf) * 13);
            for (Eigen::Index k = 0; k < V.rows(); ++k) {
                for (int c = 0; c < 3; ++c) put_le(out, V(k, c));
                if (quality.size()) put_le(out, quality(k));
                if (colors.size()) {
                    for (int c = 0; c < 3; ++c)
                        put_le(out, static_cast<std::uint8_t>(std::min(255, std::max(0, colors(k, c)))));
                    put_le(out, std::uint8_t(255));
                }
            }
            for (Eigen::Index f = 0; f < nf; ++f) {
                put_le(out, std::uint8_t(3));
                for (int c = 0; c < 3; ++c) put_le(out, static_cast<std::int32_t>(F(f, c)));
            }
            break;
        }
        case MeshFormat::Off: {
            out = "OFF\n" + std::to_string(V.rows()) + " " + std::to_string(nf) + " 0\n";
            for (Eigen::Index k = 0; k < V.rows(); ++k)
                out += number(V(k, 0)) + " " + number(V(k, 1)) + " " + number(V(k, 2)) + "\n";
            for (Eigen::Index f = 0; f < nf; ++f)
                out += "3 " + std::to_string(F(f, 0)) + " " + std::to_string(F(f, 1)) + " " +
                       std::to_string(F(f, 2)) + "\n";
            break;
        }
        case MeshFormat::Obj: {
            out = "# canonform\n";
            for (Eigen::Index k = 0; k < V.rows(); ++k)
                out += "v " + number(V(k, 0)) + " " + number(V(k, 1)) + " " + number(V(k, 2)) + "\n";
            for (Eigen::Index f = 0; f < nf; ++f)
                out += "f " + std::to_string(F(f, 0) + 1) + " " + std::to_string(F(f, 1) + 1) + " " +
                       std::to_string(F(f, 2) + 1) + "\n";
            break;
        }
        case MeshFormat::Stl: {
            if (nf == 0)
                refuse("an STL file cannot hold a point cloud (no faces): name it .ply, .off or .obj");
            char header[80] = "canonform binary STL";
            put(out, header, 80);
            put_le(out, static_cast<std::uint32_t>(nf));
            for (Eigen::Index f = 0; f < nf; ++f) {
                const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
                Eigen::Vector3d n = (b - a).cross(c - a);
                if (n.norm() > 0) n.normalize();
                for (int d = 0; d < 3; ++d) put_le(out, static_cast<float>(n(d)));
                for (const Eigen::Vector3d* p : {&a, &b, &c})
                    for (int d = 0; d < 3; ++d) put_le(out, static_cast<float>((*p)(d)));
                put_le(out, std::uint16_t(0));
            }
            break;
        }
    }
    return out;
}

void write_mesh(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                const Eigen::VectorXd& quality, const Eigen::MatrixXi& colors) {
    write_file_atomic(path, format_mesh(output_mesh_format(path), V, F, quality, colors, path));
}

void write_ply(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
               const Eigen::VectorXd& quality, const Eigen::MatrixXi& colors) {
    MeshFormat f;
    if (mesh_extension(lower_extension(path), &f) && f != MeshFormat::Ply)
        throw InputError("cannot write '" + path + "': a PLY file under a ." + lower_extension(path) +
                         " name; write it as " + format_name(f) + " (write_mesh) or name it .ply");
    write_file_atomic(path, format_mesh(MeshFormat::Ply, V, F, quality, colors, path));
}
}  // namespace canonform::io
