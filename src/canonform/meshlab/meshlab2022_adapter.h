// canonform: the adapter from a filter table (filter_table.h) to MeshLab 2022.02's plugin API
// (FilterPlugin, IID "vcg.meshlab.FilterPlugin/1.0"), the API of pymeshlab 2022.2.x. The sibling
// of meshlab2020_adapter.h over the same tables and the same actions: names and Python names,
// classes, requirements, parameters (RichParameterList built from the table), progress, log.
// Differences of this API: applyFilter returns the action's outputs as a map of QVariants (which
// pymeshlab returns to Python as a dict), and a failure is an MLException carrying the reason.
#pragma once

#include "canonform/meshlab/filter_table.h"

#include <common/plugins/interfaces/filter_plugin.h>

namespace canonform::plugin {
/// Applies filter `id` of a table to the document (throws on failure, document unchanged).
using ApplyFn = ActionOutputs (*)(int id, MeshDocument& md, const ParamValues& params,
                                  const ActionContext& context);

/// The outputs of an action as pymeshlab 2022.2 converts them to Python: int, double and bool
/// QVariants, vectors as Eigen::VectorXd (a numpy array).
std::map<std::string, QVariant> to_qvariant_map(const ActionOutputs& outputs);
}  // namespace canonform::plugin

class TableFilterPlugin2022 : public QObject, public FilterPlugin {
public:
    TableFilterPlugin2022(QString plugin_name, const std::vector<canonform::plugin::FilterSpec>& table,
                          canonform::plugin::ApplyFn apply);

    QString pluginName() const override { return name_; }
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
    std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par, MeshDocument& md,
                                                unsigned int& postConditionMask, vcg::CallBackPos* cb) override;

private:
    const canonform::plugin::FilterSpec& spec(ActionIDType id) const;
    QString name_;
    const std::vector<canonform::plugin::FilterSpec>& table_;
    canonform::plugin::ApplyFn apply_;
};
