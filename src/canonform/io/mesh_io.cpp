// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/io/mesh_io.h"

#include "canonform/common/errors.h"
#include "canonform/io/byte_order.h"

#include <Eigen/Geometry>

#include <charconv>
#include <clocale>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace canonform::io {

namespace {

using u64 = unsigned long long;

[[noreturn]] void fail(const std::string& name, const std::string& what) {
    throw InputError("cannot read '" + name + "': " + what);
}

std::string quoted(std::string_view text) {
    std::string s(text.substr(0, 60));
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    return "'" + s + (text.size() > 60 ? "...'" : "'");
}

/// Refuses a count a header claims that the `available` bytes after it cannot hold at
/// `min_bytes` bytes per item; the check comes before any allocation.
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

/// The lines of a text, without their end-of-line characters, numbered from 1.
class Lines {
public:
    explicit Lines(const std::string& text) : s_(text) {}
    bool next(std::string_view* line) {
        if (pos_ >= s_.size()) return false;
        std::size_t end = s_.find('\n', pos_);
        if (end == std::string::npos) end = s_.size();
        *line = std::string_view(s_).substr(pos_, end - pos_);
        if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
        pos_ = end + 1;
        ++number_;
        return true;
    }
    long number() const { return number_; }
    /// "on line N" of the line last read (`what`: "line", "header line").
    std::string where(const char* what = "line") const {
        return std::string("on ") + what + " " + std::to_string(number_);
    }
    u64 remaining() const { return pos_ >= s_.size() ? 0 : s_.size() - pos_; }

private:
    const std::string& s_;
    std::size_t pos_ = 0;
    long number_ = 0;
};

/// Whitespace-separated tokens of a text.
class Tokens {
public:
    explicit Tokens(std::string_view text) : rest_(text) {}
    bool next(std::string_view* token) {
        std::size_t k = 0;
        while (k < rest_.size() && is_space(rest_[k])) ++k;
        rest_.remove_prefix(k);
        if (rest_.empty()) return false;
        k = 0;
        while (k < rest_.size() && !is_space(rest_[k])) ++k;
        *token = rest_.substr(0, k);
        rest_.remove_prefix(k);
        return true;
    }

private:
    std::string_view rest_;
};

/// Reads lines until one holds a token: the line in *line, its first token in *keyword, the tokens after it
/// in *rest. False at the end of the text.
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

/// The faces of a file as read: every vertex index is checked against the vertex count before any
/// use. An index out of range is an error naming it, or, with ReadOptions::drop_bad_faces, drops
/// its face (counted; the first one's message kept).
class FaceList {
public:
    FaceList(const std::string& name, const ReadOptions& options)
        : name_(name), drop_(options.drop_bad_faces) {}

    /// Starts a polygon.
    void start() {
        poly_.clear();
        given_ = 0;
        bad_ = false;
    }
    /// A vertex index of the polygon (0-based), in [0, vertices) or refused with the message why()
    /// (dropped with it; the message is made only then).
    template <class Why>
    void index(long long zero_based, long long vertices, const Why& why) {
        ++given_;
        if (zero_based < 0 || zero_based >= vertices) {
            if (!drop_) fail(name_, why());
            if (!bad_ && first_dropped_.empty()) first_dropped_ = why();
            bad_ = true;
            return;
        }
        poly_.push_back(static_cast<int>(zero_based));
    }
    /// Vertex indices given so far (a dropped index counts).
    std::size_t size() const { return given_; }
    /// Ends the polygon: its fan triangulation is kept, unless it had an index out of range.
    void finish() {
        if (bad_) {
            ++dropped_;
            return;
        }
        for (std::size_t k = 1; k + 1 < poly_.size(); ++k)
            F_.insert(F_.end(), {poly_[0], poly_[k], poly_[k + 1]});
    }
    void reserve(std::size_t n) { F_.reserve(n); }

    /// The mesh of the vertices `v` (x y z per vertex), these faces and per-vertex `quality`.
    MeshFile assemble(std::vector<double>& v, std::vector<double>* quality = nullptr) {
        MeshFile r;
        const auto nv = static_cast<Eigen::Index>(v.size() / 3),
                   nf = static_cast<Eigen::Index>(F_.size() / 3);
        r.mesh.V = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(v.data(), nv, 3);
        r.mesh.F = Eigen::Map<Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(F_.data(), nf, 3);
        if (quality && !quality->empty()) r.quality = Eigen::Map<Eigen::VectorXd>(quality->data(), nv);
        r.dropped_faces = dropped_;
        r.first_dropped = first_dropped_;
        return r;
    }

private:
    const std::string& name_;
    bool drop_;
    std::vector<int> F_, poly_;
    std::size_t given_ = 0;
    bool bad_ = false;
    long long dropped_ = 0;
    std::string first_dropped_;
};

/// The message for an index out of range of OFF and PLY (0-based indices).
std::string out_of_range(long long index, long long vertices, const std::string& where) {
    return "face index " + std::to_string(index) + " " + where + " is out of range: the file has " +
           std::to_string(vertices) + " vertices (indices 0 to " + std::to_string(vertices - 1) + ")";
}

/// Appends the fan triangulation of a polygon (no index checks: the polygon's are made here).
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

// --- PLY ---------------------------------------------------------------------------------------------

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool ply_type(std::string_view t, PlyType* type) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& [n, ty] : names)
        if (t == n) {
            *type = ty;
            return true;
        }
    return false;
}

int ply_size(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
    }
    return 1;
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool list = false;
    PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
    std::string name;
    u64 count = 0;
    std::vector<PlyProperty> properties;
};

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

/// Reads the values of a PLY body, ASCII or binary, with bounds checks.
class PlyData {
public:
    PlyData(const std::string& bytes, std::size_t start, PlyFormat format, const std::string& name)
        : b_(bytes),
          pos_(start),
          format_(format),
          name_(name),
          tokens_(std::string_view(bytes).substr(start)) {}

    double value(PlyType type, const char* what) {
        if (format_ == PlyFormat::Ascii) {
            std::string_view t;
            if (!tokens_.next(&t)) fail(name_, std::string("truncated: the data ends while reading ") + what);
            double v = 0;
            if (!parse_double(t, &v)) fail(name_, std::string("bad number ") + quoted(t) + " in " + what);
            return v;
        }
        const int n = ply_size(type);
        if (b_.size() - pos_ < static_cast<u64>(n))
            fail(name_, std::string("truncated: the data ends at byte ") + std::to_string(b_.size()) +
                            " while reading " + what);
        unsigned char raw[8];
        for (int k = 0; k < n; ++k)
            raw[k] = static_cast<unsigned char>(
                b_[pos_ + static_cast<std::size_t>(format_ == PlyFormat::BinaryBig ? n - 1 - k : k)]);
        pos_ += static_cast<std::size_t>(n);
        std::uint64_t u = 0;
        for (int k = n - 1; k >= 0; --k) u = (u << 8) | raw[k];
        switch (type) {
            case PlyType::Int8:
                return static_cast<std::int8_t>(u);
            case PlyType::UInt8:
                return static_cast<std::uint8_t>(u);
            case PlyType::Int16:
                return static_cast<std::int16_t>(u);
            case PlyType::UInt16:
                return static_cast<std::uint16_t>(u);
            case PlyType::Int32:
                return static_cast<std::int32_t>(u);
            case PlyType::UInt32:
                return static_cast<std::uint32_t>(u);
            case PlyType::Float32: {
                const auto w = static_cast<std::uint32_t>(u);
                float f;
                std::memcpy(&f, &w, 4);
                return f;
            }
            case PlyType::Float64: {
                double d;
                std::memcpy(&d, &u, 8);
                return d;
            }
        }
        return 0;
    }
    /// A list's entry count, checked against what is left of the file.
    long long list_count(const PlyProperty& p, const char* what) {
        const double c = value(p.count_type, what);
        if (!(c >= 0) || !std::isfinite(c) || c != std::floor(c))
            fail(name_, std::string("bad list length in ") + what);
        const u64 min_each = format_ == PlyFormat::Ascii ? 2 : static_cast<u64>(ply_size(p.type));
        const u64 left = format_ == PlyFormat::Ascii ? b_.size() - pos_ + 1 : b_.size() - pos_;
        if (c > static_cast<double>(left / min_each)) {
            // The count as written, whatever its size (an ASCII count is read as a double: the
            // fuzzer's 2.2e25 has no u64, and converting it was undefined behaviour).
            char claimed[400];
            std::snprintf(claimed, sizeof claimed, "%.0f", c);
            fail(name_,
                 "a list in " + std::string(what) + " claims " + claimed +
                     " entries, more than the rest of the file holds: the file lies (truncated or corrupt)");
        }
        return static_cast<long long>(c);
    }

private:
    const std::string& b_;
    std::size_t pos_;
    PlyFormat format_;
    const std::string& name_;
    Tokens tokens_;
};

MeshFile parse_ply(const std::string& bytes, const std::string& name, const ReadOptions& options) {
    Lines lines(bytes);
    std::string_view line, token;
    if (!lines.next(&line) || line != "ply") {
        if (line.substr(0, 3) == "OFF")
            fail(name, "not a PLY file: it starts like an OFF file (name it .off)");
        fail(name, "not a PLY file (it does not start with 'ply')");
    }
    PlyFormat format = PlyFormat::Ascii;
    bool have_format = false, ended = false;
    std::vector<PlyElement> elements;
    std::size_t header_end = 0;
    Tokens t(line);
    while (next_statement(lines, &line, &t, &token)) {
        const std::string where = " " + lines.where("header line");
        if (token == "end_header") {
            ended = true;
            header_end = bytes.size() - static_cast<std::size_t>(lines.remaining());
            break;
        }
        if (token == "comment" || token == "obj_info") continue;
        if (token == "format") {
            std::string_view f;
            t.next(&f);
            if (f == "ascii")
                format = PlyFormat::Ascii;
            else if (f == "binary_little_endian")
                format = PlyFormat::BinaryLittle;
            else if (f == "binary_big_endian")
                format = PlyFormat::BinaryBig;
            else
                fail(name, "unknown PLY format " + quoted(f) + where);
            have_format = true;
        } else if (token == "element") {
            PlyElement e;
            std::string_view n, c;
            long long count = 0;
            if (!t.next(&n) || !t.next(&c) || !parse_integer(c, &count) || count < 0)
                fail(name, "bad element line" + where + ": " + quoted(line));
            e.name = std::string(n);
            e.count = static_cast<u64>(count);
            elements.push_back(e);
        } else if (token == "property") {
            if (elements.empty()) fail(name, "a property before any element" + where);
            PlyProperty p;
            std::string_view a, b, c;
            if (!t.next(&a)) fail(name, "bad property line" + where);
            if (a == "list") {
                p.list = true;
                if (!t.next(&b) || !t.next(&c) || !ply_type(b, &p.count_type) || !ply_type(c, &p.type) ||
                    !t.next(&a))
                    fail(name, "bad list property" + where + ": " + quoted(line));
                if (p.count_type == PlyType::Float32 || p.count_type == PlyType::Float64)
                    fail(name, "a list length of floating-point type" + where);
                p.name = std::string(a);
            } else {
                if (!ply_type(a, &p.type) || !t.next(&b))
                    fail(name, "bad property line" + where + ": " + quoted(line));
                p.name = std::string(b);
            }
            elements.back().properties.push_back(p);
        } else {
            fail(name, "unknown PLY header line " + quoted(line) + where);
        }
    }
    if (!ended) fail(name, "truncated: the PLY header has no end_header line");
    if (!have_format) fail(name, "the PLY header has no format line");

    // Where the mesh is: vertex x, y, z (and quality), face vertex_indices.
    const PlyElement* vertex = nullptr;
    const PlyElement* face = nullptr;
    for (const auto& e : elements) {
        if (e.name == "vertex" && !vertex) vertex = &e;
        if (e.name == "face" && !face) face = &e;
    }
    if (!vertex) fail(name, "the PLY header has no vertex element");
    auto find = [](const PlyElement& e, std::initializer_list<const char*> names, bool list) -> int {
        for (std::size_t k = 0; k < e.properties.size(); ++k)
            for (const char* n : names)
                if (e.properties[k].name == n && e.properties[k].list == list) return static_cast<int>(k);
        return -1;
    };
    const int px = find(*vertex, {"x"}, false), py = find(*vertex, {"y"}, false),
              pz = find(*vertex, {"z"}, false);
    if (px < 0 || py < 0 || pz < 0) fail(name, "the vertex element has no x, y and z properties");
    const int pq = find(*vertex, {"quality"}, false);
    const int pf = face ? find(*face, {"vertex_indices", "vertex_index"}, true) : -1;
    if (face && face->count > 0 && pf < 0) fail(name, "the face element has no vertex_indices list");

    // Every count against the size of the data before anything is allocated.
    const u64 available = bytes.size() - header_end + (format == PlyFormat::Ascii ? 1 : 0);
    u64 used = 0;
    for (const auto& e : elements) {
        u64 each = 0;
        for (const auto& p : e.properties)
            each +=
                format == PlyFormat::Ascii ? 2 : static_cast<u64>(ply_size(p.list ? p.count_type : p.type));
        if (each == 0) continue;
        check_claim(name, e.count, "'" + e.name + "' elements", each, available - used);
        used += e.count * each;
    }
    check_index_range(name, vertex->count, "vertices");
    const auto nv = static_cast<long long>(vertex->count);

    std::vector<double> V, Q;
    FaceList F(name, options);
    V.reserve(3 * vertex->count);
    if (pq >= 0) Q.reserve(vertex->count);
    PlyData data(bytes, header_end, format, name);
    for (const auto& e : elements) {
        if (e.properties.empty()) continue;
        const bool is_vertex = &e == vertex, is_face = &e == face;
        const std::string what = "'" + e.name + "' elements";
        for (u64 k = 0; k < e.count; ++k) {
            double x[3] = {0, 0, 0};
            for (std::size_t p = 0; p < e.properties.size(); ++p) {
                const PlyProperty& prop = e.properties[p];
                if (!prop.list) {
                    const double v = data.value(prop.type, what.c_str());
                    if (is_vertex) {
                        const int ip = static_cast<int>(p);
                        if (ip == px) x[0] = v;
                        if (ip == py) x[1] = v;
                        if (ip == pz) x[2] = v;
                        if (ip == pq) Q.push_back(v);
                    }
                    continue;
                }
                const long long n = data.list_count(prop, what.c_str());
                const bool indices = is_face && static_cast<int>(p) == pf;
                if (indices && n < 3)
                    fail(name, "face " + std::to_string(k) + " has " + std::to_string(n) +
                                   " vertices (at least 3)");
                if (indices) F.start();
                for (long long c = 0; c < n; ++c) {
                    const double v = data.value(prop.type, what.c_str());
                    if (!indices) continue;
                    if (v != std::floor(v) || !(std::abs(v) < 9e18))
                        fail(name,
                             "face " + std::to_string(k) + " has a vertex index that is not a whole number");
                    F.index(static_cast<long long>(v), nv, [&] {
                        return out_of_range(static_cast<long long>(v), nv, "in face " + std::to_string(k));
                    });
                }
                if (indices) F.finish();
            }
            if (is_vertex) V.insert(V.end(), {x[0], x[1], x[2]});
        }
    }
    return F.assemble(V, pq >= 0 ? &Q : nullptr);
}

// --- STL ---------------------------------------------------------------------------------------------

/// The 4 bytes of b at `at`, least significant first (the caller checks that they exist).
std::uint32_t le32(const std::string& b, std::size_t at) {
    return get_u32(reinterpret_cast<const unsigned char*>(b.data()) + at);
}

/// Merges STL's per-face vertices with equal coordinates (in order of first use).
class VertexMerger {
public:
    int add(const double p[3]) {
        Key k;
        for (int c = 0; c < 3; ++c) {
            const double x = p[c] == 0 ? 0.0 : p[c];  // -0 and +0 are one point
            std::memcpy(&k.bits[c], &x, 8);
        }
        const auto [it, inserted] = index_.emplace(k, static_cast<int>(V.size() / 3));
        if (inserted) V.insert(V.end(), {p[0], p[1], p[2]});
        return it->second;
    }
    std::vector<double> V;

private:
    struct Key {
        std::uint64_t bits[3];
        bool operator==(const Key& o) const {
            return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
        }
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = 1469598103934665603ULL;
            for (auto b : k.bits) h = (h ^ b) * 1099511628211ULL;
            return static_cast<std::size_t>(h ^ (h >> 29));
        }
    };
    std::unordered_map<Key, int, Hash> index_;
};

MeshFile parse_stl_binary(const std::string& bytes, const std::string& name, u64 n) {
    VertexMerger merge;
    std::vector<int> F;
    F.reserve(3 * n);
    for (u64 t = 0; t < n; ++t) {
        const std::size_t at = 84 + 50 * static_cast<std::size_t>(t) + 12;  // after the normal
        for (int c = 0; c < 3; ++c) {
            double p[3];
            for (int d = 0; d < 3; ++d) {
                const std::uint32_t w = le32(bytes, at + static_cast<std::size_t>(12 * c + 4 * d));
                float f;
                std::memcpy(&f, &w, 4);
                p[d] = f;
            }
            F.push_back(merge.add(p));
        }
    }
    (void)name;
    return assemble(merge.V, F);
}

MeshFile parse_stl_ascii(const std::string& bytes, const std::string& name) {
    Lines lines(bytes);
    std::string_view line, token;
    VertexMerger merge;
    std::vector<int> F, poly;
    bool in_loop = false, solid = false;
    Tokens t(line);
    while (next_statement(lines, &line, &t, &token)) {
        const auto where = [&lines] { return " " + lines.where(); };  // (made only for a message)
        if (token == "solid") {
            solid = true;
        } else if (!solid) {
            fail(name, "not an ASCII STL file: the first word is " + quoted(token) + " (expected 'solid')");
        } else if (token == "outer") {
            if (in_loop) fail(name, "'outer loop' inside a loop" + where());
            in_loop = true;
            poly.clear();
        } else if (token == "vertex") {
            if (!in_loop) fail(name, "a vertex outside 'outer loop ... endloop'" + where());
            double p[3];
            for (double& c : p)
                if (!t.next(&token) || !parse_double(token, &c))
                    fail(name, "bad vertex" + where() + ": " + quoted(line));
            poly.push_back(merge.add(p));
            if (merge.V.size() / 3 > static_cast<std::size_t>(std::numeric_limits<int>::max()))
                fail(name, "more vertices than this program handles");
        } else if (token == "endloop") {
            if (!in_loop) fail(name, "'endloop' without 'outer loop'" + where());
            if (poly.size() < 3)
                fail(name,
                     "a facet of " + std::to_string(poly.size()) + " vertices" + where() + " (at least 3)");
            add_polygon(F, poly);
            in_loop = false;
        } else if (token != "facet" && token != "endfacet" && token != "endsolid") {
            fail(name, "unexpected " + quoted(token) + where() +
                           " (an ASCII STL file has solid, facet, outer loop, "
                           "vertex, endloop, endfacet, endsolid)");
        }
    }
    if (!solid) fail(name, "not an STL file (empty)");
    if (in_loop) fail(name, "truncated: the file ends inside a facet");
    return assemble(merge.V, F);
}

MeshFile parse_stl(const std::string& bytes, const std::string& name) {
    if (bytes.size() >= 84) {
        const u64 n = le32(bytes, 80);
        if (84 + 50 * n == bytes.size()) return parse_stl_binary(bytes, name, n);
    }
    std::size_t k = 0;
    while (k < bytes.size() && is_space(bytes[k])) ++k;
    if (bytes.compare(k, 5, "solid") == 0 && (k + 5 == bytes.size() || is_space(bytes[k + 5])))
        return parse_stl_ascii(bytes, name);
    if (bytes.size() < 84)
        fail(name, "not an STL file: " + std::to_string(bytes.size()) +
                       " bytes, too short for a binary STL (84 bytes or more) and no 'solid' keyword");
    const u64 n = le32(bytes, 80);
    std::ostringstream m;
    m << "the binary STL header claims " << n << " triangles (" << 84 + 50 * n << " bytes), but the file has "
      << bytes.size() << " bytes: the header lies (a truncated or corrupt file)";
    fail(name, m.str());
}

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
    if (bytes.empty()) fail(name, "the file is empty");
    switch (format) {
        case MeshFormat::Off:
            return parse_off(bytes, name, options);
        case MeshFormat::Ply:
            return parse_ply(bytes, name, options);
        case MeshFormat::Obj:
            return parse_obj(bytes, name, options);
        case MeshFormat::Stl:
            return parse_stl(bytes, name);  // no indices in STL
    }
    fail(name, "unknown format");
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
