// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: little-endian integers and floats in byte strings, the byte order of the binary files
// the views area writes and reads (codebooks, descriptor files), whatever the machine's.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

namespace canonform::io {

/// Appends v as 4 bytes, least significant first.
inline void put_u32(std::string& out, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xFFu));
}
/// Appends v in two's complement as 4 bytes, least significant first.
inline void put_i32(std::string& out, std::int32_t v) {
    put_u32(out, static_cast<std::uint32_t>(v));
}
/// Appends the IEEE 754 bits of f as 4 bytes, least significant first.
inline void put_f32(std::string& out, float f) {
    std::uint32_t v;
    std::memcpy(&v, &f, 4);
    put_u32(out, v);
}
/// The 4 bytes at p, least significant first (the caller checks that they exist).
inline std::uint32_t get_u32(const unsigned char* p) {
    return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
           (std::uint32_t(p[3]) << 24);
}

}  // namespace canonform::io
