// SPDX-License-Identifier: GPL-3.0-or-later
// canonform Python module: the functions of each area, added to the module by module.cpp.
#pragma once

#include <pybind11/pybind11.h>

namespace canonform::python {

void bind_meshes(pybind11::module_& m);     // mesh_bindings.cpp
void bind_views(pybind11::module_& m);      // view_bindings.cpp
void bind_retrieval(pybind11::module_& m);  // retrieval_bindings.cpp

}  // namespace canonform::python
