// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/io/files.h"

#include "canonform/common/errors.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace canonform::io {

fs::path fs_path(const std::string& utf8) {
#ifdef _WIN32
    return fs::u8path(utf8);
#else
    return fs::path(utf8);
#endif
}

std::string utf8_path(const fs::path& p) {
#ifdef _WIN32
    return p.u8string();
#else
    return p.string();
#endif
}

std::string read_file(const std::string& path) {
    std::error_code ec;
    const fs::file_status st = fs::status(io::fs_path(path), ec);
    if (!fs::exists(st)) throw InputError("cannot read '" + path + "': no such file");
    if (fs::is_directory(st)) throw InputError("cannot read '" + path + "': it is a folder, not a file");
    std::ifstream in(io::fs_path(path), std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "': permission denied or unreadable");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError("cannot read '" + path + "': read error");
    return ss.str();
}

std::string lower_extension(const std::string& path) {
    std::string ext = utf8_path(io::fs_path(path).filename().extension());
    if (!ext.empty()) ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

std::string stem(const std::string& path) {
    return utf8_path(io::fs_path(path).stem());
}

std::string temporary_path_for(const std::string& path) {
    std::random_device rd;
    char buf[32];
    std::snprintf(buf, sizeof buf, ".tmp%08x", static_cast<unsigned>(rd()));
    const fs::path p = io::fs_path(path);
    const std::string ext = lower_extension(path);
    const fs::path tmp =
        p.parent_path() / io::fs_path("." + utf8_path(p.filename()) + buf + (ext.empty() ? "" : "." + ext));
    return utf8_path(tmp);
}

void commit_file(const std::string& tmp, const std::string& path) {
    std::error_code ec;
    fs::rename(io::fs_path(tmp), io::fs_path(path), ec);
    if (ec) {
        fs::remove(io::fs_path(tmp), ec);
        throw std::runtime_error("cannot write '" + path + "'");
    }
}

void write_file_atomic(const std::string& path, const std::string& bytes) {
    const std::string tmp = temporary_path_for(path);
    {
        std::ofstream out(io::fs_path(tmp), std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            std::error_code ec;
            fs::remove(io::fs_path(tmp), ec);
            throw std::runtime_error("cannot write '" + path + "'");
        }
    }
    commit_file(tmp, path);
}

void make_directories(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(io::fs_path(dir), ec);
    if (!fs::is_directory(io::fs_path(dir), ec))
        throw std::runtime_error("cannot create the folder '" + dir + "'");
}

bool is_file(const std::string& path) {
    std::error_code ec;
    return fs::is_regular_file(io::fs_path(path), ec);
}

std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h) {
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ULL;
    }
    return h;
}

std::string hex(std::uint64_t v) {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

}  // namespace canonform::io
