// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/heap_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define SANITIZED 1  // AddressSanitizer's own allocator: nothing is advised (heap_pages.cpp)
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SANITIZED 1
#endif
#endif

namespace {

/// The VmFlags line of the mapping in /proc/self/smaps that holds address `a` ("" if none).
std::string vm_flags_at(std::uintptr_t a) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = lo <= a && a < hi;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return "";
}

}  // namespace

// Where the kernel has transparent huge pages (its sysfs switch exists, whatever it is set to),
// the heap's reserve is advised for them: a block taken after the advice lies in a mapping
// flagged "hg" (MADV_HUGEPAGE). Without them, or off glibc/Linux, nothing is advised.
TEST(HeapPages, TheHeapReserveIsAdvisedWhereTheKernelHasHugePages) {
    const bool advised = canonform::advise_heap_huge_pages();
#if !defined(__linux__) || !defined(__GLIBC__) || defined(SANITIZED)
    EXPECT_FALSE(advised);
#else
    if (!std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled")) {
        EXPECT_FALSE(advised);
        return;
    }
    ASSERT_TRUE(advised);
    constexpr std::size_t kSize = std::size_t{4} << 20;
    auto* block = static_cast<unsigned char*>(std::malloc(kSize));
    ASSERT_NE(block, nullptr);
    std::memset(block, 7, kSize);
    const std::string flags = vm_flags_at(reinterpret_cast<std::uintptr_t>(block) + kSize / 2);
    EXPECT_EQ(block[kSize - 1], 7);
    std::free(block);
    EXPECT_NE((flags + " ").find(" hg "), std::string::npos) << "'" << flags << "'";
#endif
}
