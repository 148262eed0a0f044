// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: little-endian integers and floats in byte strings, the byte order of the binary files
// the library writes and reads (binary PLY and STL meshes, codebooks, descriptor files), whatever
// the machine's.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace canonform::io {

/// Appends the bytes of v (an integer in two's complement, or the IEEE 754 bits of a float or a
/// double), least significant first.
template <class T>
inline void put_le(std::string& out, T v) {
    static_assert(std::is_arithmetic_v<T> &&
                  (sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8));
    using Bits = std::conditional_t<
        sizeof(T) == 1, std::uint8_t,
        std::conditional_t<sizeof(T) == 2, std::uint16_t,
                           std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
    Bits b;
    std::memcpy(&b, &v, sizeof(T));
    for (std::size_t k = 0; k < sizeof(T); ++k) out.push_back(static_cast<char>((b >> (8 * k)) & 0xFFu));
}
inline void put_u32(std::string& out, std::uint32_t v) {
    put_le(out, v);
}
inline void put_i32(std::string& out, std::int32_t v) {
    put_le(out, v);
}
inline void put_f32(std::string& out, float f) {
    put_le(out, f);
}
/// The 4 bytes at p, least significant first (the caller checks that they exist).
inline std::uint32_t get_u32(const unsigned char* p) {
    return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
           (std::uint32_t(p[3]) << 24);
}

}  // namespace canonform::io
