// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: functions compiled for several x86-64 instruction sets, the one for the running CPU
// chosen at run time (GCC's target_clones, resolved through ELF's ifunc).
//
// A function marked so must give the same bits in every clone: integer arithmetic, or IEEE
// +, -, *, / and sqrt per lane in an order fixed by the source. Neither "avx2" nor the default
// target has FMA, so no multiply-add is contracted there; "arch=x86-64-v4" has it, so
// CANONFORM_CLONES_AVX512 is only for code with no floating-point multiply-add to contract
// (integers, sums, divisions) or compiled with -ffp-contract=off (the views library).
//
// Nowhere else: clang does not make these clones; Windows has no ifunc, and GCC keeps 32-byte AVX
// values on the 16-byte-aligned stack of the Windows x64 ABI with aligned moves; sanitizer builds
// keep one path. There the default (SSE2) code runs, with the same bits.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(_WIN32)
/// Where the clones are made, code written with one instruction set's intrinsics may also be built
/// and chosen at run time (__builtin_cpu_supports); elsewhere only the portable code is.
#define CANONFORM_CPU_DISPATCH 1
/// AVX2 and the x86-64 baseline.
#define CANONFORM_CLONES __attribute__((target_clones("avx2", "default")))
#if __GNUC__ >= 11
/// Also AVX-512 (x86-64-v4), for 64-byte vectors in one instruction.
#define CANONFORM_CLONES_AVX512 __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else  // GCC 10 (bullseye: the portable build and the wheel) knows no arch=x86-64-v4
#define CANONFORM_CLONES_AVX512 CANONFORM_CLONES
#endif
#else
#define CANONFORM_CLONES
#define CANONFORM_CLONES_AVX512
#endif
