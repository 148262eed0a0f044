// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the adapter from a filter table (filter_table.h) to MeshLab 2020.09's plugin API
// (MeshFilterInterface). Each plugin is a subclass that names its table and its apply function
// and adds Qt's plugin metadata; everything else - names, classes, requirements, parameters,
// errorMessage + Log() on failure, progress - is done here once for all plugins. MeshLab
// 2022.02's FilterPlugin API (pymeshlab 2022.2) has the sibling meshlab2022_adapter.h over the
// same tables and actions; what both share is in meshlab_adapter_common.h (TableAdapter).
#pragma once

#include <common/interfaces.h>

#include "canonform/meshlab/meshlab_adapter_common.h"

class TableFilterPlugin2020 : public canonform::meshlab::TableAdapter<MeshFilterInterface> {
public:
    using TableAdapter::TableAdapter;

    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* a) override;
    FILTER_ARITY filterArity(QAction*) const override { return SINGLE_MESH; }
    int getRequirements(QAction* a) override;
    int getPreConditions(QAction*) const override { return MeshModel::MM_NONE; }
    int postCondition(QAction* a) const override;
    void initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) override;
    bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                     vcg::CallBackPos* cb) override;
};
