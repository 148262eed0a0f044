# SPDX-License-Identifier: GPL-3.0-or-later
# MeshLab's meshlab-common library compiled here from Debian's source package, in double
# precision: what pymeshlab is (every pymeshlab release is MeshLab's meshlab-common built with
# MESHLAB_SCALAR=double, behind pybind11). No Debian release packages such a library.
#
#   canonform_meshlab_from_source(NAME name VERSION 2022.02|2025.07 SOURCE_DIR dir)
#
# builds <build>/<name>/lib/libmeshlab-common.so (target <name>::common) from SOURCE_DIR (the
# tree tools/setup.sh unpacks into external/, never committed): the sources listed in that
# release's own src/common/CMakeLists.txt (its set(SOURCES ...), read here rather than copied),
# its resources and EasyExif; Qt 5.15, GLEW and Eigen from apt. Version string VERSION + "d", as
# MeshLab's CMake makes it for a double build ("2022.02d", "2025.07d"). None of MeshLab's own
# plugins or programs are built. Registers the plugin flavour <name> (plugins in
# <build>/<name>/plugins). About 2.5 CPU-minutes each.

find_package(Qt5 5.15 COMPONENTS Core Gui Widgets OpenGL Xml Network REQUIRED)
find_package(GLEW REQUIRED)
set(OpenGL_GL_PREFERENCE LEGACY)  # as MeshLab's own build
find_package(OpenGL REQUIRED)

function(canonform_meshlab_from_source)
  cmake_parse_arguments(M "" "NAME;VERSION;SOURCE_DIR" "" ${ARGN})
  set(src "${M_SOURCE_DIR}/src")
  if(NOT EXISTS "${src}/common/plugins/interfaces/filter_plugin.h" OR NOT EXISTS "${src}/vcglib/vcg/complex/complex.h")
    message(FATAL_ERROR "MeshLab ${M_VERSION} source not found under ${M_SOURCE_DIR}.\n"
                        "Run tools/setup.sh (fetches Debian's meshlab ${M_VERSION} source package into external/), "
                        "or turn the option of this build off.")
  endif()
  file(READ "${M_SOURCE_DIR}/ML_VERSION" version)
  string(STRIP "${version}" version)
  if(NOT version STREQUAL M_VERSION)
    message(FATAL_ERROR "${M_SOURCE_DIR} is MeshLab ${version}, not ${M_VERSION}")
  endif()
  string(SUBSTRING "${version}" 0 4 api)
  set(out "${CMAKE_BINARY_DIR}/${M_NAME}")

  # The library's sources as its own CMakeLists.txt lists them.
  file(READ "${src}/common/CMakeLists.txt" lists)
  if(NOT lists MATCHES "set\\(SOURCES([^)]*)\\)")
    message(FATAL_ERROR "no set(SOURCES ...) in ${src}/common/CMakeLists.txt")
  endif()
  string(REGEX REPLACE "[ \t\r\n]+" ";" sources "${CMAKE_MATCH_1}")
  list(FILTER sources INCLUDE REGEX "\\.cpp$")
  list(TRANSFORM sources PREPEND "${src}/common/")
  list(LENGTH sources n)

  # meshlab-common's one bundled dependency (EasyExif: src/external/easyexif[-1.0]).
  file(GLOB exif "${src}/external/easyexif*/exif.cpp")
  if(NOT exif)
    message(FATAL_ERROR "EasyExif not found under ${src}/external")
  endif()
  get_filename_component(exif_dir "${exif}" DIRECTORY)
  add_library(${M_NAME}_exif STATIC "${exif}")
  target_include_directories(${M_NAME}_exif SYSTEM PUBLIC "${exif_dir}")
  target_compile_options(${M_NAME}_exif PRIVATE -w)

  set(lib ${M_NAME}_common)
  add_library(${lib} SHARED ${sources} "${src}/common/meshlab-common.qrc")
  add_library(${M_NAME}::common ALIAS ${lib})
  set_target_properties(${lib} PROPERTIES OUTPUT_NAME meshlab-common AUTOMOC ON AUTORCC ON
                                          LIBRARY_OUTPUT_DIRECTORY "${out}/lib")
  target_compile_definitions(${lib} PUBLIC MESHLAB_VERSION=${version}d MESHLAB_SCALAR=double CANONFORM_MESHLAB_API=${api})
  target_include_directories(${lib} SYSTEM PUBLIC "${src}" "${src}/vcglib")
  target_compile_options(${lib} PRIVATE -w)  # third-party code: its warnings are not ours
  target_link_libraries(${lib}
    PUBLIC Qt5::Core Qt5::Gui Qt5::OpenGL Qt5::Widgets Qt5::Xml Qt5::Network GLEW::GLEW OpenGL::GL Eigen3::Eigen
    PRIVATE ${M_NAME}_exif)
  target_link_options(${lib} PRIVATE -Wl,--no-undefined)
  message(STATUS "canonform: MeshLab ${version}d meshlab-common (double, ${n} sources) from ${M_SOURCE_DIR} -> ${out}/lib")

  canonform_meshlab_flavour(${M_NAME} COMMON ${M_NAME}::common API ${api} SCALAR double VERSION ${version}d
                            DIR "${out}/plugins")
endfunction()
