// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/views/descriptor_file.h"

#include "canonform/io/byte_order.h"
#include "canonform/io/files.h"
#include "canonform/views/codebook.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace canonform::views {
namespace {

using io::put_f32;
using io::put_i32;
using io::put_u32;

// Bounded little-endian reader; every read past the end throws "truncated".
class Reader {
public:
    Reader(const std::string& bytes, std::string where) : b_(bytes), where_(std::move(where)) {}
    [[noreturn]] void fail(const std::string& what) const { throw InputError(where_ + what); }
    void need(std::uint64_t n, const char* what) const {
        if (b_.size() - pos_ < n)
            fail(std::string("truncated while reading ") + what + " (offset " + std::to_string(pos_) +
                 ", file has " + std::to_string(b_.size()) + " bytes).");
    }
    std::uint32_t u32(const char* what) {
        need(4, what);
        const auto* p = reinterpret_cast<const unsigned char*>(b_.data() + pos_);
        pos_ += 4;
        return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
               (std::uint32_t(p[3]) << 24);
    }
    std::int32_t i32(const char* what) { return static_cast<std::int32_t>(u32(what)); }
    float f32(const char* what) {
        const std::uint32_t v = u32(what);
        float f;
        std::memcpy(&f, &v, 4);
        return f;
    }
    std::string bytes(std::uint64_t n, const char* what) {
        need(n, what);
        std::string s = b_.substr(pos_, static_cast<std::size_t>(n));
        pos_ += static_cast<std::size_t>(n);
        return s;
    }
    std::size_t remaining() const { return b_.size() - pos_; }

private:
    const std::string& b_;
    std::string where_;
    std::size_t pos_ = 0;
};

// The consistency rules of the header, shared by the writer and the reader.
void validate(const ModelDescriptor& d, const std::string& where) {
    auto fail = [&](const std::string& what) { throw InputError(where + what); };
    if (d.version != 1)
        fail("unsupported version " + std::to_string(d.version) + " (this build handles version 1).");
    if (d.views < 1) fail("the number of views must be >= 1 (got " + std::to_string(d.views) + ").");
    if (d.image_size < 1) fail("the image size must be >= 1 (got " + std::to_string(d.image_size) + ").");
    if (d.codebook_words < 0) fail("negative codebook size.");
    const auto V = static_cast<std::size_t>(d.views);
    if (d.keypoints_per_view.size() != V)
        fail("inconsistent counts: " + std::to_string(d.keypoints_per_view.size()) + " keypoint counts for " +
             std::to_string(V) + " views.");
    for (std::size_t v = 0; v < V; ++v)
        if (d.keypoints_per_view[v] < 0) fail("negative keypoint count of view " + std::to_string(v) + ".");
    if (d.codebook_words > 0) {
        if (!d.raw.empty())
            fail("inconsistent content: both histograms (codebook used) and raw descriptors.");
        if (d.histograms.size() != V)
            fail("inconsistent counts: " + std::to_string(d.histograms.size()) + " histograms for " +
                 std::to_string(V) + " views.");
        for (std::size_t v = 0; v < V; ++v) {
            int last = -1;
            double sum = 0;
            for (const auto& e : d.histograms[v]) {
                if (e.first <= last || e.first >= d.codebook_words)
                    fail("histogram of view " + std::to_string(v) + ": word " + std::to_string(e.first) +
                         " out of order or outside [0, " + std::to_string(d.codebook_words) + ").");
                if (!(e.second > 0) || !std::isfinite(e.second))
                    fail("histogram of view " + std::to_string(v) +
                         ": a count is not a finite positive number.");
                last = e.first;
                sum += e.second;
            }
            if (sum != static_cast<double>(d.keypoints_per_view[v]))
                fail("inconsistent counts: the histogram of view " + std::to_string(v) + " sums to " +
                     std::to_string(sum) + ", the view has " + std::to_string(d.keypoints_per_view[v]) +
                     " keypoints.");
        }
    } else {
        if (!d.histograms.empty())
            fail("inconsistent content: histograms without a codebook size (codebook_words = 0).");
        if (d.raw.size() != V)
            fail("inconsistent counts: " + std::to_string(d.raw.size()) + " raw descriptor sets for " +
                 std::to_string(V) + " views.");
        for (std::size_t v = 0; v < V; ++v) {
            if (d.raw[v].rows() != d.keypoints_per_view[v])
                fail("inconsistent counts: view " + std::to_string(v) + " has " +
                     std::to_string(d.raw[v].rows()) + " descriptors and " +
                     std::to_string(d.keypoints_per_view[v]) + " keypoints.");
            if (!d.raw[v].allFinite())
                fail("a descriptor of view " + std::to_string(v) + " has a non-finite value.");
        }
    }
}

}  // namespace

void write_descriptor(const std::string& path, const ModelDescriptor& d) {
    validate(d, "Descriptor for '" + path + "': ");
    if (d.source.size() > std::numeric_limits<std::uint32_t>::max())
        throw InputError("Descriptor for '" + path + "': the source string is too long.");
    std::string out;
    out.append("CFVD", 4);
    put_u32(out, 1);
    put_u32(out, static_cast<std::uint32_t>(d.source.size()));
    out.append(d.source);
    put_i32(out, d.views);
    put_i32(out, d.image_size);
    put_i32(out, d.codebook_words);
    for (int k : d.keypoints_per_view) put_i32(out, k);
    if (d.codebook_words > 0) {
        for (const auto& h : d.histograms) {
            put_u32(out, static_cast<std::uint32_t>(h.size()));
            for (const auto& e : h) {
                put_i32(out, e.first);
                put_f32(out, e.second);
            }
        }
    } else {
        for (const auto& m : d.raw) {
            put_u32(out, static_cast<std::uint32_t>(m.rows()));
            for (Eigen::Index r = 0; r < m.rows(); ++r)
                for (int c = 0; c < kDescriptorSize; ++c) put_f32(out, m(r, c));
        }
    }

    io::write_file_atomic(path, out);
}

ModelDescriptor read_descriptor(const std::string& path) {
    return parse_descriptor(io::read_file(path), "Descriptor file '" + path + "': ");
}

ModelDescriptor parse_descriptor(const std::string& bytes, const std::string& where) {
    Reader in(bytes, where);
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), "CFVD", 4) != 0)
        in.fail("wrong magic (not a canonform view-descriptor file).");
    in.bytes(4, "the magic");
    ModelDescriptor d;
    const std::uint32_t version = in.u32("the version");
    if (version != 1)
        in.fail("unsupported version " + std::to_string(version) + " (this build reads version 1).");
    d.version = 1;
    const std::uint32_t L = in.u32("the source length");
    d.source = in.bytes(L, "the source string");
    d.views = in.i32("the view count");
    d.image_size = in.i32("the image size");
    d.codebook_words = in.i32("the codebook size");
    if (d.views < 1) in.fail("the number of views must be >= 1 (got " + std::to_string(d.views) + ").");
    if (d.image_size < 1) in.fail("the image size must be >= 1 (got " + std::to_string(d.image_size) + ").");
    if (d.codebook_words < 0) in.fail("negative codebook size.");
    const auto V = static_cast<std::size_t>(d.views);
    in.need(4ull * V, "the keypoint counts");  // before allocating
    d.keypoints_per_view.resize(V);
    for (auto& k : d.keypoints_per_view) k = in.i32("the keypoint counts");
    if (d.codebook_words > 0) {
        d.histograms.resize(V);
        for (std::size_t v = 0; v < V; ++v) {
            const std::uint32_t nnz = in.u32("a histogram size");
            if (nnz > static_cast<std::uint32_t>(d.codebook_words))
                in.fail("inconsistent counts: the histogram of view " + std::to_string(v) + " has " +
                        std::to_string(nnz) + " non-zero words, the codebook only " +
                        std::to_string(d.codebook_words) + ".");
            in.need(8ull * nnz, "a histogram");
            d.histograms[v].resize(nnz);
            for (auto& e : d.histograms[v]) {
                e.first = in.i32("a histogram");
                e.second = in.f32("a histogram");
            }
        }
    } else {
        d.raw.resize(V);
        for (std::size_t v = 0; v < V; ++v) {
            const std::uint32_t rows = in.u32("a descriptor count");
            if (static_cast<std::int64_t>(rows) != d.keypoints_per_view[v])
                in.fail("inconsistent counts: view " + std::to_string(v) + " has " + std::to_string(rows) +
                        " descriptors and " + std::to_string(d.keypoints_per_view[v]) + " keypoints.");
            in.need(4ull * kDescriptorSize * rows, "the descriptors");
            d.raw[v].resize(rows, kDescriptorSize);
            for (std::uint32_t r = 0; r < rows; ++r)
                for (int c = 0; c < kDescriptorSize; ++c) d.raw[v](r, c) = in.f32("the descriptors");
        }
    }
    if (in.remaining() != 0) in.fail(std::to_string(in.remaining()) + " unexpected trailing bytes.");
    validate(d, where);
    return d;
}

}  // namespace canonform::views
