# SPDX-License-Identifier: GPL-3.0-or-later
# MeshLab's meshlab-common library compiled here from Debian's source package, in double
# precision: what pymeshlab is (every pymeshlab release is MeshLab's meshlab-common built with
# MESHLAB_SCALAR=double, behind pybind11). No Debian release packages such a library.
#
#   canonform_meshlab_from_source(NAME name VERSION 2022.02|2025.07 SOURCE_DIR dir
#                                 [ALSO_AS name2 version2])
#
# builds <build>/<name>/lib/libmeshlab-common.so (target <name>::common) from SOURCE_DIR (the
# tree tools/setup.sh unpacks into external/, never committed): the sources listed in that
# release's own src/common/CMakeLists.txt (its set(SOURCES ...), read here rather than copied),
# its resources and EasyExif; Qt 5.15, GLEW and Eigen from apt. Version string VERSION + "d", as
# MeshLab's CMake makes it for a double build ("2022.02d", "2025.07d"). None of MeshLab's own
# plugins or programs are built. Registers the plugin flavour <name> (plugins in
# <build>/<name>/plugins). About 2.5 CPU-minutes each.
#
# ALSO_AS name2 version2: a second library from the same source with only the version string
# changed (version2 + "d"), <build>/<name2>/lib/libmeshlab-common.so (target <name2>::common),
# sharing every object file but those of the sources that use the version (globals.cpp and
# plugins/plugin_manager.cpp, whose checkPlugin compares it): seconds, not minutes. Registers
# flavour <name2> for the pymeshlab harness only (NO_PLUGINS). Used for pymeshlab 2023.12: the
# 2025.07 source as "2023.12d" (Debian has no 2023.12 source; cmake/MeshLabPortable.cmake says
# why 2025.07's headers and layouts are 2023.12's).

find_package(Qt5 5.15 COMPONENTS Core Gui Widgets OpenGL Xml Network REQUIRED)
find_package(GLEW REQUIRED)
set(OpenGL_GL_PREFERENCE LEGACY)  # as MeshLab's own build
find_package(OpenGL REQUIRED)

function(canonform_meshlab_from_source)
  cmake_parse_arguments(M "" "NAME;VERSION;SOURCE_DIR" "ALSO_AS" ${ARGN})
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

  # Objects that do not depend on the version string, shared with an ALSO_AS variant: every source
  # but those that name it (2025.07: globals.cpp, plugins/plugin_manager.cpp; 2022.02 also
  # mlapplication.cpp). Of the headers only globals.h (meshlabVersion(), inline) and the plugin
  # interface's export macro name it, checked here too.
  set(versioned "")
  set(shared_sources "")
  foreach(f ${sources})
    file(STRINGS "${f}" uses REGEX "meshlabVersion|MESHLAB_VERSION|MESHLAB_PLUGIN_IID_EXPORTER")
    if(uses)
      list(APPEND versioned "${f}")
    else()
      list(APPEND shared_sources "${f}")
    endif()
  endforeach()
  file(GLOB_RECURSE headers "${src}/common/*.h")
  foreach(f ${headers})
    file(STRINGS "${f}" uses REGEX "meshlabVersion\\(\\)")
    if(uses AND NOT f MATCHES "/(globals|meshlab_plugin)\\.h$")
      message(FATAL_ERROR "${f} calls meshlabVersion(): the sources that include it cannot be shared between versions")
    endif()
  endforeach()
  set(objects ${M_NAME}_common_objects)
  add_library(${objects} OBJECT ${shared_sources} "${src}/common/meshlab-common.qrc")
  set_target_properties(${objects} PROPERTIES AUTOMOC ON AUTORCC ON POSITION_INDEPENDENT_CODE ON)
  target_compile_definitions(${objects} PUBLIC MESHLAB_SCALAR=double CANONFORM_MESHLAB_API=${api}
                                         PRIVATE MESHLAB_VERSION=${version}d)
  target_include_directories(${objects} SYSTEM PUBLIC "${src}" "${src}/vcglib")
  target_compile_options(${objects} PRIVATE -w)  # third-party code: its warnings are not ours
  # Its compile time is parsing (Qt, GLEW, vcglib and Eigen headers in each of about 60 sources),
  # not optimising: the headers most of them include, precompiled once (GLEW first, as it requires).
  target_precompile_headers(${objects} PRIVATE <GL/glew.h> <QString> <QObject> <QDomElement> <QAction> <QImage>
                                               <QReadWriteLock> <vcg/complex/complex.h> <vector> <map> <list>)
  target_link_libraries(${objects} PUBLIC Qt5::Core Qt5::Gui Qt5::OpenGL Qt5::Widgets Qt5::Xml Qt5::Network GLEW::GLEW
                                          OpenGL::GL Eigen3::Eigen ${M_NAME}_exif)

  set(variants "${M_NAME}|${version}")
  if(M_ALSO_AS)
    list(GET M_ALSO_AS 0 also_name)
    list(GET M_ALSO_AS 1 also_version)
    list(APPEND variants "${also_name}|${also_version}")
  endif()
  foreach(variant ${variants})
    string(REPLACE "|" ";" variant "${variant}")
    list(GET variant 0 name)
    list(GET variant 1 v)
    set(lib ${name}_common)
    add_library(${lib} SHARED ${versioned} $<TARGET_OBJECTS:${objects}>)
    add_library(${name}::common ALIAS ${lib})
    set_target_properties(${lib} PROPERTIES OUTPUT_NAME meshlab-common AUTOMOC ON
                                            LIBRARY_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/${name}/lib")
    target_compile_definitions(${lib} PUBLIC MESHLAB_VERSION=${v}d MESHLAB_SCALAR=double CANONFORM_MESHLAB_API=${api})
    target_include_directories(${lib} SYSTEM PUBLIC "${src}" "${src}/vcglib")
    target_compile_options(${lib} PRIVATE -w)
    target_link_libraries(${lib}
      PUBLIC Qt5::Core Qt5::Gui Qt5::OpenGL Qt5::Widgets Qt5::Xml Qt5::Network GLEW::GLEW OpenGL::GL Eigen3::Eigen
      PRIVATE ${M_NAME}_exif)
    target_link_options(${lib} PRIVATE -Wl,--no-undefined)
    message(STATUS "canonform: MeshLab ${v}d meshlab-common (double, ${n} sources of ${version}) from ${M_SOURCE_DIR} -> "
                   "${CMAKE_BINARY_DIR}/${name}/lib")
  endforeach()
  if(M_ALSO_AS)
    canonform_meshlab_flavour(${also_name} COMMON ${also_name}::common API ${api} SCALAR double VERSION ${also_version}d
                              DIR "${CMAKE_BINARY_DIR}/${also_name}/plugins" NO_PLUGINS)
  endif()

  canonform_meshlab_flavour(${M_NAME} COMMON ${M_NAME}::common API ${api} SCALAR double VERSION ${version}d
                            DIR "${out}/plugins")
endfunction()
