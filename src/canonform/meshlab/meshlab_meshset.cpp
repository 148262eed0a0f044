// SPDX-License-Identifier: GPL-3.0-or-later
#include "canonform/meshlab/meshlab_meshset.h"

#include <common/globals.h>
#include <common/plugins/action_searcher.h>
#include <common/plugins/interfaces/filter_plugin.h>
#include <common/plugins/plugin_manager.h>
#include <common/python/function_set.h>
#include <common/utilities/eigen_mesh_conversions.h>
#include <common/utilities/load_save.h>

#include <vcg/complex/algorithms/update/selection.h>
#if CANONFORM_MESHLAB_API >= 2025
#include <vcg/complex/allocate.h>
#endif

#include <QDir>
#include <QFileInfo>

#include <nlohmann/json.hpp>

#include <cctype>
#include <cstdlib>

namespace canonform::meshlab {

void load_plugin(const std::string& filename) {
    const MeshLabPluginType type = PluginManager::checkPlugin(QString::fromStdString(filename));
    if (!(type.isIOPlugin() || type.isFilterPlugin()))
        throw MLException("Error while loading plugin: PyMeshLab only supports IO or Filter plugins.");
    PluginManager& pm = ::meshlab::pluginManagerInstance();
    pymeshlab::FunctionSet& fs = pymeshlab::functionSetInstance();
    MeshLabPlugin* ipf = pm.loadPlugin(QString::fromStdString(filename));
    const MeshLabPluginType tp(ipf);
    if (tp.isFilterPlugin()) {
        auto* fp = dynamic_cast<FilterPlugin*>(ipf);
        fs.loadFilterPlugin(fp);
        ActionSearcher& as = ::meshlab::actionSearcherInstance();
        for (QAction* a : fp->actions()) {
            a->setToolTip(fp->filterInfo(a));
            as.addAction(a);
        }
    } else if (tp.isIOPlugin()) {
        fs.loadIOPlugin(dynamic_cast<IOPlugin*>(ipf));
    } else {
        throw MLException("Error while loading plugin: Unknown plugin type.");
    }
}

std::string load_plugins(const std::string& dir) {
    std::string refused;
    try {
        ::meshlab::pluginManagerInstance().loadPlugins(QDir(QString::fromStdString(dir)));
    } catch (const MLException& e) {
        refused = e.what();
    }
    pymeshlab::functionSetInstance();  // built from the plugin manager on first use
    return refused;
}

namespace {

bool parse_bool(const std::string& s, bool& out) {
    std::string t;
    for (char c : s) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (t == "true" || t == "1" || t == "yes" || t == "on") return out = true, true;
    if (t == "false" || t == "0" || t == "no" || t == "off") return out = false, true;
    return false;
}

bool parse_int(const std::string& s, int& out) {
    if (s.empty()) return false;
    char* end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (*end != '\0' || v < INT32_MIN || v > INT32_MAX) return false;
    out = static_cast<int>(v);
    return true;
}

bool parse_double(const std::string& s, double& out) {
    if (s.empty()) return false;
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return *end == '\0';
}

/// Command-line text as the Python value pymeshlab would get for a parameter of this type.
PyValue from_text(const RichParameter& par, const std::string& key, const std::string& text) {
    auto wrong = [&](const char* want) {
        return MLException(QString::fromStdString("Parameter " + key + ": '" + text + "' is not " + want));
    };
    if (par.isOfType<RichBool>()) {
        bool b = false;
        if (!parse_bool(text, b)) throw wrong("a bool (true/false)");
        return b;
    }
    if (par.isOfType<RichInt>()) {
        int i = 0;
        if (!parse_int(text, i)) throw wrong("an int");
        return i;
    }
    if (par.isOfType<RichFloat>()) {
        double d = 0;
        if (!parse_double(text, d)) throw wrong("a float");
        return d;
    }
    if (par.isOfType<RichEnum>()) {  // by name, else by index
        int i = 0;
        if (dynamic_cast<const RichEnum&>(par).enumvalues.indexOf(QString::fromStdString(text)) == -1 &&
            parse_int(text, i))
            return i;
        return text;
    }
    return text;
}

/// One keyword on its parameter, as pymeshlab's updateRichParameterFromKwarg converts it.
void set_from_kwarg(RichParameter& par, const std::string& key, const PyValue& value) {
    const PyValue v =
        std::holds_alternative<Text>(value) ? from_text(par, key, std::get<Text>(value).text) : value;
    auto wrong = [&](const char* want) {
        return MLException(QString::fromStdString("Parameter " + key + ": expected " + want));
    };
    if (par.isOfType<RichBool>()) {
        if (!std::holds_alternative<bool>(v)) throw wrong("a bool");
        par.setValue(BoolValue(std::get<bool>(v)));
    } else if (par.isOfType<RichInt>()) {
        if (!std::holds_alternative<int>(v)) throw wrong("an int");
        par.setValue(IntValue(std::get<int>(v)));
    } else if (par.isOfType<RichFloat>()) {  // pymeshlab: FloatValue(py::cast<float>(value))
        if (std::holds_alternative<double>(v))
            par.setValue(FloatValue(static_cast<float>(std::get<double>(v))));
        else if (std::holds_alternative<int>(v))
            par.setValue(FloatValue(static_cast<float>(std::get<int>(v))));
        else
            throw wrong("a float");
    } else if (par.isOfType<RichEnum>()) {  // by name, or by index
        auto& en = dynamic_cast<RichEnum&>(par);
        int index = -1;
        if (std::holds_alternative<std::string>(v)) {
            index = en.enumvalues.indexOf(QString::fromStdString(std::get<std::string>(v)));
            if (index == -1) {
                std::string list;
                for (const QString& s : en.enumvalues) list += "'" + s.toStdString() + "'; ";
                throw MLException(QString::fromStdString("Enum '" + std::get<std::string>(v) +
                                                         "' not found. Possible values are " + list));
            }
        } else if (std::holds_alternative<int>(v)) {
            index = std::get<int>(v);
            if (index < 0 || index >= en.enumvalues.size())
                throw MLException(QString::fromStdString("Enum " + std::to_string(index) + " not valid."));
        } else {
            throw wrong("a str or an int");
        }
        en.setValue(IntValue(index));
    } else if (par.isOfType<RichString>()) {
        if (!std::holds_alternative<std::string>(v)) throw wrong("a str");
        par.setValue(StringValue(QString::fromStdString(std::get<std::string>(v))));
    } else {
        throw MLException(
            QString::fromStdString("Parameter " + key + ": a type canonform's MeshSet does not set"));
    }
}

/// The progress callback (pymeshlab passes its own: some of MeshLab's filters call it unchecked).
bool quiet_progress(const int, const char*) {
    return true;
}

FilterPlugin* plugin_of(const QString& meshlab_name, QAction*& action) {
    for (FilterPlugin* fp : ::meshlab::pluginManagerInstance().filterPluginIterator())
        for (QAction* a : fp->actions())
            if (meshlab_name == fp->filterName(a)) {
                action = a;
                return fp;
            }
    throw MLException("no plugin has the filter " + meshlab_name);
}

}  // namespace

void MeshSet::add_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const QString& name) {
    const CMeshO m = ::meshlab::meshFromMatrices(V.cast<Scalarm>(), F);
    addNewMesh(m, name);
}

void MeshSet::load_new_mesh(const std::string& path) {
    const QString file = QString::fromStdString(path);
    if (!QFileInfo::exists(file)) throw MLException("File " + file + " does not exist.");
    ::meshlab::loadMeshWithStandardParameters(file, *this, &quiet_progress);
}

void MeshSet::save_mesh(const std::string& path, MeshModel& m) {
    const QString file = QString::fromStdString(path);
    const QString extension = QFileInfo(file).suffix().toLower();
    IOPlugin* io = ::meshlab::pluginManagerInstance().outputMeshPlugin(extension);
    if (io == nullptr)
        throw MLException("Mesh " + file + " cannot be saved: MeshLab has no plugin to save " + extension +
                          " files");
    io->setLog(&Log);
    int capability = 0, default_bits = 0;
    io->exportMaskCapability(extension, capability, default_bits);
    namespace io_mask = vcg::tri::io;
    int mask = 0;
    for (const int bit :
         {io_mask::Mask::IOM_VERTCOLOR, io_mask::Mask::IOM_VERTQUALITY, io_mask::Mask::IOM_VERTNORMAL,
          io_mask::Mask::IOM_VERTTEXCOORD, io_mask::Mask::IOM_FACECOLOR, io_mask::Mask::IOM_FACEQUALITY,
          io_mask::Mask::IOM_FACENORMAL, io_mask::Mask::IOM_WEDGTEXCOORD})
        if ((capability & bit) && m.hasDataMask(MeshModel::io2mm(bit))) mask |= bit;
    io->save(extension, file, m, mask, io->initSaveParameter(extension, m), &quiet_progress);
}

Dict MeshSet::apply_filter(const std::string& filtername, const Kwargs& kwargs) {
    const pymeshlab::FunctionSet& fs = pymeshlab::functionSetInstance();
    const QString fname = QString::fromStdString(filtername);
    if (!fs.containsFilterFunction(fname))
        throw MLException("Failed to apply filter: " + fname +
                          "\nFilter does not exists. Take a look at MeshSet.print_filter_list function.");
    const pymeshlab::Function& f = fs.filterFunction(fname);
    QAction* action = nullptr;
    FilterPlugin* fp = plugin_of(f.meshlabFunctionName(), action);
    if (fp->filterArity(action) != FilterPlugin::NONE && meshNumber() == 0)
        throw MLException(fname + " requires at least one mesh loaded in the MeshSet.");
    RichParameterList rpl = fp->initParameterList(action, *this);
    for (const auto& [key, value] : kwargs) {
        const QString k = QString::fromStdString(key);
        if (!f.contains(k))
            throw MLException("Parameter " + k + " not found for filter " + fname +
                              ". Please check the documentation.");
        auto it = rpl.findParameter(f.getFilterFunctionParameter(k).meshlabName());
        if (it != rpl.end()) set_from_kwarg(*it, key, value);
    }
#if CANONFORM_MESHLAB_API >= 2025  // pymeshlab 2025.7 checks the filter's preconditions first
    QStringList missing;
    if (mm() != nullptr && !fp->isFilterApplicable(action, *mm(), missing))
        throw MLException("Failed to apply filter:  '" + fname + ". Current mesh does not have " +
                          missing.join(",") + ".");
#endif
    fp->setLog(&Log);
    try {
        const int req = fp->getRequirements(action);
        if (mm() != nullptr) mm()->updateDataMask(req);
        meshDocStateData().clear();
        meshDocStateData().create(*this);
        unsigned int post_condition_mask = MeshModel::MM_UNKNOWN;
        Dict out = fp->applyFilter(action, rpl, *this, post_condition_mask, &quiet_progress);
#if CANONFORM_MESHLAB_API >= 2025  // pymeshlab 2025.7 compacts every mesh after a filter
        for (MeshModel& m : meshIterator()) vcg::tri::Allocator<CMeshO>::CompactEveryVector(m.cm);
#endif
        if (mm() != nullptr) {
            mm()->cm.svn = int(vcg::tri::UpdateSelection<CMeshO>::VertexCount(mm()->cm));
            mm()->cm.sfn = int(vcg::tri::UpdateSelection<CMeshO>::FaceCount(mm()->cm));
        }
        fp->setLog(nullptr);
        return out;
    } catch (const std::exception& e) {
        fp->setLog(nullptr);
        throw MLException("Failed to apply filter: " + fname + "\nDetails: " + e.what());
    }
}

std::string to_json(const Dict& d, bool vector_summary) {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (const auto& [k, v] : d) {
        const std::string t = v.typeName() ? v.typeName() : "";
        if (t == "int")
            j[k] = v.toInt();
        else if (t == "double" || t == "float")
            j[k] = v.toDouble();
        else if (t == "bool")
            j[k] = v.toBool();
        else if (v.canConvert<Eigen::VectorXd>()) {
            const Eigen::VectorXd e = v.value<Eigen::VectorXd>();
            if (vector_summary)
                j[k] = {{"length", e.size()}, {"sum", e.sum()}};
            else
                j[k] = std::vector<double>(e.data(), e.data() + e.size());
        } else {
            j[k] = nullptr;
        }
    }
    return j.dump();
}

}  // namespace canonform::meshlab
