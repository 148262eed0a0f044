// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/meshlab/meshlab2020_adapter.h"

#include "canonform/meshlab/meshlab_adapter_common.h"

using canonform::meshlab::FilterKind;
using canonform::meshlab::FilterSpec;
using canonform::meshlab::mesh_mask;

QString TableFilterPlugin2020::filterName(FilterIDType filter) const {
    return QString::fromStdString(spec(filter).name);
}

QString TableFilterPlugin2020::filterInfo(FilterIDType filter) const {
    return QString::fromStdString(spec(filter).info);
}

MeshFilterInterface::FilterClass TableFilterPlugin2020::getClass(QAction* a) {
    return canonform::meshlab::filter_class<MeshFilterInterface>(spec(ID(a)).kind);
}

int TableFilterPlugin2020::getRequirements(QAction* a) {
    return mesh_mask<MeshModel>(spec(ID(a)).needs);
}

int TableFilterPlugin2020::postCondition(QAction* a) const {
    return mesh_mask<MeshModel>(spec(ID(a)).changes);
}

void TableFilterPlugin2020::initParameterSet(QAction* a, MeshModel&, RichParameterList& par) {
    canonform::meshlab::add_params(spec(ID(a)), par);
}

bool TableFilterPlugin2020::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                        vcg::CallBackPos* cb) {
    const FilterSpec& s = spec(ID(a));
    const canonform::meshlab::ParamValues values = canonform::meshlab::read_params(s, par);
    canonform::meshlab::ActionContext ctx;
    ctx.log = [this](const std::string& line) { Log("%s", line.c_str()); };
    ctx.progress = canonform::meshlab::progress_to(cb);
    Log("%s", canonform::meshlab::log_header(s).c_str());
    try {
        apply_(s.id, md, values, ctx);
        return true;
    } catch (const std::exception& e) {
        errorMessage = QString("%1: %2").arg(QString::fromStdString(s.name), QString::fromUtf8(e.what()));
        Log("%s failed: %s", s.name.c_str(), e.what());
        return false;
    }
}
