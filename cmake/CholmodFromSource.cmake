# SPDX-License-Identifier: GPL-3.0-or-later
# CHOLMOD for a build that cannot link the system's (the Windows cross build): its simplicial
# LDL^T - the part numerics/sparse_cholesky.cpp calls - compiled from Debian's suitesparse source
# package (the version of the host's libsuitesparse-dev, so that the factor, and with it every
# canonical form, is the same to the bit as the Linux build's; docs/install.md, "Windows").
# tools/setup.sh fetches the source into external/suitesparse/ (only SuiteSparse_config, AMD, COLAMD
# and CHOLMOD). Compiled: CHOLMOD's Core and Cholesky modules (32-bit integer versions) with AMD
# and COLAMD, without the Supernodal, Partition (METIS), Modify, MatrixOps and Check modules
# (-DNSUPERNODAL ...), hence without BLAS, LAPACK and METIS.
#   canonform_cholmod_from_source(SOURCE_DIR) -> static library canonform_cholmod (target); the
#   C language must be enabled (CMakeLists.txt does for Windows)
function(canonform_cholmod_from_source src)
  foreach(f SuiteSparse_config/SuiteSparse_config.c AMD/Source/amd_order.c COLAMD/Source/colamd.c
            CHOLMOD/Cholesky/cholmod_analyze.c CHOLMOD/Include/cholmod.h)
    if(NOT EXISTS "${src}/${f}")
      message(FATAL_ERROR "CHOLMOD source: ${src}/${f} missing (tools/setup.sh fetches Debian's suitesparse source)")
    endif()
  endforeach()
  if(NOT CMAKE_C_COMPILER_LOADED)
    message(FATAL_ERROR "CHOLMOD from source needs the C language (enable_language(C) in the top CMakeLists.txt)")
  endif()
  set(amd aat 1 2 dump postorder defaults post_tree order control info valid preprocess)
  set(core aat add band change_factor common complex copy dense error factor memory sparse transpose triplet version)
  set(cholesky amd analyze colamd etree factorize postorder rcond resymbol rowcolcounts rowfac solve spsolve)
  set(sources "${src}/SuiteSparse_config/SuiteSparse_config.c" "${src}/COLAMD/Source/colamd.c")
  foreach(f ${amd})
    list(APPEND sources "${src}/AMD/Source/amd_${f}.c")
  endforeach()
  foreach(f ${core})
    list(APPEND sources "${src}/CHOLMOD/Core/cholmod_${f}.c")
  endforeach()
  foreach(f ${cholesky})
    list(APPEND sources "${src}/CHOLMOD/Cholesky/cholmod_${f}.c")
  endforeach()
  add_library(canonform_cholmod STATIC ${sources})
  # AMD's sources are compiled once per integer type; DINT: the int version CHOLMOD's int calls use.
  foreach(f ${amd})
    set_source_files_properties("${src}/AMD/Source/amd_${f}.c" PROPERTIES COMPILE_DEFINITIONS DINT)
  endforeach()
  target_compile_definitions(canonform_cholmod PRIVATE NSUPERNODAL NPARTITION NCAMD NMODIFY NMATRIXOPS NCHECK NTIMER
                                                       NPRINT)
  target_include_directories(canonform_cholmod SYSTEM PUBLIC "$<BUILD_INTERFACE:${src}/CHOLMOD/Include>"
                                                             "$<BUILD_INTERFACE:${src}/SuiteSparse_config>"
                                                      PRIVATE "${src}/AMD/Include" "${src}/COLAMD/Include")
  target_compile_options(canonform_cholmod PRIVATE -w)  # third-party code: its warnings are not ours
endfunction()
