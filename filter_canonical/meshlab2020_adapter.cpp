#include "meshlab2020_adapter.h"

using canonform::plugin::FilterKind;
using canonform::plugin::FilterSpec;
using canonform::plugin::ParamKind;

namespace {

int mesh_mask(unsigned flags) {
    using namespace canonform::plugin;
    int m = MeshModel::MM_NONE;
    if (flags & kVertexQuality) m |= MeshModel::MM_VERTQUALITY;
    if (flags & kVertexColor) m |= MeshModel::MM_VERTCOLOR;
    if (flags & kVertexSelection) m |= MeshModel::MM_VERTFLAGSELECT;
    if (flags & kVertexCoordinates) m |= MeshModel::MM_VERTCOORD;
    if (flags & kNormals) m |= MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
    return m;
}

}  // namespace

TableFilterPlugin2020::TableFilterPlugin2020(QString plugin_name, const std::vector<FilterSpec>& table,
                                             canonform::plugin::ApplyFn apply)
    : name_(std::move(plugin_name)), table_(table), apply_(apply) {
    for (const auto& f : table_) {
        typeList << f.id;
        actionList << new QAction(QString::fromUtf8(f.name), this);
    }
}

const FilterSpec& TableFilterPlugin2020::spec(FilterIDType id) const {
    return canonform::plugin::filter_spec(table_, id);
}

QString TableFilterPlugin2020::filterName(FilterIDType filter) const {
    return QString::fromUtf8(spec(filter).name);
}

QString TableFilterPlugin2020::filterInfo(FilterIDType filter) const {
    return QString::fromStdString(spec(filter).info);
}

MeshFilterInterface::FilterClass TableFilterPlugin2020::getClass(QAction* a) {
    switch (spec(ID(a)).kind) {
    case FilterKind::Quality: return MeshFilterInterface::Quality;
    case FilterKind::Selection: return MeshFilterInterface::Selection;
    case FilterKind::Smoothing: return MeshFilterInterface::Smoothing;
    case FilterKind::Measure: return MeshFilterInterface::Measure;
    }
    return MeshFilterInterface::Measure;
}

int TableFilterPlugin2020::getRequirements(QAction* a) { return mesh_mask(spec(ID(a)).requires); }

int TableFilterPlugin2020::postCondition(QAction* a) const { return mesh_mask(spec(ID(a)).changes); }

void TableFilterPlugin2020::initParameterSet(QAction* a, MeshModel&, RichParameterList& par) {
    for (const auto& p : spec(ID(a)).params) {
        const QString name = QString::fromUtf8(p.name), label = QString::fromUtf8(p.label),
                      tip = QString::fromUtf8(p.tooltip);
        switch (p.kind) {
        case ParamKind::Bool: par.addParam(RichBool(name, p.default_value != 0, label, tip)); break;
        case ParamKind::Int: par.addParam(RichInt(name, static_cast<int>(p.default_value), label, tip)); break;
        case ParamKind::Float: par.addParam(RichFloat(name, static_cast<float>(p.default_value), label, tip)); break;
        case ParamKind::String: par.addParam(RichString(name, QString::fromStdString(p.default_text), label, tip)); break;
        case ParamKind::Enum: {
            QStringList choices;
            for (const auto& c : p.choices) choices << QString::fromStdString(c);
            par.addParam(RichEnum(name, static_cast<int>(p.default_value), choices, label, tip));
            break;
        }
        }
    }
}

bool TableFilterPlugin2020::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                        vcg::CallBackPos* cb) {
    const FilterSpec& s = spec(ID(a));
    canonform::plugin::ParamValues values;
    for (const auto& p : s.params) {
        const QString name = QString::fromUtf8(p.name);
        if (!par.hasParameter(name)) continue;  // reported by ParamValues::get
        switch (p.kind) {
        case ParamKind::Bool: values.values[p.name] = par.getBool(name) ? 1 : 0; break;
        case ParamKind::Int: values.values[p.name] = par.getInt(name); break;
        case ParamKind::Float: values.values[p.name] = par.getFloat(name); break;
        case ParamKind::Enum: values.values[p.name] = par.getEnum(name); break;
        case ParamKind::String: values.strings[p.name] = par.getString(name).toStdString(); break;
        }
    }
    canonform::plugin::ActionContext ctx;
    ctx.log = [this](const std::string& line) { Log("%s", line.c_str()); };
    ctx.progress = [cb](double f, const char* stage) {
        if (cb) cb(static_cast<int>(100 * f), stage);
        return true;
    };
    try {
        apply_(s.id, md, values, ctx);
        return true;
    } catch (const std::exception& e) {
        errorMessage = QString("%1: %2").arg(QString::fromUtf8(s.name), QString::fromUtf8(e.what()));
        Log("%s failed: %s", s.name, e.what());
        return false;
    }
}
