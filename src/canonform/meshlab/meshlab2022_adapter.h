// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the adapter from a filter table (filter_table.h) to the FilterPlugin API (IID
// "vcg.meshlab.FilterPlugin/1.0") of MeshLab 2022.02 and 2025.07 and of pymeshlab 2022.2.x and
// 2025.7.x; it compiles unchanged against both releases' headers (2025.07 split and renamed some
// parameter headers and classes, none of which it names). The sibling
// of meshlab2020_adapter.h over the same tables and the same actions: names and Python names,
// classes, requirements, parameters (RichParameterList built from the table), progress, log.
// Differences of this API: applyFilter returns the action's outputs as a map of QVariants (which
// pymeshlab returns to Python as a dict), and a failure is an MLException carrying the reason.
#pragma once

#include <common/plugins/interfaces/filter_plugin.h>

#include "canonform/meshlab/meshlab_adapter_common.h"

namespace canonform::meshlab {
/// The outputs of an action as pymeshlab converts them to Python: int, double and bool QVariants,
/// vectors as Eigen::VectorXd (a flat numpy array: pymeshlab 2022.2 and 2025.7 convert 1-D only).
std::map<std::string, QVariant> to_qvariant_map(const ActionOutputs& outputs);
}  // namespace canonform::meshlab

class TableFilterPlugin2022 : public canonform::meshlab::TableAdapter<FilterPlugin> {
public:
    using TableAdapter::TableAdapter;

    QString vendor() const override { return QStringLiteral("canonform"); }
    QString filterName(ActionIDType filter) const override;
    QString pythonFilterName(ActionIDType filter) const override;
    QString filterInfo(ActionIDType filter) const override;
    FilterClass getClass(const QAction* a) const override;
    FilterArity filterArity(const QAction*) const override { return SINGLE_MESH; }
    int getRequirements(const QAction* a) override;
    int getPreConditions(const QAction*) const override { return MeshModel::MM_NONE; }
    int postCondition(const QAction* a) const override;
    RichParameterList initParameterList(const QAction* a, const MeshModel& m) override;
    std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par,
                                                MeshDocument& md, unsigned int& postConditionMask,
                                                vcg::CallBackPos* cb) override;
};
