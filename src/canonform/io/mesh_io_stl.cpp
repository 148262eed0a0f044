// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: mesh_io.h's STL reader, binary and ASCII (the helpers it shares with the other
// formats: mesh_io_detail.h).
#include "canonform/common/errors.h"
#include "canonform/io/byte_order.h"
#include "canonform/io/mesh_io_detail.h"

#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace canonform::io {
namespace detail {
namespace {

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

}  // namespace

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

}  // namespace detail
}  // namespace canonform::io
