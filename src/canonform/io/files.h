// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: files and folders - whole-file reads, atomic writes, folders - on std::filesystem.
//
// Every output of the project is written atomically: to a temporary file in the same folder,
// renamed over the target only when complete, so that a failure never leaves a half-written
// file. Every read names the file and the real cause (missing, a folder, unreadable).
//
// Paths are UTF-8 strings everywhere in the library. On Windows every file is opened through its
// UTF-16 name (fs_path() below), so that any name works whatever the process's code page is (a
// program of its own, or the Python interpreter that loaded the library's DLL).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace canonform::io {

/// The file-system path of a UTF-8 path string. On Windows through UTF-16 (libstdc++ would read a
/// narrow string in the C library's code page there); elsewhere the bytes as they are.
std::filesystem::path fs_path(const std::string& utf8);

/// A file-system path as a UTF-8 string (the inverse of fs_path()).
std::string utf8_path(const std::filesystem::path& p);

/// The whole file as bytes. InputError naming `path` if it is missing, a folder or unreadable.
std::string read_file(const std::string& path);

/// Writes `bytes` to `path` atomically (temporary file + rename). std::runtime_error naming the
/// path if it cannot.
void write_file_atomic(const std::string& path, const std::string& bytes);

/// A temporary path next to `path` (same folder, same extension) for an atomic write;
/// commit_file() renames it over `path` (and removes it if that fails).
std::string temporary_path_for(const std::string& path);
void commit_file(const std::string& tmp, const std::string& path);

/// Creates `dir` and its missing parents (std::runtime_error naming it if it cannot).
void make_directories(const std::string& dir);

/// True if `path` names an existing regular file (or a link to one).
bool is_file(const std::string& path);

/// The lower-case extension of the file name of `path`, without the dot ("ply"; "" if none).
/// Only the last path component counts: "/data/v1.2/D" has none.
std::string lower_extension(const std::string& path);

/// The file name of `path` without folder and extension ("/a/b/cat0.off" -> "cat0").
std::string stem(const std::string& path);

/// 64-bit FNV-1a hash of `bytes`, continuing from `h` (content keys of the retrieval cache).
std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 1469598103934665603ULL);

/// `v` as 16 lower-case hex digits.
std::string hex(std::uint64_t v);

}  // namespace canonform::io
