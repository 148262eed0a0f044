// canonform: the adapter from a filter table (filter_table.h) to MeshLab 2020.09's plugin API
// (MeshFilterInterface). Each plugin is a subclass that names its table and its apply function
// and adds Qt's plugin metadata; everything else - names, classes, requirements, parameters,
// errorMessage + Log() on failure, progress - is done here once for all plugins. MeshLab
// 2022.02's FilterPlugin API (pymeshlab 2022.2) has the sibling meshlab2022_adapter.h over the
// same tables and actions; what both share is in meshlab_adapter_common.h.
#pragma once

#include "canonform/meshlab/filter_table.h"

#include <common/interfaces.h>

namespace canonform::plugin {
/// Applies filter `id` of a table to the document (throws on failure, document unchanged).
using ApplyFn = ActionOutputs (*)(int id, MeshDocument& md, const ParamValues& params,
                                  const ActionContext& context);
}  // namespace canonform::plugin

class TableFilterPlugin2020 : public QObject, public MeshFilterInterface {
public:
    TableFilterPlugin2020(QString plugin_name, const std::vector<canonform::plugin::FilterSpec>& table,
                          canonform::plugin::ApplyFn apply);

    QString pluginName() const override { return name_; }
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* a) override;
    FILTER_ARITY filterArity(QAction*) const override { return SINGLE_MESH; }
    int getRequirements(QAction* a) override;
    int getPreConditions(QAction*) const override { return MeshModel::MM_NONE; }
    int postCondition(QAction* a) const override;
    void initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) override;
    bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;

private:
    const canonform::plugin::FilterSpec& spec(FilterIDType id) const;
    QString name_;
    const std::vector<canonform::plugin::FilterSpec>& table_;
    canonform::plugin::ApplyFn apply_;
};
