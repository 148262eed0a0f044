// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: MeshLab's document types (MeshDocument, MeshModel, CMeshO) for the API being built.
// The actions (filter_actions.cpp, view_actions.cpp) are one source for both APIs; only the
// header differs: 2020.09 has common/meshmodel.h, 2022.02 common/ml_document/. Scalars follow
// MESHLAB_SCALAR (float for 2020.09, double for pymeshlab 2022.2): the actions convert through
// vcg_bridge.h, which reads and writes the mesh's own scalar types.
#pragma once

#if defined(CANONFORM_MESHLAB_API) && CANONFORM_MESHLAB_API >= 2022
#include <common/ml_document/mesh_document.h>
#else
#include <common/meshmodel.h>
#endif
