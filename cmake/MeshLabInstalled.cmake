# SPDX-License-Identifier: GPL-3.0-or-later
# The MeshLab the system has installed (Debian's `meshlab` package), as the target
# meshlab_installed::common: its own libmeshlab-common.so, with the headers of the same release
# from Debian's source package (external/, fetched by tools/setup.sh), in single precision as
# Debian builds it.
#
#   MeshLab   Debian            plugin API                         headers
#   2020.09   bookworm          MeshFilterInterface (interfaces.h) external/meshlab-2020.09
#   2022.02   trixie            FilterPlugin                       external/meshlab-2022.02/src
#   2025.07   forky, sid        FilterPlugin (headers split)       external/meshlab-2025.07/src
#
# Sets CANONFORM_MESHLAB_INSTALLED (2020.09, 2022.02 or 2025.07) and CANONFORM_VCGLIB_DIR (the vcglib
# of that source tree, which the core and the tool also use).
# ABI: MESHLAB_SCALAR=float (a double plugin loads, then crashes in 2020.09; 2022.02 and later refuse
# it), MESHLAB_VERSION = the release (the plugin manager compares its first 6 characters), gnu++14
# or later, Qt5, GLEW; the plugin MODULE links the installed library with -Wl,--no-undefined.

set(CANONFORM_MESHLAB_HOST "auto" CACHE STRING
    "Installed MeshLab to build plugins for: auto (the version of Debian's meshlab package), 2020.09, 2022.02, 2025.07")
set(MESHLAB_LIBRARY_DIR "/usr/lib/x86_64-linux-gnu/meshlab" CACHE PATH
    "Directory of the installed MeshLab's libmeshlab-common.so and plugins/")

set(_ml_version "${CANONFORM_MESHLAB_HOST}")
if(_ml_version STREQUAL "auto")
  execute_process(COMMAND dpkg-query -W -f=\${Version} meshlab OUTPUT_VARIABLE _ml_deb RESULT_VARIABLE _ml_rc ERROR_QUIET)
  if(NOT _ml_rc EQUAL 0)
    message(FATAL_ERROR "Debian's meshlab package is not installed: run tools/setup.sh, or configure with "
                        "-DCANONFORM_BUILD_PLUGINS=OFF")
  endif()
  string(REGEX REPLACE "^([0-9]+:)?([0-9]+\\.[0-9]+).*" "\\2" _ml_version "${_ml_deb}")
  message(STATUS "canonform: installed MeshLab ${_ml_version} (Debian package ${_ml_deb})")
endif()
set(CANONFORM_MESHLAB_INSTALLED "${_ml_version}")

if(_ml_version STREQUAL "2020.09")
  set(MESHLAB_SOURCE_DIR "${PROJECT_SOURCE_DIR}/external/meshlab-2020.09" CACHE PATH
      "MeshLab 2020.09 source tree (Debian source package meshlab=2020.09+dfsg1-2): headers and vcglib")
  set(_ml_src "${MESHLAB_SOURCE_DIR}")
  set(_ml_includes "${_ml_src}/src" "${_ml_src}/src/common" "${_ml_src}/vcglib")
  set(CANONFORM_VCGLIB_DIR "${_ml_src}/vcglib")
  set(_ml_check "${_ml_src}/src/common/interfaces.h")
  set(_ml_api 2020)
  find_package(Qt5 COMPONENTS Core Gui Widgets OpenGL Xml REQUIRED)
elseif(_ml_version STREQUAL "2022.02" OR _ml_version STREQUAL "2025.07")
  set(MESHLAB${_ml_version}_SOURCE_DIR "${PROJECT_SOURCE_DIR}/external/meshlab-${_ml_version}" CACHE PATH
      "MeshLab ${_ml_version} source tree (Debian's source package): headers and vcglib")
  set(_ml_src "${MESHLAB${_ml_version}_SOURCE_DIR}")
  set(_ml_includes "${_ml_src}/src" "${_ml_src}/src/vcglib")
  set(CANONFORM_VCGLIB_DIR "${_ml_src}/src/vcglib")
  set(_ml_check "${_ml_src}/src/common/plugins/interfaces/filter_plugin.h")
  string(SUBSTRING "${_ml_version}" 0 4 _ml_api)
  find_package(Qt5 5.15 COMPONENTS Core Gui Widgets OpenGL Xml Network REQUIRED)
else()
  message(FATAL_ERROR "MeshLab ${_ml_version}: this project has plugins for MeshLab 2020.09, 2022.02 and 2025.07 "
                      "(set CANONFORM_MESHLAB_HOST, or -DCANONFORM_BUILD_PLUGINS=OFF)")
endif()
if(NOT EXISTS "${_ml_check}")
  message(FATAL_ERROR "MeshLab ${_ml_version}'s headers not found (${_ml_check}): run tools/setup.sh, which fetches "
                      "Debian's source package of the installed MeshLab into external/")
endif()
find_package(GLEW REQUIRED)
set(OpenGL_GL_PREFERENCE LEGACY)  # as MeshLab's own build
find_package(OpenGL REQUIRED)
find_library(MESHLAB_COMMON_LIBRARY meshlab-common PATHS "${MESHLAB_LIBRARY_DIR}" NO_DEFAULT_PATH)
if(NOT MESHLAB_COMMON_LIBRARY)
  message(FATAL_ERROR "libmeshlab-common.so not found in ${MESHLAB_LIBRARY_DIR}: install Debian's meshlab package (tools/setup.sh)")
endif()

if(NOT TARGET meshlab_installed_common)
  add_library(meshlab_installed_common SHARED IMPORTED GLOBAL)
  set_target_properties(meshlab_installed_common PROPERTIES IMPORTED_LOCATION "${MESHLAB_COMMON_LIBRARY}"
                                                            IMPORTED_NO_SONAME TRUE)
  target_include_directories(meshlab_installed_common SYSTEM INTERFACE ${_ml_includes})
  target_compile_definitions(meshlab_installed_common INTERFACE MESHLAB_SCALAR=float CANONFORM_MESHLAB_API=${_ml_api})
  target_link_libraries(meshlab_installed_common INTERFACE Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml
                                                           GLEW::GLEW OpenGL::GL Eigen3::Eigen)
  if(NOT _ml_api EQUAL 2020)  # 2020.09 has no version check (and defines its own MESHLAB_VERSION)
    target_compile_definitions(meshlab_installed_common INTERFACE MESHLAB_VERSION=${_ml_version})
    target_link_libraries(meshlab_installed_common INTERFACE Qt5::Network)
  endif()
  add_library(meshlab_installed::common ALIAS meshlab_installed_common)
endif()
message(STATUS "canonform: plugins for the installed MeshLab ${_ml_version} (float, ${MESHLAB_COMMON_LIBRARY}), "
               "headers from ${_ml_src}")

set(CANONFORM_MESHLAB_API ${_ml_api})  # of the installed MeshLab: 2020, 2022 or 2025
canonform_meshlab_flavour(meshlab${_ml_api}
  COMMON meshlab_installed::common API ${_ml_api} SCALAR float VERSION ${_ml_version}
  DIR "${CMAKE_BINARY_DIR}/meshlab/plugins" INSTALLED)
