// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: transparent huge pages for a program's malloc heap.
//
// Why: one canonical form or descriptor of a 10k-vertex mesh touches a few MB of fresh heap (the
// LDL^T factors, the image stacks), about 1,500 pages of 4 kB, each a page fault and a TLB entry.
// Linux backs memory advised MADV_HUGEPAGE with 2 MB pages when transparent huge pages are enabled
// "always" or "madvise" (Debian's default); glibc advises its heap so only when the user sets
// GLIBC_TUNABLES=glibc.malloc.hugetlb=1. The measured gain is in docs/benchmarks.md.
//
// What advise_heap_huge_pages() does (glibc on Linux; elsewhere nothing):
// - blocks below 32 MB come from the heap (glibc's own mmap threshold rises to 32 MB after the
//   first frees anyway), larger ones are mapped apart and returned when freed, as before;
// - the heap grows 64 MB at a time and keeps up to 128 MB freed at its top (no shrinking and
//   faulting in again between the stages of a run);
// - the heap's current reserve (about 64 MB of address space, no memory until touched) is advised
//   MADV_HUGEPAGE. Memory the heap takes beyond it, and other threads' arenas, keep 4 kB pages.
//
// For programs only: the tool and the benches call it first thing in main(). Library code never
// does: a host process (MeshLab, Python) keeps its allocator as it set it. Where memory lives
// changes, results do not.
#pragma once

namespace canonform {

/// See the header comment. Returns true if the advice was given (false: not Linux/glibc, or the
/// kernel refused it, e.g. without transparent huge pages; the thresholds stay set wherever glibc
/// took them); either way the program runs on.
bool advise_heap_huge_pages();

}  // namespace canonform
