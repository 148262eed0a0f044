// canonform: the filter_canonical plugin for MeshLab 2020.09 (MeshFilterInterface).
//
// A thin adapter: names, classes and parameters come from filter_table.h, the work is done by
// filter_actions.h; this file only translates between them and MeshLab 2020.09's API (rich
// parameters, errorMessage + Log() on failure, the progress callback).
#pragma once

#include <common/interfaces.h>

class FilterCanonicalPlugin : public QObject, public MeshFilterInterface {
    Q_OBJECT
    MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
    Q_INTERFACES(MeshFilterInterface)

public:
    FilterCanonicalPlugin();

    QString pluginName() const override;
    QString filterName(FilterIDType filter) const override;
    QString filterInfo(FilterIDType filter) const override;
    FilterClass getClass(QAction* a) override;
    FILTER_ARITY filterArity(QAction*) const override { return SINGLE_MESH; }
    int getRequirements(QAction* a) override;
    int getPreConditions(QAction*) const override { return MeshModel::MM_NONE; }
    int postCondition(QAction* a) const override;
    void initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) override;
    bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb) override;
};
