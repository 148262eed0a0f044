# SPDX-License-Identifier: GPL-3.0-or-later
# What the Windows cross build (cmake/mingw-w64-x86_64.cmake) needs beyond the toolchain, included
# by CMakeLists.txt when cross-compiling for Windows:
# - the header-only libraries of the host (Debian's libeigen3-dev, nlohmann-json3-dev,
#   libcli11-dev), each seen through a folder of its own in the build folder (windows-deps/), so
#   that no other host header can reach a Windows compile;
# - googletest, compiled for Windows from Debian's googletest source package (/usr/src/googletest),
#   found by the tests' find_package(GTest) as GTest::gtest and GTest::gtest_main;
# - the libraries that Debian has only for Linux left out, each with its own option (docs/install.md,
#   "Windows"): OpenCV (the `opencv` SIFT extractor), FAISS (the `kmeans` codebook method), oneTBB
#   (std::thread instead), Qt (the tool's picture commands). The sparse LDL^T is Eigen's, as on Linux.
enable_language(C)  # the C API's test program (tests/c_api)
set(_deps "${CMAKE_BINARY_DIR}/windows-deps")
file(MAKE_DIRECTORY "${_deps}/include")

# canonform_windows_header_package(NAME TARGET CONFIG_DIR INCLUDE_DIR [HEADER_DIR]): a CMake package
# NAME whose INTERFACE target TARGET sees INCLUDE_DIR, with the host package's own version file,
# so that find_package(NAME VERSION) checks the real version. With HEADER_DIR (a folder of
# /usr/include), INCLUDE_DIR is windows-deps/include, where a link to it is made.
function(canonform_windows_header_package name target config_dir include_dir)
  foreach(h ${ARGN})
    if(NOT EXISTS "/usr/include/${h}")
      message(FATAL_ERROR "/usr/include/${h} missing: tools/setup.sh installs the header-only libraries")
    endif()
    file(CREATE_LINK "/usr/include/${h}" "${_deps}/include/${h}" SYMBOLIC)
  endforeach()
  set(dir "${_deps}/cmake/${name}")
  file(MAKE_DIRECTORY "${dir}")
  file(GLOB version_file "${config_dir}/${name}ConfigVersion.cmake" "${config_dir}/${name}-config-version.cmake")
  if(NOT version_file)
    message(FATAL_ERROR "no version file of ${name} in ${config_dir}")
  endif()
  configure_file("${version_file}" "${dir}/${name}ConfigVersion.cmake" COPYONLY)
  file(WRITE "${dir}/${name}Config.cmake"
       "if(NOT TARGET ${target})\n"
       "  add_library(${target} INTERFACE IMPORTED)\n"
       "  set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES \"${include_dir}\")\n"
       "endif()\n")
  set(${name}_DIR "${dir}" CACHE PATH "${name} for the Windows build (cmake/WindowsCross.cmake)" FORCE)
endfunction()

canonform_windows_header_package(nlohmann_json nlohmann_json::nlohmann_json /usr/share/cmake/nlohmann_json
                                 "${_deps}/include" nlohmann)
canonform_windows_header_package(CLI11 CLI11::CLI11 /usr/share/cmake/CLI11 "${_deps}/include" CLI)
canonform_windows_header_package(Eigen3 Eigen3::Eigen /usr/share/eigen3/cmake /usr/include/eigen3)  # Eigen alone

# googletest for Windows, from Debian's source (googletest package), as GTest::gtest(_main).
if(CANONFORM_BUILD_TESTS)
  if(NOT EXISTS /usr/src/googletest/CMakeLists.txt)
    message(FATAL_ERROR "/usr/src/googletest missing: Debian's googletest package (tools/setup.sh) is the tests' source")
  endif()
  set(BUILD_GMOCK OFF CACHE BOOL "" FORCE)
  set(INSTALL_GTEST OFF CACHE BOOL "" FORCE)
  add_subdirectory(/usr/src/googletest "${CMAKE_BINARY_DIR}/googletest" EXCLUDE_FROM_ALL)
  set(dir "${_deps}/cmake/GTest")
  file(WRITE "${dir}/GTestConfig.cmake" "# googletest built by cmake/WindowsCross.cmake\n")
  set(GTest_DIR "${dir}" CACHE PATH "googletest for the Windows build (cmake/WindowsCross.cmake)" FORCE)
endif()
