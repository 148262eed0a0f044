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

std::string read_file(const std::string& path) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) throw InputError("cannot read '" + path + "': no such file");
    if (fs::is_directory(st)) throw InputError("cannot read '" + path + "': it is a folder, not a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "': permission denied or unreadable");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError("cannot read '" + path + "': read error");
    return ss.str();
}

std::string lower_extension(const std::string& path) {
    std::string ext = fs::path(path).filename().extension().string();
    if (!ext.empty()) ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

std::string temporary_path_for(const std::string& path) {
    std::random_device rd;
    char buf[32];
    std::snprintf(buf, sizeof buf, ".tmp%08x", static_cast<unsigned>(rd()));
    const fs::path p(path);
    const std::string ext = lower_extension(path);
    const fs::path tmp = p.parent_path() / ("." + p.filename().string() + buf + (ext.empty() ? "" : "." + ext));
    return tmp.string();
}

void commit_file(const std::string& tmp, const std::string& path) {
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + path + "'");
    }
}

void write_file_atomic(const std::string& path, const std::string& bytes) {
    const std::string tmp = temporary_path_for(path);
    {
        std::ofstream out(tmp, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            std::remove(tmp.c_str());
            throw std::runtime_error("cannot write '" + path + "'");
        }
    }
    commit_file(tmp, path);
}

void make_directories(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir)) throw std::runtime_error("cannot create the folder '" + dir + "'");
}

bool is_file(const std::string& path) {
    std::error_code ec;
    return fs::is_regular_file(path, ec);
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
