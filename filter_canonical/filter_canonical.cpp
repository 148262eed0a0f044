#include "filter_canonical.h"

#include "filter_actions.h"
#include "filter_table.h"

using canonform::plugin::FilterId;
using canonform::plugin::FilterKind;
using canonform::plugin::ParamKind;

FilterCanonicalPlugin::FilterCanonicalPlugin() {
    for (const auto& f : canonform::plugin::filter_table()) {
        typeList << static_cast<FilterIDType>(f.id);
        actionList << new QAction(QString::fromUtf8(f.name), this);
    }
}

QString FilterCanonicalPlugin::pluginName() const { return "FilterCanonical"; }

QString FilterCanonicalPlugin::filterName(FilterIDType filter) const {
    return QString::fromUtf8(canonform::plugin::filter_spec(static_cast<FilterId>(filter)).name);
}

QString FilterCanonicalPlugin::filterInfo(FilterIDType filter) const {
    return QString::fromStdString(canonform::plugin::filter_spec(static_cast<FilterId>(filter)).info);
}

MeshFilterInterface::FilterClass FilterCanonicalPlugin::getClass(QAction* a) {
    switch (canonform::plugin::filter_spec(static_cast<FilterId>(ID(a))).kind) {
    case FilterKind::Quality: return MeshFilterInterface::Quality;
    case FilterKind::Selection: return MeshFilterInterface::Selection;
    case FilterKind::Smoothing: return MeshFilterInterface::Smoothing;
    }
    return MeshFilterInterface::Quality;
}

int FilterCanonicalPlugin::getRequirements(QAction* a) {
    switch (static_cast<FilterId>(ID(a))) {
    case FilterId::ConformalFactor: return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    default: return MeshModel::MM_VERTQUALITY;
    }
}

int FilterCanonicalPlugin::postCondition(QAction* a) const {
    switch (static_cast<FilterId>(ID(a))) {
    case FilterId::ConformalFactor: return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTCOLOR;
    case FilterId::FeaturePoints: return MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTFLAGSELECT;
    case FilterId::EuclideanCanonicalForm:
    case FilterId::GeodesicCanonicalForm:
        return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL |
               MeshModel::MM_VERTQUALITY | MeshModel::MM_VERTFLAGSELECT;
    }
    return MeshModel::MM_VERTQUALITY;
}

void FilterCanonicalPlugin::initParameterSet(QAction* a, MeshModel&, RichParameterList& par) {
    for (const auto& p : canonform::plugin::filter_spec(static_cast<FilterId>(ID(a))).params) {
        const QString name = QString::fromUtf8(p.name), label = QString::fromUtf8(p.label),
                      tip = QString::fromUtf8(p.tooltip);
        switch (p.kind) {
        case ParamKind::Bool: par.addParam(RichBool(name, p.default_value != 0, label, tip)); break;
        case ParamKind::Int: par.addParam(RichInt(name, static_cast<int>(p.default_value), label, tip)); break;
        case ParamKind::Float: par.addParam(RichFloat(name, static_cast<float>(p.default_value), label, tip)); break;
        case ParamKind::Enum: {
            QStringList choices;
            for (const auto& c : p.choices) choices << QString::fromStdString(c);
            par.addParam(RichEnum(name, static_cast<int>(p.default_value), choices, label, tip));
            break;
        }
        }
    }
}

bool FilterCanonicalPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                        vcg::CallBackPos* cb) {
    const auto id = static_cast<FilterId>(ID(a));
    const auto& spec = canonform::plugin::filter_spec(id);
    canonform::plugin::ParamValues values;
    for (const auto& p : spec.params) {
        const QString name = QString::fromUtf8(p.name);
        if (!par.hasParameter(name)) continue;  // reported by ParamValues::get
        switch (p.kind) {
        case ParamKind::Bool: values.values[p.name] = par.getBool(name) ? 1 : 0; break;
        case ParamKind::Int: values.values[p.name] = par.getInt(name); break;
        case ParamKind::Float: values.values[p.name] = par.getFloat(name); break;
        case ParamKind::Enum: values.values[p.name] = par.getEnum(name); break;
        }
    }
    canonform::plugin::ActionContext ctx;
    ctx.log = [this](const std::string& s) { Log("%s", s.c_str()); };
    ctx.progress = [cb](double f, const char* stage) {
        if (cb) cb(static_cast<int>(100 * f), stage);
        return true;
    };
    try {
        canonform::plugin::apply_filter_action(id, md, values, ctx);
        return true;
    } catch (const std::exception& e) {
        errorMessage = QString("%1: %2").arg(QString::fromUtf8(spec.name), QString::fromUtf8(e.what()));
        Log("%s failed: %s", spec.name, e.what());
        return false;
    }
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterCanonicalPlugin)
