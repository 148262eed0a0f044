# Building a filter plugin that the installed MeshLab 2020.09 (Debian's `meshlab` package) loads.
# ABI facts: MESHLAB_SCALAR=float, gnu++14 or later, Qt5, GLEW,
# link the MODULE against the installed libmeshlab-common.so with -Wl,--no-undefined.

find_package(Qt5 COMPONENTS Core Gui Widgets OpenGL Xml REQUIRED)
find_package(GLEW REQUIRED)
find_package(OpenGL REQUIRED)

if(NOT EXISTS "${MESHLAB_SOURCE_DIR}/src/common/interfaces.h")
  message(FATAL_ERROR "MeshLab headers not found under MESHLAB_SOURCE_DIR=${MESHLAB_SOURCE_DIR}; run tools/setup.sh")
endif()
find_library(MESHLAB_COMMON_LIBRARY meshlab-common PATHS "${MESHLAB_LIBRARY_DIR}" NO_DEFAULT_PATH)
if(NOT MESHLAB_COMMON_LIBRARY)
  message(FATAL_ERROR "libmeshlab-common.so not found in ${MESHLAB_LIBRARY_DIR}: install Debian's meshlab package (tools/setup.sh)")
endif()

if(NOT TARGET meshlab_common_2020)
  add_library(meshlab_common_2020 SHARED IMPORTED GLOBAL)
  set_target_properties(meshlab_common_2020 PROPERTIES IMPORTED_LOCATION "${MESHLAB_COMMON_LIBRARY}"
                                                       IMPORTED_NO_SONAME TRUE)
  target_include_directories(meshlab_common_2020 SYSTEM INTERFACE
    "${MESHLAB_SOURCE_DIR}/src" "${MESHLAB_SOURCE_DIR}/src/common" "${MESHLAB_SOURCE_DIR}/vcglib")
  target_compile_definitions(meshlab_common_2020 INTERFACE MESHLAB_SCALAR=float CANONFORM_MESHLAB_API=2020)
  target_link_libraries(meshlab_common_2020 INTERFACE Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml
                                                      GLEW::GLEW OpenGL::GL)
  add_library(meshlab::common ALIAS meshlab_common_2020)
endif()

set(CANONFORM_PLUGIN_DIR "${CMAKE_BINARY_DIR}/meshlab/plugins" CACHE INTERNAL "")
set(CANONFORM_PLUGIN_INSTALL_DIR "lib/x86_64-linux-gnu/meshlab/plugins" CACHE STRING
    "Plugin directory relative to the install prefix (MeshLab searches <bin>/../lib/x86_64-linux-gnu/meshlab/plugins)")

# The MeshLab glue every 2020.09 plugin is built with: the table-driven MeshFilterInterface adapter.
set(CANONFORM_GLUE2020_SOURCES
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab2020_adapter.cpp"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab2020_adapter.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab_adapter_common.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab_adapter.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/vcg_bridge.h"
  "${PROJECT_SOURCE_DIR}/src/canonform/meshlab/meshlab_document.h")

# canonform_add_meshlab_plugin(NAME SOURCES ... LIBRARIES ... SCRIPTS ...): the plugin's own
# sources (table, actions, plugin class) plus the shared glue, against MeshLab 2020.09.
function(canonform_add_meshlab_plugin name)
  cmake_parse_arguments(P "" "" "SOURCES;LIBRARIES;SCRIPTS" ${ARGN})
  add_library(${name} MODULE ${P_SOURCES} ${CANONFORM_GLUE2020_SOURCES})
  add_library(canonform::${name} ALIAS ${name})
  set_target_properties(${name} PROPERTIES AUTOMOC ON PREFIX "lib"
                                           LIBRARY_OUTPUT_DIRECTORY "${CANONFORM_PLUGIN_DIR}")
  target_include_directories(${name} PRIVATE "${CMAKE_CURRENT_SOURCE_DIR}")
  target_link_libraries(${name} PRIVATE meshlab::common canonform::filter_table ${P_LIBRARIES} canonform::warnings)
  target_link_options(${name} PRIVATE -Wl,--no-undefined)
  install(TARGETS ${name} LIBRARY DESTINATION "${CANONFORM_PLUGIN_INSTALL_DIR}")
  foreach(s ${P_SCRIPTS})
    get_filename_component(script_name "${s}" NAME)
    configure_file("${CMAKE_CURRENT_SOURCE_DIR}/${s}" "${CANONFORM_PLUGIN_DIR}/${name}/${script_name}" COPYONLY)
    install(FILES "${CMAKE_CURRENT_SOURCE_DIR}/${s}" DESTINATION "${CANONFORM_PLUGIN_INSTALL_DIR}/${name}")
  endforeach()
endfunction()
