// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: mesh_io.h's PLY reader: ASCII, binary little and big endian (the helpers it shares
// with the other formats: mesh_io_detail.h).
#include "canonform/common/errors.h"
#include "canonform/io/mesh_io_detail.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace canonform::io {
namespace detail {
namespace {

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
        std::uint64_t u = 0;  // the value's bytes, least significant first
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
        // Little-endian data on a little-endian machine: its bytes are already in that order.
        if (format_ == PlyFormat::BinaryLittle) {
            std::memcpy(&u, b_.data() + pos_, static_cast<std::size_t>(n));
            pos_ += static_cast<std::size_t>(n);
        } else
#endif
        {
            unsigned char raw[8];
            for (int k = 0; k < n; ++k)
                raw[k] = static_cast<unsigned char>(
                    b_[pos_ + static_cast<std::size_t>(format_ == PlyFormat::BinaryBig ? n - 1 - k : k)]);
            pos_ += static_cast<std::size_t>(n);
            for (int k = n - 1; k >= 0; --k) u = (u << 8) | raw[k];
        }
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

}  // namespace

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

}  // namespace detail
}  // namespace canonform::io
