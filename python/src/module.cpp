// SPDX-License-Identifier: GPL-3.0-or-later
// canonform Python module (`import canonform`): the library with numpy arrays in and out.
// The package's __init__.py re-exports everything defined here; docs/python.md is the user's page.
#include "bindings.h"
#include "support.h"

#include "canonform/views/opencv_sift.h"

#ifndef CANONFORM_VERSION
#error "CANONFORM_VERSION must be defined (python/CMakeLists.txt)"
#endif

PYBIND11_MODULE(_canonform, m) {
    namespace py = pybind11;
    m.doc() = "canonform: Euclidean canonical forms of non-rigid meshes (Pickup et al. 2015) and view-based "
              "shape retrieval, with numpy arrays in and out.";
    m.attr("__version__") = CANONFORM_VERSION;
    canonform::python::register_errors(m);
    canonform::python::bind_meshes(m);
    // The `opencv` SIFT extractor lives in a library of its own (sift_features.h); the module carries it.
    canonform::views::register_opencv_sift();
    canonform::python::bind_views(m);
    canonform::python::bind_retrieval(m);
}
