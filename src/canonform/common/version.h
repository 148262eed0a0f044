// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the project's version, from the one number in CMakeLists.txt's project() (passed to
// every target as CANONFORM_VERSION by src/CMakeLists.txt). `canonform --version`, the filters' log,
// the packages and the documentation show it.
#pragma once

#ifndef CANONFORM_VERSION
#error \
    "CANONFORM_VERSION is not defined: link canonform::common (src/CMakeLists.txt defines it from project())"
#endif

namespace canonform {

/// The version, "MAJOR.MINOR.PATCH" (CMake's PROJECT_VERSION).
inline const char* version() {
    return CANONFORM_VERSION;
}

}  // namespace canonform
