# SPDX-License-Identifier: GPL-3.0-or-later
# CMake toolchain file: Windows x86-64 programs and DLLs cross-built on Debian with MinGW-w64
# (g++-mingw-w64-x86-64-posix: GCC with POSIX threads, winpthreads linked in statically).
#
#   cmake -S . -B build/windows --toolchain cmake/mingw-w64-x86_64.cmake     (or tools/build.sh --windows)
#
# Libraries come from the MinGW-w64 root (/usr/x86_64-w64-mingw32) only: none of the host's
# Linux libraries can be linked into a Windows program. The header-only ones the build uses
# (Eigen, nlohmann-json, CLI11) are taken from the host's /usr/include by cmake/WindowsCross.cmake,
# each from its own folder, never /usr/include itself. Outputs are linked statically against
# libstdc++, libgcc and winpthreads, so that a program needs only Windows' own DLLs (kernel32,
# msvcrt, ...). Programs run on the build machine through Wine (tools/wine.sh): ctest and
# gtest_discover_tests start them with it (CMAKE_CROSSCOMPILING_EMULATOR).
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CANONFORM_MINGW_TRIPLET x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${CANONFORM_MINGW_TRIPLET}-gcc-posix)
set(CMAKE_CXX_COMPILER ${CANONFORM_MINGW_TRIPLET}-g++-posix)
set(CMAKE_RC_COMPILER ${CANONFORM_MINGW_TRIPLET}-windres)
set(CMAKE_FIND_ROOT_PATH /usr/${CANONFORM_MINGW_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# -static: MinGW's runtime DLLs linked in; --no-insert-timestamp: no link time in the PE header, so
# that the same objects link to the same bytes (the release zip and wheel hold the build's files).
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static -Wl,--no-insert-timestamp")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-static -Wl,--no-insert-timestamp")
set(CMAKE_CROSSCOMPILING_EMULATOR "${CMAKE_CURRENT_LIST_DIR}/../tools/wine.sh")
