// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/common/heap_pages.h"

#include <cstdint>
#include <cstdlib>  // (defines __GLIBC__ where the C library is glibc)

// AddressSanitizer brings its own allocator (GCC says so with __SANITIZE_ADDRESS__, clang with
// __has_feature): nothing to advise there.
#if defined(__SANITIZE_ADDRESS__)
#define CANONFORM_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CANONFORM_ASAN 1
#endif
#endif

#if defined(__linux__) && defined(__GLIBC__) && !defined(CANONFORM_ASAN)
#define CANONFORM_HEAP_PAGES 1
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace canonform {

bool advise_heap_huge_pages() {
#ifdef CANONFORM_HEAP_PAGES
    constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
    constexpr std::size_t kProbe = std::size_t{8} << 20;
    if (mallopt(M_MMAP_THRESHOLD, 32 << 20) != 1 || mallopt(M_TRIM_THRESHOLD, 128 << 20) != 1 ||
        mallopt(M_TOP_PAD, 64 << 20) != 1)
        return false;
    // A block larger than the heap's spare top makes the heap grow by it and the new reserve; the
    // advice covers the whole 2 MB pages from that block to the heap's new end. Nothing is advised
    // unless the heap is seen to grow with the block at its end (another allocator, or a block
    // mapped apart: no advice).
    const auto before = reinterpret_cast<std::uintptr_t>(sbrk(0));
    void* probe = std::malloc(kProbe);
    if (!probe) return false;
    const auto at = reinterpret_cast<std::uintptr_t>(probe);
    const auto after = reinterpret_cast<std::uintptr_t>(sbrk(0));
    std::free(probe);
    if (!(after > before && at < after && after - at >= kProbe && after - at <= (std::uintptr_t{256} << 20)))
        return false;
    const std::uintptr_t lo = (at + kHugePage - 1) & ~(kHugePage - 1), hi = after & ~(kHugePage - 1);
    return hi > lo && madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE) == 0;
#else
    return false;
#endif
}

}  // namespace canonform
