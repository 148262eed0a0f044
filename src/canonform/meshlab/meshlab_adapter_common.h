// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: what the adapters of MeshLab 2020.09's and of the FilterPlugin API (2022.02, 2025.07)
// share, written once over the parts of MeshLab's API that did not change between the releases (the
// plugin's typeList/actionList, MeshModel's data masks, RichParameterList's getters and parameter
// classes). Included by meshlab2020_adapter.h and meshlab2022_adapter.h after their MeshLab header.
#pragma once

#include "canonform/meshlab/filter_table.h"

#include <QAction>
#include <QObject>
#include <QString>

#include <vector>

namespace canonform::meshlab {

/// Applies filter `id` of a table to the document (throws on failure, document unchanged).
using ApplyFn = ActionOutputs (*)(int id, MeshDocument& md, const ParamValues& params,
                                  const ActionContext& context);

/// What an adapter of either API holds: the plugin's name, its table and its apply function, and
/// MeshLab's list of filter ids and QActions made from the table.
template <class Interface>
class TableAdapter : public QObject, public Interface {
public:
    TableAdapter(QString plugin_name, const std::vector<FilterSpec>& table, ApplyFn apply)
        : name_(std::move(plugin_name)), table_(table), apply_(apply) {
        for (const auto& f : table_) {
            this->typeList.push_back(f.id);
            this->actionList.push_back(new QAction(QString::fromStdString(f.name), this));
        }
    }
    QString pluginName() const override { return name_; }

protected:
    const FilterSpec& spec(int id) const { return filter_spec(table_, id); }
    QString name_;
    const std::vector<FilterSpec>& table_;
    ApplyFn apply_;
};

/// MeshLab's MeshModel data mask (MM_*) of MeshData flags.
template <class MeshModelT>
int mesh_mask(unsigned flags) {
    int m = MeshModelT::MM_NONE;
    if (flags & kVertexQuality) m |= MeshModelT::MM_VERTQUALITY;
    if (flags & kVertexColor) m |= MeshModelT::MM_VERTCOLOR;
    if (flags & kVertexSelection) m |= MeshModelT::MM_VERTFLAGSELECT;
    if (flags & kVertexCoordinates) m |= MeshModelT::MM_VERTCOORD;
    if (flags & kNormals) m |= MeshModelT::MM_VERTNORMAL | MeshModelT::MM_FACENORMAL;
    if (flags & kTopology) m |= MeshModelT::MM_VERTNUMBER | MeshModelT::MM_FACENUMBER;
    return m;
}

/// The values of `spec`'s parameters in MeshLab's parameter list `par` (a missing one is left
/// out; ParamValues::get then names it).
template <class RichParameterListT>
ParamValues read_params(const FilterSpec& spec, const RichParameterListT& par) {
    ParamValues values;
    for (const auto& p : spec.params) {
        const auto name = QString::fromStdString(p.name());
        if (!par.hasParameter(name)) continue;
        switch (p.type()) {
            case ParameterType::Bool:
                values.values[p.name()] = par.getBool(name) ? 1 : 0;
                break;
            case ParameterType::Int:
                values.values[p.name()] = par.getInt(name);
                break;
            case ParameterType::Float:
                values.values[p.name()] = static_cast<double>(par.getFloat(name));
                break;
            case ParameterType::Choice:
                values.values[p.name()] = par.getEnum(name);
                break;
            case ParameterType::Text:
                values.strings[p.name()] = par.getString(name).toStdString();
                break;
        }
    }
    return values;
}

/// MeshLab's filter class (the plugin interface's FilterClass: same enumerators in both APIs) of
/// a table's FilterKind.
template <class PluginInterface>
typename PluginInterface::FilterClass filter_class(FilterKind kind) {
    switch (kind) {
        case FilterKind::Quality:
            return PluginInterface::Quality;
        case FilterKind::Selection:
            return PluginInterface::Selection;
        case FilterKind::Smoothing:
            return PluginInterface::Smoothing;
        case FilterKind::Measure:
            return PluginInterface::Measure;
    }
    return PluginInterface::Measure;
}

/// Progress of an action as MeshLab's callback cb(percent, stage) (both APIs).
template <class CallBack>
ProgressFn progress_to(CallBack* cb) {
    return [cb](double f, const char* stage) {
        if (cb) cb(static_cast<int>(100 * f), stage);
        return true;
    };
}

/// Adds `spec`'s parameters, at their defaults, to MeshLab's parameter list (RichBool, RichInt,
/// RichFloat, RichString, RichEnum exist with these arguments in both APIs; a float is stored
/// in MESHLAB_SCALAR, float for 2020.09 and double for pymeshlab 2022.2).
template <class RichParameterListT>
void add_params(const FilterSpec& spec, RichParameterListT& par) {
    for (const auto& p : spec.params) {
        const QString name = QString::fromStdString(p.name()), label = QString::fromStdString(p.label()),
                      tip = QString::fromStdString(tooltip(p));
        switch (p.type()) {
            case ParameterType::Bool:
                par.addParam(RichBool(name, default_number(p) != 0, label, tip));
                break;
            case ParameterType::Int:
                par.addParam(RichInt(name, static_cast<int>(default_number(p)), label, tip));
                break;
            case ParameterType::Float:
                par.addParam(RichFloat(name, static_cast<MESHLAB_SCALAR>(default_number(p)), label, tip));
                break;
            case ParameterType::Text:
                par.addParam(RichString(name, QString::fromStdString(p.default_value()), label, tip));
                break;
            case ParameterType::Choice: {
                QStringList choices;
                for (const auto& c : p.choices()) choices << QString::fromStdString(c);
                par.addParam(RichEnum(name, static_cast<int>(default_number(p)), choices, label, tip));
                break;
            }
        }
    }
}

}  // namespace canonform::meshlab
