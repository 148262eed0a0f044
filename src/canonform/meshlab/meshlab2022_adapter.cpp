// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/meshlab/meshlab2022_adapter.h"

#include "canonform/meshlab/meshlab_adapter_common.h"

#include <QStringList>

#include <Eigen/Core>

#include <type_traits>
#include <variant>

using canonform::meshlab::FilterKind;
using canonform::meshlab::FilterSpec;
using canonform::meshlab::mesh_mask;

std::map<std::string, QVariant> canonform::meshlab::to_qvariant_map(const ActionOutputs& outputs) {
    std::map<std::string, QVariant> out;
    for (const auto& [name, value] : outputs) {
        out[name] = std::visit(
            [](const auto& v) -> QVariant {
                using T = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<T, std::vector<double>>) {
                    const Eigen::VectorXd e =
                        Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
                    return QVariant::fromValue(e);
                } else {
                    return QVariant(v);
                }
            },
            value);
    }
    return out;
}

QString TableFilterPlugin2022::filterName(ActionIDType filter) const {
    return QString::fromStdString(spec(filter).name);
}

QString TableFilterPlugin2022::pythonFilterName(ActionIDType filter) const {
    return QString::fromStdString(spec(filter).python_name);
}

QString TableFilterPlugin2022::filterInfo(ActionIDType filter) const {
    return QString::fromStdString(spec(filter).info);
}

FilterPlugin::FilterClass TableFilterPlugin2022::getClass(const QAction* a) const {
    return canonform::meshlab::filter_class<FilterPlugin>(spec(ID(a)).kind);
}

int TableFilterPlugin2022::getRequirements(const QAction* a) {
    return mesh_mask<MeshModel>(spec(ID(a)).needs);
}

int TableFilterPlugin2022::postCondition(const QAction* a) const {
    return mesh_mask<MeshModel>(spec(ID(a)).changes);
}

RichParameterList TableFilterPlugin2022::initParameterList(const QAction* a, const MeshModel&) {
    RichParameterList par;
    canonform::meshlab::add_params(spec(ID(a)), par);
    return par;
}

std::map<std::string, QVariant> TableFilterPlugin2022::applyFilter(const QAction* a,
                                                                   const RichParameterList& par,
                                                                   MeshDocument& md,
                                                                   unsigned int& /*postConditionMask*/,
                                                                   vcg::CallBackPos* cb) {
    const FilterSpec& s = spec(ID(a));
    const canonform::meshlab::ParamValues values = canonform::meshlab::read_params(s, par);
    canonform::meshlab::ActionContext ctx;
    ctx.log = [this](const std::string& line) { log(line); };
    ctx.progress = canonform::meshlab::progress_to(cb);
    log(canonform::meshlab::log_header(s));
    try {
        return canonform::meshlab::to_qvariant_map(apply_(s.id, md, values, ctx));
    } catch (const std::exception& e) {
        log(s.name + " failed: " + e.what());
        throw MLException(QString("%1: %2").arg(QString::fromStdString(s.name), QString::fromUtf8(e.what())));
    }
}
