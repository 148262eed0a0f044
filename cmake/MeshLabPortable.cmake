# SPDX-License-Identifier: GPL-3.0-or-later
# The portable flavours: both plugins for each MeshLab or pymeshlab release users install, compiled
# in one build on Debian bullseye (glibc 2.31, GCC 10's libstdc++, Qt 5.15.2: tools/host.sh bullseye)
# so that they load on any Linux at least that old. tools/package.sh --portable HOST configures this
# build (CANONFORM_PORTABLE=ON, nothing else) and makes one archive per flavour from it.
#
#   flavour          host (archive name)              MeshLab headers   precision  version    linked against
#   pymeshlab2022    pymeshlab 2022.2.x               2022.02           double     2022.02d   a 2022.02d meshlab-common
#   pymeshlab2023    pymeshlab 2023.12.x              2025.07 (below)   double     2023.12d   a 2025.07d meshlab-common
#   pymeshlab2025    pymeshlab 2025.7.x               2025.07           double     2025.07d   a 2025.07d meshlab-common
#   meshlab2025      MeshLab 2025.07 (AppImage,       2025.07           float      2025.07    Debian forky's libmeshlab-common.so
#                    Flathub, Debian forky)
#
# The libmeshlab-common.so each flavour links was built elsewhere and is given as
# CANONFORM_PORTABLE_COMMON_<flavour> (the bookworm build's build/pymeshlab2022/lib and
# build/pymeshlab2025/lib, forky's package): at link time only its exported symbols are read, and
# the plugin names it by its soname, libmeshlab-common.so, which binds at run time to the copy the
# host process already has (pymeshlab's wheel bundles its own; MeshLab's AppImage too). No
# meshlab-common is compiled here. The build links with --as-needed (CMAKE_*_LINKER_FLAGS, set by
# tools/package.sh), so a plugin names only the Qt modules and libraries it calls.
#
# pymeshlab 2023.12 (version "2023.12d", FilterPlugin API): Debian never packaged MeshLab 2023.12, so
# the plugin is compiled against MeshLab 2025.07's headers (external/meshlab-2025.07) with
# MESHLAB_VERSION 2023.12d. It relies on these headers and object layouts of MeshLab: the plugin
# interfaces (src/common/plugins/interfaces/: MeshLabPlugin, FilterPlugin and its virtual
# functions, the Qt plugin IID), the plugin manager's checks (plugins/plugin_manager.cpp: precision
# and the first six characters of the version), the parameter classes (src/common/parameters/:
# RichParameterList, RichBool/Int/Float/String/Enum and their values), the document
# (src/common/ml_document/: MeshDocument, MeshModel, CMeshO and the vcglib components it is made
# of), globals.h and MLException. Why 2025.07's are 2023.12's: in MeshLab's history, the commits
# that pymeshlab 2023.12, 2023.12.post1, .post2 and .post3 pin (2dbd2f4, 9c29999, 12a7f9d, 42bd621;
# ML_VERSION 2023.12) have src/common/plugins/, parameters/, ml_document/, python/, globals.h,
# globals.cpp and mlexception.h identical to the MeshLab-2025.07 tag's, except for one Python type
# name string in python/python_utils.h at 2dbd2f4 (pymeshlab's own documentation string; no plugin
# reads it); their vcglib pins (6ac9e0c, 88c881d) differ from 2025.07's (c94ef4e) only in functions
# (face and edge topology helpers, polygon tessellation, the outline packer), not in the mesh
# components that make up CMeshO. 2022.02's headers are not an option: 2023.12 changed
# RichParameter's layout (a default-value member) and renamed its value getters. The test
# portable.symbols checks that every MeshLab symbol the plugin leaves undefined is exported by a
# meshlab-common built from 2025.07's source.

set(CANONFORM_PORTABLE_FLAVOURS pymeshlab2022 pymeshlab2023 pymeshlab2025 meshlab2025)

# canonform_portable_flavour(NAME SOURCE_VERSION headers' release VERSION version string SCALAR s
#                            [OBJECTS_OF flavour])
function(canonform_portable_flavour name)
  cmake_parse_arguments(P "" "SOURCE_VERSION;VERSION;SCALAR;OBJECTS_OF" "" ${ARGN})
  set(lib "${CANONFORM_PORTABLE_COMMON_${name}}")
  if(NOT EXISTS "${lib}")
    message(FATAL_ERROR "CANONFORM_PORTABLE_COMMON_${name}: no libmeshlab-common.so given for the ${name} flavour "
                        "('${lib}'); tools/package.sh --portable passes them")
  endif()
  set(src "${PROJECT_SOURCE_DIR}/external/meshlab-${P_SOURCE_VERSION}/src")
  if(NOT EXISTS "${src}/common/plugins/interfaces/filter_plugin.h")
    message(FATAL_ERROR "MeshLab ${P_SOURCE_VERSION}'s headers not found in ${src}: run tools/setup.sh on bookworm")
  endif()
  string(SUBSTRING "${P_SOURCE_VERSION}" 0 4 api)
  set(t portable_${name}_common)
  add_library(${t} SHARED IMPORTED GLOBAL)
  set_target_properties(${t} PROPERTIES IMPORTED_LOCATION "${lib}" IMPORTED_NO_SONAME TRUE)
  target_include_directories(${t} SYSTEM INTERFACE "${src}" "${src}/vcglib")
  target_compile_definitions(${t} INTERFACE MESHLAB_VERSION=${P_VERSION} MESHLAB_SCALAR=${P_SCALAR}
                                            CANONFORM_MESHLAB_API=${api})
  target_link_libraries(${t} INTERFACE Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml Qt5::Network Eigen3::Eigen)
  set(objects_of "")
  if(P_OBJECTS_OF)
    set(objects_of OBJECTS_OF ${P_OBJECTS_OF})
  endif()
  canonform_meshlab_flavour(${name} COMMON ${t} API ${api} SCALAR ${P_SCALAR} VERSION ${P_VERSION}
                            DIR "${CMAKE_BINARY_DIR}/portable/${name}" NO_TWIN ${objects_of})
  message(STATUS "canonform: portable ${name}: MeshLab ${P_SOURCE_VERSION} headers, ${P_SCALAR}, version ${P_VERSION}, "
                 "linked against ${lib}")
endfunction()

find_package(Qt5 5.15 COMPONENTS Core Gui Widgets OpenGL Xml Network REQUIRED)
canonform_portable_flavour(pymeshlab2022 SOURCE_VERSION 2022.02 VERSION 2022.02d SCALAR double)
# pymeshlab2023's plugins differ from pymeshlab2025's only in the version string: the same objects
# apart from the plugin classes (cmake/MeshLabPlugin.cmake: OBJECTS_OF).
canonform_portable_flavour(pymeshlab2023 SOURCE_VERSION 2025.07 VERSION 2023.12d SCALAR double OBJECTS_OF pymeshlab2025)
canonform_portable_flavour(pymeshlab2025 SOURCE_VERSION 2025.07 VERSION 2025.07d SCALAR double)
canonform_portable_flavour(meshlab2025 SOURCE_VERSION 2025.07 VERSION 2025.07 SCALAR float)
