// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: what mesh_io.h's format readers share - the error of an unreadable file, the checks of a
// header's claims, a text's lines and tokens, number parsing, the faces as read - and the readers
// themselves, one per format (OFF and OBJ in mesh_io.cpp, PLY in mesh_io_ply.cpp, STL in
// mesh_io_stl.cpp). Internal: not an interface of the library.
#pragma once

#include "canonform/io/mesh_io.h"

#include <Eigen/Core>

#include <string>
#include <string_view>
#include <vector>

namespace canonform::io {
namespace detail {

using u64 = unsigned long long;

/// Throws InputError "cannot read 'name': what".
[[noreturn]] void fail(const std::string& name, const std::string& what);
/// At most 60 characters of text in quotes, non-printable ones as '?'.
std::string quoted(std::string_view text);
/// Refuses a count a header claims that the `available` bytes after it cannot hold at
/// `min_bytes` bytes per item; the check comes before any allocation.
void check_claim(const std::string& name, u64 count, const std::string& what, u64 min_bytes, u64 available);
/// Refuses a count beyond what an int index holds.
void check_index_range(const std::string& name, u64 count, const char* what);

bool is_space(char c);

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
bool next_statement(Lines& lines, std::string_view* line, Tokens* rest, std::string_view* keyword);
/// A decimal number (or inf, nan) as the whole of t, read the same in every locale.
bool parse_double(std::string_view t, double* v);
/// A decimal integer as the whole of t.
bool parse_integer(std::string_view t, long long* v);

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
std::string out_of_range(long long index, long long vertices, const std::string& where);
/// Appends the fan triangulation of a polygon (no index checks: the polygon's are made here).
void add_polygon(std::vector<int>& F, const std::vector<int>& poly);
/// The mesh of the vertices v (x y z per vertex) and the triangles f (3 indices each).
MeshFile assemble(std::vector<double>& v, std::vector<int>& f);

MeshFile parse_off(const std::string& bytes, const std::string& name, const ReadOptions& options);
MeshFile parse_obj(const std::string& bytes, const std::string& name, const ReadOptions& options);
MeshFile parse_ply(const std::string& bytes, const std::string& name, const ReadOptions& options);
MeshFile parse_stl(const std::string& bytes, const std::string& name);

}  // namespace detail
}  // namespace canonform::io
