# SPDX-License-Identifier: GPL-3.0-or-later
# The MeshLab builds ("flavours") a plugin is compiled for, and the function that compiles a
# plugin for each of them from one set of sources.
#
#   flavour         host                                         API    precision  plugins in
#   meshlab2020     MeshLab 2020.09 (Debian bookworm)             2020   float      <build>/meshlab/plugins
#   meshlab2022     MeshLab 2022.02 (Debian trixie)               2022   float      <build>/meshlab/plugins
#   meshlab2025     MeshLab 2025.07 (Debian forky/sid)            2025   float      <build>/meshlab/plugins
#   pymeshlab2022   pymeshlab 2022.2.x (meshlab-common built here) 2022  double     <build>/pymeshlab2022/plugins
#   pymeshlab2025   pymeshlab 2025.7.x (meshlab-common built here) 2025  double     <build>/pymeshlab2025/plugins
#
# The first three are the installed MeshLab (cmake/MeshLabInstalled.cmake: one of them per
# system), the last two options CANONFORM_MESHLAB2022 / CANONFORM_MESHLAB2025
# (cmake/MeshLabFromSource.cmake). API 2020 is MeshLab 2020.09's MeshFilterInterface; 2022 and
# 2025 are the FilterPlugin API, which 2025.07 kept (its headers were split and some parameter
# classes renamed, none of which our adapters use: src/canonform/meshlab/meshlab2022_adapter.cpp
# compiles against both).

set(CANONFORM_PLUGIN_INSTALL_DIR "lib/x86_64-linux-gnu/meshlab/plugins" CACHE STRING
    "Plugin directory relative to the install prefix (where Debian's MeshLab looks: /usr/<this>)")

# canonform_meshlab_flavour(NAME COMMON target API 2020|2022|2025 SCALAR float|double VERSION v
#                           DIR dir [INSTALLED] [NO_TWIN] [NO_PLUGINS] [OBJECTS_OF flavour])
# NO_TWIN: no WRONG_PRECISION twin for this flavour (the portable flavours, cmake/MeshLabPortable.cmake).
# NO_PLUGINS: no plugins at all, only its MeshSet (src/CMakeLists.txt) for the pymeshlab harness.
# OBJECTS_OF: a flavour of the same headers and precision that differs only in its version string;
# its plugins' objects are this one's too (only the plugin class is compiled again).
function(canonform_meshlab_flavour name)
  cmake_parse_arguments(F "INSTALLED;NO_TWIN;NO_PLUGINS" "COMMON;API;SCALAR;VERSION;DIR;OBJECTS_OF" "" ${ARGN})
  set_property(GLOBAL APPEND PROPERTY CANONFORM_MESHLAB_FLAVOURS ${name})
  foreach(k COMMON API SCALAR VERSION DIR INSTALLED NO_TWIN NO_PLUGINS OBJECTS_OF)
    set_property(GLOBAL PROPERTY CANONFORM_FLAVOUR_${name}_${k} "${F_${k}}")
  endforeach()
endfunction()

# canonform_flavour_get(VAR flavour KEY): KEY one of COMMON API SCALAR VERSION DIR INSTALLED PLUGINS
# (PLUGINS: the plugin targets made for it; WRONG_PRECISION: the twin built for the other precision).
function(canonform_flavour_get var name key)
  get_property(v GLOBAL PROPERTY CANONFORM_FLAVOUR_${name}_${key})
  set(${var} "${v}" PARENT_SCOPE)
endfunction()

# canonform_add_meshlab_plugin(NAME PLUGIN_CLASS ... SOURCES ... LIBRARIES ... [SCRIPTS ...]
#                              [INCLUDE_DIRS ...] [WRONG_PRECISION])
# Compiles plugin NAME (lib<NAME>.so) for every flavour: target NAME for the installed MeshLab,
# NAME_<flavour> for the others; the adapter of the flavour's API is linked in. The installed
# MeshLab's plugin and SCRIPTS (.mlx, for 2020.09's meshlabserver) are installed in component
# `plugins` (what tools/package.sh puts in the Debian package).
# PLUGIN_CLASS: the sources of the Qt plugin class (its .cpp includes its moc output, so that the
# class's MeshLab headers are compiled once). Only they depend on the flavour's version string (the
# class's getMLVersion(), from MeshLab's MESHLAB_PLUGIN_IID_EXPORTER), so only they are compiled
# for each plugin target; SOURCES are compiled once per flavour (object library NAME_<flavour>_objects,
# shared with an OBJECTS_OF flavour), the adapter once per flavour for every plugin
# (canonform_meshlab_glue_<flavour>).
# WRONG_PRECISION: for API 2022 and 2025 also a twin whose plugin class is compiled for the other
# precision (and that precision's version string), target NAME_<flavour>_wrong_precision in
# <DIR>/../wrong_precision: what a plugin built for the other host is to this one; the tests check
# that MeshLab's plugin manager refuses it, with its message. It is never applied.
function(canonform_add_meshlab_plugin name)
  cmake_parse_arguments(P "WRONG_PRECISION" "" "PLUGIN_CLASS;SOURCES;LIBRARIES;SCRIPTS;INCLUDE_DIRS" ${ARGN})
  set(glue "${PROJECT_SOURCE_DIR}/src/canonform/meshlab")  # the MeshLab glue both plugins share
  set(glue_headers "${glue}/meshlab_adapter.h" "${glue}/meshlab_adapter_common.h" "${glue}/vcg_bridge.h"
                   "${glue}/meshlab_document.h")
  get_property(flavours GLOBAL PROPERTY CANONFORM_MESHLAB_FLAVOURS)
  foreach(f ${flavours})
    foreach(k COMMON API SCALAR VERSION DIR INSTALLED NO_TWIN NO_PLUGINS OBJECTS_OF)
      canonform_flavour_get(${k} ${f} ${k})
    endforeach()
    if(NO_PLUGINS)
      continue()
    endif()
    if(API EQUAL 2020)
      set(adapter "${glue}/meshlab2020_adapter.cpp" "${glue}/meshlab2020_adapter.h")
    else()
      set(adapter "${glue}/meshlab2022_adapter.cpp" "${glue}/meshlab2022_adapter.h")
    endif()
    if(INSTALLED)
      set(target ${name})
    else()
      set(target ${name}_${f})
    endif()
    # The objects that do not depend on the version string: compiled with the COMMON of the flavour
    # they belong to (OBJECTS_OF's, if given).
    set(key ${f})
    set(key_common ${COMMON})
    if(OBJECTS_OF)
      set(key ${OBJECTS_OF})
      canonform_flavour_get(key_common ${OBJECTS_OF} COMMON)
    endif()
    set(glue_target canonform_meshlab_glue_${key})
    if(NOT TARGET ${glue_target})
      add_library(${glue_target} OBJECT ${adapter} ${glue_headers})
      set_target_properties(${glue_target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
      target_link_libraries(${glue_target} PRIVATE ${key_common} canonform::filter_table canonform::warnings)
    endif()
    set(objects ${name}_${key}_objects)
    if(NOT TARGET ${objects})
      add_library(${objects} OBJECT ${P_SOURCES})
      set_target_properties(${objects} PROPERTIES POSITION_INDEPENDENT_CODE ON)
      target_include_directories(${objects} PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}" ${P_INCLUDE_DIRS})
      target_link_libraries(${objects} PRIVATE ${key_common} canonform::filter_table ${P_LIBRARIES} canonform::warnings)
    endif()
    set(variants ${target})
    if(P_WRONG_PRECISION AND NOT API EQUAL 2020 AND NOT NO_TWIN)
      list(APPEND variants ${target}_wrong_precision)
    endif()
    foreach(t ${variants})
      add_library(${t} MODULE ${P_PLUGIN_CLASS} $<TARGET_OBJECTS:${objects}> $<TARGET_OBJECTS:${glue_target}>)
      set_target_properties(${t} PROPERTIES AUTOMOC ON PREFIX "lib" OUTPUT_NAME ${name})
      target_include_directories(${t} PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}" ${P_INCLUDE_DIRS})
      target_link_libraries(${t} PRIVATE ${COMMON} canonform::filter_table ${P_LIBRARIES} canonform::warnings)
    endforeach()
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY "${DIR}")
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
    set_property(GLOBAL APPEND PROPERTY CANONFORM_FLAVOUR_${f}_PLUGINS ${target})
    if(TARGET ${target}_wrong_precision)
      # The definitions are given again after the library's: the compiler takes the last -D. The
      # plugin class then disagrees with the objects it links about Scalarm, so it is not linked
      # with --no-undefined (the plugin manager refuses it before any of that is called).
      string(REGEX REPLACE "d$" "" float_version "${VERSION}")
      if(SCALAR STREQUAL "double")
        set(other float)
        set(other_version ${float_version})
      else()
        set(other double)
        set(other_version ${VERSION}d)
      endif()
      get_filename_component(wrong_dir "${DIR}/../wrong_precision" ABSOLUTE)
      set_target_properties(${target}_wrong_precision PROPERTIES LIBRARY_OUTPUT_DIRECTORY "${wrong_dir}")
      target_compile_options(${target}_wrong_precision PRIVATE -UMESHLAB_SCALAR -DMESHLAB_SCALAR=${other}
                                                               -UMESHLAB_VERSION -DMESHLAB_VERSION=${other_version})
      set_property(GLOBAL PROPERTY CANONFORM_FLAVOUR_${f}_WRONG_PRECISION ${target}_wrong_precision)
    endif()
    if(INSTALLED)
      add_library(canonform::${name} ALIAS ${target})
      install(TARGETS ${target} LIBRARY DESTINATION "${CANONFORM_PLUGIN_INSTALL_DIR}" COMPONENT plugins)
      if(API EQUAL 2020)  # meshlabserver scripts, next to the plugin
        foreach(s ${P_SCRIPTS})
          get_filename_component(script_name "${s}" NAME)
          configure_file("${CMAKE_CURRENT_SOURCE_DIR}/${s}" "${DIR}/${name}/${script_name}" COPYONLY)
          install(FILES "${CMAKE_CURRENT_SOURCE_DIR}/${s}" DESTINATION "${CANONFORM_PLUGIN_INSTALL_DIR}/${name}"
                  COMPONENT plugins)
        endforeach()
      endif()
    endif()
  endforeach()
endfunction()
