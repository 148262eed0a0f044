# MeshLab 2022.02 for the pymeshlab 2022.2 plugins (option CANONFORM_MESHLAB2022).
#
# pymeshlab 2022.2.x is MeshLab 2022.02's meshlab-common built with MESHLAB_SCALAR=double. No
# Debian release packages that library, so it is compiled here, in our build tree, from Debian's
# source package meshlab=2022.02+dfsg1-1 that tools/setup.sh unpacks into external/ (never
# committed): target meshlab2022::common, the library libmeshlab-common.so in
# <build>/meshlab2022/lib, double precision, version string "2022.02d" as upstream's CMake makes
# it for a double build. Only meshlab-common is built (its sources are listed below, as in
# src/common/CMakeLists.txt of that release); none of MeshLab's own plugins or programs.
#
# canonform_add_meshlab2022_plugin(NAME SOURCES ... LIBRARIES ... [SCALAR float|double]
#                                  [OUTPUT_DIR dir]) then builds a filter plugin that MeshLab
# 2022.02's PluginManager (and so pymeshlab's load_plugin) accepts.

set(MESHLAB2022_SOURCE_DIR "${PROJECT_SOURCE_DIR}/external/meshlab-2022.02" CACHE PATH
    "MeshLab 2022.02 source tree (Debian source package meshlab=2022.02+dfsg1-1)")
set(MESHLAB2022_SCALAR double)  # pymeshlab 2022.2's precision (a float build is what it refuses)

set(_ml22 "${MESHLAB2022_SOURCE_DIR}/src")
if(NOT EXISTS "${_ml22}/common/plugins/interfaces/filter_plugin.h" OR NOT EXISTS "${_ml22}/vcglib/vcg/complex/complex.h")
  message(FATAL_ERROR "MeshLab 2022.02 source not found under MESHLAB2022_SOURCE_DIR=${MESHLAB2022_SOURCE_DIR}.\n"
                      "Run tools/setup.sh (fetches Debian's meshlab 2022.02+dfsg1-1 source package into external/) "
                      "or configure with -DCANONFORM_MESHLAB2022=OFF.")
endif()

find_package(Qt5 5.15 COMPONENTS Core Gui Widgets OpenGL Xml Network REQUIRED)
find_package(GLEW REQUIRED)
set(OpenGL_GL_PREFERENCE LEGACY)  # as MeshLab's own build
find_package(OpenGL REQUIRED)

file(READ "${MESHLAB2022_SOURCE_DIR}/ML_VERSION" _ml22_version)
string(STRIP "${_ml22_version}" _ml22_version)
if(NOT _ml22_version STREQUAL "2022.02")
  message(FATAL_ERROR "${MESHLAB2022_SOURCE_DIR} is MeshLab ${_ml22_version}, not 2022.02")
endif()
set(MESHLAB2022_VERSION "${_ml22_version}d")  # upstream appends "d" to a double build's version
set(MESHLAB2022_OUTPUT_DIR "${CMAKE_BINARY_DIR}/meshlab2022")
message(STATUS "canonform: MeshLab ${MESHLAB2022_VERSION} meshlab-common (MESHLAB_SCALAR=${MESHLAB2022_SCALAR}) "
               "from ${MESHLAB2022_SOURCE_DIR}")

# meshlab-common's one bundled dependency (EasyExif), as src/external/easyexif.cmake builds it.
add_library(meshlab2022_exif STATIC "${_ml22}/external/easyexif/exif.cpp")
target_include_directories(meshlab2022_exif SYSTEM PUBLIC "${_ml22}/external/easyexif")
target_compile_options(meshlab2022_exif PRIVATE -w)

set(_ml22_common_sources
  ml_document/helpers/mesh_document_state_data.cpp
  ml_document/cmesh.cpp
  ml_document/mesh_document.cpp
  ml_document/mesh_model.cpp
  ml_document/mesh_model_state.cpp
  ml_document/raster_model.cpp
  ml_document/render_raster.cpp
  ml_shared_data_context/ml_plugin_gl_context.cpp
  ml_shared_data_context/ml_scene_gl_shared_data_context.cpp
  ml_shared_data_context/ml_shared_data_context.cpp
  parameters/rich_parameter.cpp
  parameters/rich_parameter_list.cpp
  parameters/value.cpp
  plugins/containers/decorate_plugin_container.cpp
  plugins/containers/edit_plugin_container.cpp
  plugins/containers/filter_plugin_container.cpp
  plugins/containers/io_plugin_container.cpp
  plugins/containers/render_plugin_container.cpp
  plugins/interfaces/meshlab_plugin_logger.cpp
  plugins/interfaces/decorate_plugin.cpp
  plugins/interfaces/filter_plugin.cpp
  plugins/interfaces/io_plugin.cpp
  plugins/action_searcher.cpp
  plugins/meshlab_plugin_type.cpp
  plugins/plugin_manager.cpp
  python/function.cpp
  python/function_parameter.cpp
  python/function_set.cpp
  python/python_utils.cpp
  utilities/eigen_mesh_conversions.cpp
  utilities/load_save.cpp
  globals.cpp
  GLExtensionsManager.cpp
  GLLogStream.cpp
  filterscript.cpp
  ml_selection_buffers.cpp
  ml_thread_safe_memory_info.cpp
  mlapplication.cpp
  meshlab-common.qrc)
list(TRANSFORM _ml22_common_sources PREPEND "${_ml22}/common/")
add_library(meshlab_common_2022 SHARED ${_ml22_common_sources})
add_library(meshlab2022::common ALIAS meshlab_common_2022)
set_target_properties(meshlab_common_2022 PROPERTIES
  OUTPUT_NAME meshlab-common AUTOMOC ON AUTORCC ON
  LIBRARY_OUTPUT_DIRECTORY "${MESHLAB2022_OUTPUT_DIR}/lib")
target_compile_definitions(meshlab_common_2022 PUBLIC
  MESHLAB_VERSION=${MESHLAB2022_VERSION} MESHLAB_SCALAR=${MESHLAB2022_SCALAR} CANONFORM_MESHLAB_API=2022)
target_include_directories(meshlab_common_2022 SYSTEM PUBLIC "${_ml22}" "${_ml22}/vcglib")
target_compile_options(meshlab_common_2022 PRIVATE -w)  # third-party code: its warnings are not ours
target_link_libraries(meshlab_common_2022
  PUBLIC Qt5::Core Qt5::Gui Qt5::OpenGL Qt5::Widgets Qt5::Xml Qt5::Network GLEW::GLEW OpenGL::GL Eigen3::Eigen
  PRIVATE meshlab2022_exif)
target_link_options(meshlab_common_2022 PRIVATE -Wl,--no-undefined)

set(CANONFORM_PLUGIN2022_DIR "${MESHLAB2022_OUTPUT_DIR}/plugins" CACHE INTERNAL "")

# canonform_add_meshlab2022_plugin(target OUTPUT_NAME name SOURCES ... LIBRARIES ...
#                                  [SCALAR_OVERRIDE float] [OUTPUT_DIR dir])
# SCALAR_OVERRIDE compiles the plugin's own code for another precision than the library (only to
# show that MeshLab's PluginManager refuses such a plugin; it is never applied).
set(CANONFORM_GLUE2022_SOURCES
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab2022_adapter.cpp"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab2022_adapter.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab_adapter_common.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab_adapter.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/vcg_bridge.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab_document.h")
function(canonform_add_meshlab2022_plugin target)
  cmake_parse_arguments(P "" "OUTPUT_NAME;SCALAR_OVERRIDE;OUTPUT_DIR" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT P_OUTPUT_DIR)
    set(P_OUTPUT_DIR "${CANONFORM_PLUGIN2022_DIR}")
  endif()
  add_library(${target} MODULE ${P_SOURCES} ${CANONFORM_GLUE2022_SOURCES})
  set_target_properties(${target} PROPERTIES AUTOMOC ON PREFIX "lib" OUTPUT_NAME "${P_OUTPUT_NAME}"
                                             LIBRARY_OUTPUT_DIRECTORY "${P_OUTPUT_DIR}")
  target_include_directories(${target} PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}")
  target_link_libraries(${target} PRIVATE meshlab2022::common canonform::filter_table ${P_LIBRARIES} canonform::warnings)
  if(P_SCALAR_OVERRIDE)
    # The definition is given again after the library's: the compiler takes the last -D.
    target_compile_options(${target} PRIVATE -UMESHLAB_SCALAR -DMESHLAB_SCALAR=${P_SCALAR_OVERRIDE})
  else()
    target_link_options(${target} PRIVATE -Wl,--no-undefined)
  endif()
endfunction()
