// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the collection index's file (format in collection_index.h), read and written in
// sections straight from and to the index's arrays (an index of 10^6 models is about 2 GB: no
// second copy in memory), and the index of a run's method folder.
#include "canonform/retrieval/collection_index.h"

#include "canonform/common/parallel.h"
#include "canonform/io/csv.h"
#include "canonform/io/files.h"
#include "canonform/retrieval/collection_index_detail.h"
#include "canonform/views/descriptor_file.h"
#include "canonform/views/view_directions.h"

#if defined(__unix__) || defined(__APPLE__)
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>
#define CANONFORM_INDEX_MMAP 1
#endif

#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace canonform::retrieval {

namespace {

/// Little-endian sections of a file being read, each checked against the bytes left.
struct In {
    std::ifstream f;
    std::string where;
    std::uint64_t size = 0, at = 0;

    explicit In(const std::string& path) : f(path, std::ios::binary), where("'" + path + "'") {
        std::error_code ec;
        if (!f || std::filesystem::is_directory(path, ec)) throw InputError("cannot read " + where);
        f.seekg(0, std::ios::end);
        size = static_cast<std::uint64_t>(f.tellg());
        f.seekg(0);
    }
    void need(std::uint64_t n) const {
        if (size - at < n) throw InputError(where + ": truncated at byte " + std::to_string(at));
    }
    void read(void* dst, std::uint64_t n) {
        need(n);
        f.read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
        if (!f) throw InputError(where + ": read error at byte " + std::to_string(at));
        at += n;
    }
    template <class T>
    T get() {
        T v;
        read(&v, sizeof v);
        return v;
    }
    std::string get_string() {
        const auto n = get<std::uint32_t>();
        std::string s(n, '\0');
        read(s.data(), n);
        return s;
    }
};

/// Sections of a file being written.
struct Out {
    std::ofstream f;
    template <class T>
    void put(T v) {
        f.write(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void put_bytes(const void* p, std::size_t n) {
        f.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    }
    void put_string(const std::string& s) {
        put(static_cast<std::uint32_t>(s.size()));
        put_bytes(s.data(), s.size());
    }
};

}  // namespace

/// Reading and writing the file (a friend of CollectionIndex).
class IndexFile {
public:
    static CollectionIndex load(const std::string& path, bool map) {
        In in(path);
        char magic[4];
        in.need(4);
        in.read(magic, 4);
        if (std::memcmp(magic, "CFCI", 4) != 0)
            throw InputError(in.where + ": not a canonform collection index");
        const auto version = in.get<std::uint32_t>();
        if (version != 1 && version != 2)
            throw InputError(in.where + ": unsupported version " + std::to_string(version));
        const auto n = in.get<std::uint32_t>(), v = in.get<std::uint32_t>(), w = in.get<std::uint32_t>();
        if (n == 0 || v == 0 || v > static_cast<std::uint32_t>(detail::kMaxViews) || w == 0 || w > 65535)
            throw InputError(in.where + ": bad header (models, views or words out of range)");
        CollectionIndex x;
        x.views_ = static_cast<int>(v);
        x.method_ = in.get_string();
        x.simplify_ = in.get<std::int32_t>();
        x.names_.reserve(n);
        x.classes_.reserve(n);
        for (std::uint32_t k = 0; k < n; ++k) {
            x.names_.push_back(in.get_string());
            x.classes_.push_back(in.get_string());
        }
        views::DescriptorMatrix words(static_cast<Eigen::Index>(w), 128);
        in.read(words.data(), static_cast<std::uint64_t>(w) * 128 * sizeof(float));
        x.codebook_ = views::Codebook::from_words(std::move(words));
        if (version == 1)
            read_v1(in, x);
        else
            read_v2(in, x, map ? path : std::string());
        if (in.at != in.size)
            throw InputError(in.where + ": " + std::to_string(in.size - in.at) + " trailing bytes");
        return x;
    }

    static void save(const CollectionIndex& x, const std::string& path) {
        const std::string tmp = io::temporary_path_for(path);
        {
            Out o{std::ofstream(tmp, std::ios::binary | std::ios::trunc)};
            if (!o.f) throw std::runtime_error("cannot write '" + tmp + "'");
            o.put_bytes("CFCI", 4);
            o.put(std::uint32_t{2});
            o.put(static_cast<std::uint32_t>(x.size()));
            o.put(static_cast<std::uint32_t>(x.views_));
            o.put(static_cast<std::uint32_t>(x.codebook_.size()));
            o.put_string(x.method_);
            o.put(static_cast<std::int32_t>(x.simplify_));
            for (std::size_t k = 0; k < x.size(); ++k) {
                o.put_string(x.names_[k]);
                o.put_string(x.classes_[k]);
            }
            o.put_bytes(x.codebook_.words().data(),
                        static_cast<std::size_t>(x.codebook_.words().size()) * sizeof(float));
            o.put_bytes(x.offsets_.data(), x.offsets_.size() * sizeof(std::uint64_t));
            o.put_bytes(x.mapped_ ? x.mapped_.get() : x.data_.data(),
                        static_cast<std::size_t>(x.offsets_.back()));
            const SummarySearch& s = x.first_;
            o.put(static_cast<std::uint32_t>(s.trained() ? 1 : 0));
            if (s.trained()) {
                const SummaryOptions& so = s.options();
                o.put(static_cast<std::int32_t>(so.dims));
                o.put(static_cast<std::uint8_t>(so.orbits));
                o.put(static_cast<std::uint8_t>(so.sqrt_counts));
                o.put(static_cast<std::int32_t>(so.sample));
                o.put(static_cast<std::int32_t>(so.iterations));
                o.put(static_cast<std::uint64_t>(so.seed));
                o.put(static_cast<std::uint32_t>(s.summary_dims()));
                o.put(s.scale());
                o.put_bytes(s.offset().data(), s.offset().size() * sizeof(float));
                o.put_bytes(s.axes().data(), s.axes().size() * sizeof(float));
                o.put_bytes(s.codes().data(), s.codes().size());
            }
            o.f.close();
            if (!o.f) {
                std::error_code ec;
                std::filesystem::remove(tmp, ec);
                throw std::runtime_error("cannot write '" + tmp + "' (disk full?)");
            }
        }
        io::commit_file(tmp, path);
    }

private:
    static void read_v1(In& in, CollectionIndex& x) {
        const std::size_t n = x.names_.size(), v = static_cast<std::size_t>(x.views_);
        const std::size_t slots = n * v + 1;
        std::vector<std::uint64_t> offsets(slots);
        in.read(offsets.data(), slots * sizeof(std::uint64_t));
        for (std::size_t k = 0; k + 1 < slots; ++k)
            if (offsets[k + 1] < offsets[k]) throw InputError(in.where + ": offsets not increasing");
        if (offsets[0] != 0 || (in.size - in.at) != offsets.back() * 2 * sizeof(std::uint16_t))
            throw InputError(in.where +
                             ": the entries do not match the offsets (truncated or trailing bytes)");
        std::vector<std::uint16_t> entries(static_cast<std::size_t>(offsets.back()) * 2);
        in.read(entries.data(), entries.size() * sizeof(std::uint16_t));
        x.offsets_.assign(1, 0);
        std::vector<views::Histogram> model(v);
        for (std::size_t m = 0; m < n; ++m) {
            for (std::size_t j = 0; j < v; ++j) {
                model[j].clear();
                for (std::uint64_t e = offsets[m * v + j]; e < offsets[m * v + j + 1]; ++e)
                    model[j].emplace_back(entries[2 * e], static_cast<float>(entries[2 * e + 1]));
            }
            try {
                for (const auto& h : model) detail::encode_view(h, x.codebook_.size(), x.data_, x.names_[m]);
            } catch (const InputError& e) {
                throw InputError(in.where + ": an entry out of range (" + e.what() + ")");
            }
            x.offsets_.push_back(x.data_.size());
        }
    }

    /// The whole file mapped read-only; the model bytes at `at` (InputError if it cannot be).
    static void map_models(const std::string& path, In& in, CollectionIndex& x) {
#if defined(CANONFORM_INDEX_MMAP)
        const int fd = ::open(path.c_str(), O_RDONLY);
        if (fd < 0) throw InputError("cannot map " + in.where);
        void* base = ::mmap(nullptr, static_cast<std::size_t>(in.size), PROT_READ, MAP_SHARED, fd, 0);
        ::close(fd);
        if (base == MAP_FAILED) throw InputError("cannot map " + in.where);
        const std::size_t length = static_cast<std::size_t>(in.size);
        const auto* models = static_cast<const std::uint8_t*>(base) + in.at;
        // Queries read scattered models: no read-ahead.
        ::madvise(base, length, MADV_RANDOM);
        x.mapped_ = std::shared_ptr<const std::uint8_t>(
            models, [base, length](const std::uint8_t*) { ::munmap(base, length); });
        const std::size_t n = x.names_.size();
        x.checked_ = std::shared_ptr<std::atomic<std::uint8_t>[]>(new std::atomic<std::uint8_t>[n]());
        in.f.seekg(static_cast<std::streamoff>(in.at + x.offsets_.back()));
        in.at += x.offsets_.back();
#else
        (void)path;
        (void)in;
        (void)x;
#endif
    }

    static void read_v2(In& in, CollectionIndex& x, const std::string& map_path) {
        (void)map_path;  // without mmap: always read
        const std::size_t n = x.names_.size();
        x.offsets_.resize(n + 1);
        in.read(x.offsets_.data(), (n + 1) * sizeof(std::uint64_t));
        for (std::size_t k = 0; k < n; ++k)
            if (x.offsets_[k + 1] < x.offsets_[k]) throw InputError(in.where + ": offsets not increasing");
        if (x.offsets_[0] != 0) throw InputError(in.where + ": the first model does not start at 0");
        in.need(x.offsets_.back());
#if defined(CANONFORM_INDEX_MMAP)
        if (!map_path.empty()) {
            map_models(map_path, in, x);
            return read_first_pass(in, x);
        }
#endif
        x.data_.resize(static_cast<std::size_t>(x.offsets_.back()));
        in.read(x.data_.data(), x.data_.size());
        std::atomic<std::size_t> bad{n};
        parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t k, int) {
            const auto m = static_cast<std::size_t>(k);
            if (!detail::check_model(x.data_.data() + x.offsets_[m], x.data_.data() + x.offsets_[m + 1],
                                     x.views_, x.codebook_.size())) {
                std::size_t cur = bad.load();
                while (m < cur && !bad.compare_exchange_weak(cur, m)) {
                }
            }
        });
        if (bad.load() < n)
            throw InputError(
                in.where + ": model " + std::to_string(bad.load()) + " ('" + x.names_[bad.load()] +
                "') is not well-formed (an entry out of range or a view of more than 65535 keypoints)");
        read_first_pass(in, x);
    }

    static void read_first_pass(In& in, CollectionIndex& x) {
        const std::size_t n = x.names_.size();
        if (in.get<std::uint32_t>() == 0) return;
        SummaryOptions so;
        so.dims = in.get<std::int32_t>();
        so.orbits = in.get<std::uint8_t>() != 0;
        so.sqrt_counts = in.get<std::uint8_t>() != 0;
        so.sample = in.get<std::int32_t>();
        so.iterations = in.get<std::int32_t>();
        so.seed = in.get<std::uint64_t>();
        const auto sdims = in.get<std::uint32_t>();
        const auto scale = in.get<float>();
        if (so.dims < 16 || so.dims > 256 || so.dims % 16 != 0)
            throw InputError(in.where + ": first pass of " + std::to_string(so.dims) + " dimensions");
        const auto maps = views::rotation_view_maps();
        if (maps.empty() || maps[0].size() != static_cast<std::size_t>(x.views_))
            throw InputError(in.where + ": a first pass for " + std::to_string(x.views_) +
                             " views (the rotations are for " +
                             std::to_string(maps.empty() ? 0 : maps[0].size()) + ")");
        x.orbit_of_view_ = view_orbits(maps, x.views_, &x.orbit_count_);
        const std::uint64_t expected = static_cast<std::uint64_t>(so.orbits ? x.orbit_count_ : 1) *
                                       static_cast<std::uint64_t>(x.codebook_.size());
        if (sdims != expected)
            throw InputError(in.where + ": first pass of " + std::to_string(sdims) +
                             " summary coordinates, expected " + std::to_string(expected));
        const auto d = static_cast<std::size_t>(so.dims);
        std::vector<float> offset(d), axes(static_cast<std::size_t>(sdims) * d);
        in.read(offset.data(), d * sizeof(float));
        in.read(axes.data(), axes.size() * sizeof(float));
        x.first_ = SummarySearch::from_parts(so, sdims, std::move(axes), std::move(offset), scale);
        // Read in blocks straight into the layout the first pass reads (no second copy of N codes).
        std::vector<std::int8_t> split(n * d), block(4096 * d);
        for (std::size_t m = 0; m < n; m += 4096) {
            const std::size_t count = std::min<std::size_t>(4096, n - m);
            in.read(block.data(), count * d);
            for (std::size_t k = 0; k < count; ++k)
                SummarySearch::put_split(split.data(), n, so.dims, m + k, block.data() + k * d);
        }
        x.first_.set_split_codes(std::move(split));
    }
};

CollectionIndex CollectionIndex::load(const std::string& path, bool map) {
    try {
        return IndexFile::load(path, map);
    } catch (const std::bad_alloc&) {
        throw InputError("'" + path + "': not enough memory to load the index");
    }
}

void CollectionIndex::save(const std::string& path) const {
    IndexFile::save(*this, path);
}

CollectionIndex index_descriptors(const std::string& folder, const std::vector<std::string>& names,
                                  const std::vector<std::string>& classes, const std::string& method,
                                  int simplify, int threads) {
    if (names.empty()) throw InputError("'" + folder + "': no models to index");
    if (classes.size() != names.size())
        throw InputError("Collection index: names and classes differ in number");
    auto read = [&](std::size_t k) {
        const std::string path = folder + "/descriptors/" + names[k] + ".cfvd";
        views::ModelDescriptor d = views::read_descriptor(path);
        if (d.codebook_words == 0) throw InputError("'" + path + "' has no histograms");
        return std::move(d.histograms);
    };
    // Read in parallel, chunk by chunk, added in order.
    std::vector<std::vector<views::Histogram>> chunk(std::min<std::size_t>(names.size(), 4096));
    std::unique_ptr<CollectionIndex::Builder> b;
    ParallelOptions par;
    par.threads = threads;
    for (std::size_t begin = 0; begin < names.size(); begin += chunk.size()) {
        const std::size_t end = std::min(names.size(), begin + chunk.size());
        parallel_for(
            static_cast<std::ptrdiff_t>(end - begin),
            [&](std::ptrdiff_t k, int) {
                chunk[static_cast<std::size_t>(k)] = read(begin + static_cast<std::size_t>(k));
            },
            par);
        if (!b)
            b = std::make_unique<CollectionIndex::Builder>(views::Codebook::load(folder + "/codebook.bin"),
                                                           method, simplify,
                                                           static_cast<int>(chunk[0].size()));
        for (std::size_t k = begin; k < end; ++k) b->add(names[k], classes[k], chunk[k - begin]);
    }
    const SummaryOptions defaults;
    return b->finish(&defaults, threads);
}

CollectionIndex index_method_folder(const std::string& folder, const std::string& method, int simplify) {
    const auto rows = io::read_csv(folder + "/models.csv");
    std::vector<std::string> names, classes;
    for (std::size_t r = 1; r < rows.size(); ++r) {
        if (rows[r].size() < 2)
            throw InputError("'" + folder + "/models.csv': row " + std::to_string(r + 1) +
                             " is not name,class");
        names.push_back(rows[r][0]);
        classes.push_back(rows[r][1]);
    }
    if (names.empty()) throw InputError("'" + folder + "/models.csv': no models");
    return index_descriptors(folder, names, classes, method, simplify);
}

}  // namespace canonform::retrieval
