// canonform: command-line tool on the same core as the MeshLab plugins, for batch work.
//
//   canonform conformal IN OUT [--raw] [--json]
//   canonform features  IN OUT [--ring K] [--fill none|random] [--seed S] [--json]
//   canonform canonical IN OUT [--method euclidean|geodesic-ls|geodesic-classical|geodesic-fast]
//                              [--variant A|N] [--alpha A] [--beta B] [--ring K] [--seed S]
//                              [--tol T] [--max-iter M] [--solver auto|direct|multigrid]
//                              [--max-memory-gib G] [--max-seconds S] [--threads T] [--quiet] [--json]
//   canonform simplify  IN OUT --vertices K
//   canonform views      IN DIR [--size PX] [--seed S]
//   canonform codebook   OUT MESH... [--words W] [--seed S] [--random]
//   canonform descriptor IN OUT [--codebook CB] [--size PX] [--seed S] [--json]
//   canonform distance   OUT DESC... [--threads T]
//   canonform retrieve   --dataset DIR --labels CSV --out RUN --method M[,M...] [--words W]
//                        [--codebook CB] [--simplify K] [--noise SIGMA] [--seed S] [--threads T]
//   canonform evaluate   MATRIX --labels labels.csv [--json] [--pr PR.csv]
//   canonform grid       OUT.png RUN [--methods M[=LABEL],...] [--class C] [--columns K] [--size PX]
//   canonform generate  OUT [--vertices N] [--pose P] [--class C]
//   canonform generate  --collection DIR [--vertices N] [--poses K] [--classes C,...] [--seed S]
//   canonform picture   OUT.png MESH [--points PTS] [--canonical CANON] [--size PX]
//
// IN: OFF, PLY, OBJ or STL. OUT: PLY (binary) with the conformal factor as vertex quality
// (features: a point cloud of the feature points). Exit status: 0 ok, 1 bad input or failure
// (message on stderr naming the problem), 2 usage error. Outputs are written atomically.
#include "canonform/surface/conformal_factor.h"
#include "canonform/canonical/euclidean_canonical_form.h"
#include "canonform/surface/feature_points.h"
#include "canonform/canonical/geodesic_canonical_form.h"
#include "canonform/surface/mesh_topology.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/io/mesh_io.h"
#include "picture.h"
#include "canonform/surface/simplify.h"
#include "evaluate_command.h"
#include "grid.h"
#include "retrieve_command.h"
#include "views_commands.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using namespace canonform;

const char* kUsage =
    "usage:\n"
    "  canonform conformal IN OUT [--raw] [--json]\n"
    "  canonform features  IN OUT [--ring K] [--fill none|random] [--seed S] [--json]\n"
    "  canonform canonical IN OUT [--method euclidean|geodesic-ls|geodesic-classical|geodesic-fast]\n"
    "                             [--variant A|N] [--alpha A] [--beta B] [--ring K] [--seed S]\n"
    "                             [--tol T] [--max-iter M] [--solver auto|direct|multigrid]\n"
    "                             [--max-memory-gib G] [--max-seconds S] [--threads T] [--quiet] [--json]\n"
    "  canonform simplify  IN OUT --vertices K   (quadric edge collapse, as MeshLab's)\n"
    "  canonform views      IN DIR [--size PX] [--seed S]        (66 depth views + contact sheet)\n"
    "  canonform codebook   OUT MESH... [--words W] [--seed S] [--random]\n"
    "  canonform descriptor IN OUT [--codebook CB] [--size PX] [--seed S] [--json]\n"
    "  canonform distance   OUT DESC... [--threads T]           (OUT: float32 row-major, OUT.csv)\n"
    "  canonform retrieve   --dataset DIR --labels CSV --out RUN --method M[,M...] [--words W]\n"
    "                       [--codebook CB] [--simplify K] [--noise SIGMA] [--seed S] [--threads T]\n"
    "                       (M: none, euclidean-A, euclidean-N, geodesic-ls, geodesic-classical,\n"
    "                        geodesic-fast; euclidean-A:beta=B / euclidean-N:beta=B set beta)\n"
    "  canonform evaluate   MATRIX --labels labels.csv [--json] [--pr PR.csv]  (NN, tiers, E, DCG)\n"
    "  canonform grid       OUT.png RUN [--methods M[=LABEL],...] [--class C] [--columns K] [--size PX]\n"
    "                       (originals beside canonical forms of a retrieve run: Figs. 8/9)\n"
    "  canonform generate  OUT [--vertices N] [--pose P] [--class C]\n"
    "  canonform generate  --collection DIR [--vertices N] [--poses K] [--classes C,...] [--seed S]\n"
    "                      (C: standard, long-arms, short-legs, long-tail, stocky, long-neck)\n"
    "  canonform picture   OUT.png MESH [--points PTS] [--canonical CANON] [--size PX]\n"
    "IN: OFF, PLY, OBJ or STL; OUT: PLY with the conformal factor as vertex quality.\n";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Positional arguments and --options (flags have no value).
struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> options;

    Args(int argc, char** argv, int first, const std::vector<std::string>& flags) {
        for (int k = first; k < argc; ++k) {
            std::string a = argv[k];
            if (a.rfind("--", 0) == 0) {
                const auto eq = a.find('=');
                if (eq != std::string::npos) {
                    options[a.substr(2, eq - 2)] = a.substr(eq + 1);
                } else if (std::find(flags.begin(), flags.end(), a.substr(2)) != flags.end()) {
                    options[a.substr(2)] = "1";
                } else {
                    if (k + 1 >= argc) throw UsageError("option " + a + " needs a value");
                    options[a.substr(2)] = argv[++k];
                }
            } else {
                positional.push_back(a);
            }
        }
    }
    void allow(const std::vector<std::string>& names) const {
        for (const auto& [k, v] : options)
            if (std::find(names.begin(), names.end(), k) == names.end()) throw UsageError("unknown option --" + k);
    }
    bool flag(const std::string& n) const { return options.count(n) > 0; }
    std::string str(const std::string& n, const std::string& def) const {
        auto it = options.find(n);
        return it == options.end() ? def : it->second;
    }
    double num(const std::string& n, double def) const {
        auto it = options.find(n);
        if (it == options.end()) return def;
        char* end = nullptr;
        const double v = std::strtod(it->second.c_str(), &end);
        if (end == it->second.c_str() || *end != '\0') throw UsageError("--" + n + " needs a number, got '" + it->second + "'");
        return v;
    }
    int integer(const std::string& n, int def) const {
        const double v = num(n, def);
        if (v != static_cast<int>(v)) throw UsageError("--" + n + " needs an integer");
        return static_cast<int>(v);
    }
    void need(size_t count) const {
        if (positional.size() != count) throw UsageError("wrong number of arguments");
    }
};

/// A minimal JSON object writer for the --json summaries.
struct Json {
    std::ostringstream o;
    bool first = true;
    Json() { o << "{"; }
    Json& kv(const std::string& k, double v) {
        o << (first ? "" : ", ") << "\"" << k << "\": " << v;
        first = false;
        return *this;
    }
    Json& kv(const std::string& k, const std::string& v) {
        o << (first ? "" : ", ") << "\"" << k << "\": \"" << v << "\"";
        first = false;
        return *this;
    }
    Json& kv(const std::string& k, const std::vector<int>& v) {
        o << (first ? "" : ", ") << "\"" << k << "\": [";
        for (size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
        o << "]";
        first = false;
        return *this;
    }
    std::string str() { return o.str() + "}"; }
};

/// Validates the mesh (InputError names any problem) and notes an open surface on stderr.
void validate_and_note(const std::string& path, const io::MeshData& m, bool quiet) {
    MeshReport r;
    try {
        r = validate_mesh(m.V, m.F);
    } catch (const InputError& e) {
        throw InputError("'" + path + "': " + e.what());
    }
    if (r.boundary_edges > 0 && !quiet)
        std::cerr << "canonform: note: '" << path << "' is open (" << r.boundary_edges
                  << " boundary edges); boundary curvature uses pi instead of 2 pi (eq. 8)\n";
}

/// Runs fn(); an InputError it throws is re-thrown with the input's path in front.
template <class Fn>
auto on_input(const std::string& path, Fn fn) -> decltype(fn()) {
    try {
        return fn();
    } catch (const InputError& e) {
        const std::string what = e.what();
        if (what.find(path) != std::string::npos) throw;
        throw InputError("'" + path + "': " + what);
    }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// A terminal progress line on stderr (only when stderr is a terminal).
ProgressFn terminal_progress(bool quiet) {
    if (quiet || !isatty(2)) return {};
    return [](double f, const char* stage) {
        std::fprintf(stderr, "\r%3d%%  %-40s", static_cast<int>(100 * f), stage);
        if (f >= 1) std::fprintf(stderr, "\n");
        return true;
    };
}

int cmd_conformal(const Args& a) {
    a.need(2);
    a.allow({"raw", "json"});
    const auto t0 = std::chrono::steady_clock::now();
    const io::MeshData m = io::read_mesh(a.positional[0]);
    validate_and_note(a.positional[0], m, a.flag("json"));
    const ConformalFactorResult cf = on_input(a.positional[0], [&] {
        ConformalFactorOptions o;
        o.validate = false;  // validate_and_note() above
        return conformal_factor(m.V, m.F, o);
    });
    const Eigen::VectorXd& q = a.flag("raw") ? cf.raw : cf.normalized;
    io::write_ply(a.positional[1], m.V, m.F, q);
    if (a.flag("json"))
        std::cout << Json().kv("vertices", double(m.V.rows())).kv("faces", double(m.F.rows()))
                         .kv("min", cf.raw.minCoeff()).kv("max", cf.raw.maxCoeff()).kv("residual", cf.residual)
                         .kv("seconds", seconds_since(t0)).str() << "\n";
    return 0;
}

int cmd_features(const Args& a) {
    a.need(2);
    a.allow({"ring", "fill", "seed", "json"});
    const auto t0 = std::chrono::steady_clock::now();
    const io::MeshData m = io::read_mesh(a.positional[0]);
    FeaturePointOptions opt;
    opt.ring = a.integer("ring", 2);
    if (opt.ring < 1 || opt.ring > 10) throw UsageError("--ring must be between 1 and 10");
    const std::string fill = a.str("fill", "none");
    if (fill != "none" && fill != "random") throw UsageError("--fill must be none or random");
    opt.fill = fill == "random" ? FeatureFill::Random : FeatureFill::None;
    opt.seed = static_cast<std::uint64_t>(a.integer("seed", 0));
    validate_and_note(a.positional[0], m, a.flag("json"));
    const ConformalFactorResult cf = on_input(a.positional[0], [&] {
        ConformalFactorOptions o;
        o.validate = false;  // validate_and_note() above
        return conformal_factor(m.V, m.F, o);
    });
    const FeaturePoints fp = feature_points(m.F, cf.normalized, opt);
    Eigen::MatrixXd P(static_cast<Eigen::Index>(fp.indices.size()), 3);
    Eigen::VectorXd q(P.rows());
    for (size_t k = 0; k < fp.indices.size(); ++k) {
        P.row(static_cast<Eigen::Index>(k)) = m.V.row(fp.indices[k]);
        q(static_cast<Eigen::Index>(k)) = cf.normalized(fp.indices[k]);
    }
    io::write_ply(a.positional[1], P, Eigen::MatrixXi(0, 3), q);
    if (a.flag("json"))
        std::cout << Json().kv("vertices", double(m.V.rows())).kv("feature_points", double(fp.indices.size()))
                         .kv("maxima", double(fp.num_maxima)).kv("random", double(fp.num_random))
                         .kv("indices", fp.indices).kv("seconds", seconds_since(t0)).str() << "\n";
    return 0;
}

int cmd_geodesic(const Args& a, GeodesicMds method) {
    a.allow({"method", "tol", "max-iter", "max-memory-gib", "max-seconds", "threads", "quiet", "json"});
    const auto t0 = std::chrono::steady_clock::now();
    GeodesicCanonicalFormOptions opt;
    opt.method = method;
    opt.tolerance = a.num("tol", opt.tolerance);
    opt.max_iterations = a.integer("max-iter", opt.max_iterations);
    opt.max_memory_gib = a.num("max-memory-gib", opt.max_memory_gib);
    opt.max_seconds = a.num("max-seconds", opt.max_seconds);
    opt.threads = a.integer("threads", opt.threads);
    opt.progress = terminal_progress(a.flag("quiet") || a.flag("json"));
    const io::MeshData m = io::read_mesh(a.positional[0]);
    validate_and_note(a.positional[0], m, a.flag("json") || a.flag("quiet"));
    const GeodesicCanonicalFormResult r =
        on_input(a.positional[0], [&] { return geodesic_canonical_form(m.V, m.F, opt); });
    io::write_ply(a.positional[1], r.V, m.F);
    if (a.flag("json")) {
        std::cout << Json().kv("vertices", double(m.V.rows())).kv("faces", double(m.F.rows()))
                         .kv("method", geodesic_mds_name(method)).kv("iterations", double(r.iterations))
                         .kv("initial_stress", r.initial_stress).kv("final_stress", r.final_stress)
                         .kv("mean_relative_edge_change", r.mean_relative_edge_change)
                         .kv("geodesic_seconds", r.geodesic_seconds).kv("mds_seconds", r.mds_seconds)
                         .kv("seconds", r.seconds).kv("estimated_seconds", r.estimate.seconds)
                         .kv("estimated_bytes", r.estimate.bytes).kv("total_seconds", seconds_since(t0)).str()
                  << "\n";
    } else if (!a.flag("quiet")) {
        std::cerr << "geodesic canonical form (" << geodesic_mds_name(method) << "): " << m.V.rows()
                  << " vertices, geodesics " << r.geodesic_seconds << " s, MDS " << r.mds_seconds << " s\n";
    }
    return 0;
}

int cmd_canonical(const Args& a) {
    a.need(2);
    const std::string method = a.str("method", "euclidean");
    if (method == "geodesic-ls") return cmd_geodesic(a, GeodesicMds::LeastSquares);
    if (method == "geodesic-classical") return cmd_geodesic(a, GeodesicMds::Classical);
    if (method == "geodesic-fast") return cmd_geodesic(a, GeodesicMds::Fast);
    if (method != "euclidean")
        throw UsageError("--method must be euclidean, geodesic-ls, geodesic-classical or geodesic-fast");
    a.allow({"method", "variant", "alpha", "beta", "ring", "seed", "tol", "max-iter", "solver", "quiet", "json"});
    const auto t0 = std::chrono::steady_clock::now();
    EuclideanCanonicalFormOptions opt;
    const std::string variant = a.str("variant", "N");
    if (variant != "A" && variant != "N") throw UsageError("--variant must be A or N");
    opt.variant = variant == "A" ? CanonicalVariant::A : CanonicalVariant::N;
    opt.alpha = a.num("alpha", opt.alpha);
    opt.beta = a.num("beta", opt.beta);
    opt.ring = a.integer("ring", opt.ring);
    if (opt.ring < 1 || opt.ring > 10) throw UsageError("--ring must be between 1 and 10");
    opt.seed = static_cast<std::uint64_t>(a.integer("seed", 0));
    opt.tolerance = a.num("tol", opt.tolerance);
    opt.max_iterations = a.integer("max-iter", opt.max_iterations);
    const std::string solver = a.str("solver", "auto");
    if (solver == "direct") opt.linear_solver = LinearSolver::Direct;
    else if (solver == "multigrid") opt.linear_solver = LinearSolver::Multigrid;
    else if (solver != "auto") throw UsageError("--solver must be auto, direct or multigrid");
    opt.progress = terminal_progress(a.flag("quiet") || a.flag("json"));
    const io::MeshData m = io::read_mesh(a.positional[0]);
    const double read_seconds = seconds_since(t0);
    validate_and_note(a.positional[0], m, a.flag("json") || a.flag("quiet"));
    opt.validate = false;
    const EuclideanCanonicalFormResult r =
        on_input(a.positional[0], [&] { return euclidean_canonical_form(m.V, m.F, opt); });
    io::write_ply(a.positional[1], r.V, m.F, r.phi);
    if (a.flag("json")) {
        std::cout << Json().kv("vertices", double(m.V.rows())).kv("faces", double(m.F.rows()))
                         .kv("method", "euclidean").kv("variant", variant).kv("alpha", opt.alpha).kv("beta", r.beta)
                         .kv("feature_points", double(r.features.size())).kv("maxima", double(r.num_maxima))
                         .kv("random", double(r.num_random)).kv("iterations", double(r.iterations))
                         .kv("converged", r.converged ? 1.0 : 0.0).kv("initial_stress", r.initial_stress)
                         .kv("final_stress", r.final_stress).kv("solver", to_string(r.linear_solver))
                         .kv("mean_relative_edge_change", r.mean_relative_edge_change)
                         .kv("seconds", r.seconds).kv("read_seconds", read_seconds)
                         .kv("total_seconds", seconds_since(t0)).str() << "\n";
    } else if (!a.flag("quiet")) {
        std::cerr << "canonical form: " << m.V.rows() << " vertices, " << r.features.size() << " feature points, "
                  << r.iterations << " iterations, stress " << r.initial_stress << " -> " << r.final_stress
                  << ", " << r.seconds << " s\n";
    }
    return 0;
}

int cmd_simplify(const Args& a) {
    a.need(2);
    a.allow({"vertices"});
    if (!a.flag("vertices")) throw UsageError("simplify needs --vertices K");
    const io::MeshData m = io::read_mesh(a.positional[0]);
    validate_and_note(a.positional[0], m, false);
    const io::MeshData s = on_input(a.positional[0], [&] { return io::simplify_mesh(m, a.integer("vertices", 0)); });
    io::write_ply(a.positional[1], s.V, s.F);
    std::cerr << "simplified " << m.V.rows() << " -> " << s.V.rows() << " vertices\n";
    return 0;
}

cli::ViewCommandOptions view_options(const Args& a) {
    cli::ViewCommandOptions o;
    o.image_size = a.integer("size", o.image_size);
    o.seed = static_cast<unsigned long long>(a.integer("seed", 0));
    o.words = a.integer("words", o.words);
    if (o.words < 1) throw UsageError("--words must be positive");
    o.random_codebook = a.flag("random");
    o.codebook = a.str("codebook", "");
    o.threads = a.integer("threads", 0);
    o.json = a.flag("json");
    return o;
}

FigureProportions class_proportions(const std::string& name) {
    try {
        return figure_class(name);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
}

/// A labelled collection: every class (body type) in `poses` poses; pose k < 6 is named pose k
/// (shared by the classes, as the poses of TOSCA's and FAUST's models are), later ones are random
/// and differ between classes. DIR/meshes/CLASS_K.ply, DIR/labels.csv, DIR/corres/CLASS_K.vts
/// (identity: every figure has the same vertex order, so these are exact correspondences).
int generate_collection(const Args& a, int n) {
    a.need(0);
    const std::string dir = a.str("collection", "");
    const int poses = a.integer("poses", 10);
    if (poses < 2 || poses > 1000) throw UsageError("--poses must be between 2 and 1000");
    const int seed = a.integer("seed", 0);
    if (seed < 0 || seed > 100000) throw UsageError("--seed must be between 0 and 100000");
    std::vector<std::string> classes;
    std::stringstream cs(a.str("classes", ""));
    for (std::string c; std::getline(cs, c, ',');)
        if (!c.empty()) classes.push_back(c);
    if (classes.empty()) classes = figure_class_names();
    if (classes.size() < 2) throw UsageError("--classes needs at least two classes");
    for (const auto& c : classes) class_proportions(c);
    if (std::system(("mkdir -p '" + dir + "/meshes' '" + dir + "/corres'").c_str()) != 0)
        throw std::runtime_error("cannot create '" + dir + "'");
    std::ostringstream labels, ident;
    labels << "path,class\n";
    for (int v = 1; v <= n; ++v) ident << v << "\n";
    for (size_t c = 0; c < classes.size(); ++c) {
        const FigureProportions prop = class_proportions(classes[c]);
        for (int k = 0; k < poses; ++k) {
            const int pose_id = k < kFigureNamedPoses ? k : 1000 * (seed + 1) + 37 * static_cast<int>(c) + k;
            const Figure fig = make_figure(n, figure_pose(pose_id), prop);
            const std::string name = classes[c] + "_" + std::to_string(k);
            io::write_ply(dir + "/meshes/" + name + ".ply", fig.mesh.V.cast<float>().cast<double>(), fig.mesh.F);
            io::write_file_atomic(dir + "/corres/" + name + ".vts", ident.str());
            labels << "meshes/" << name << ".ply," << classes[c] << "\n";
        }
    }
    io::write_file_atomic(dir + "/labels.csv", labels.str());
    std::cerr << "generate: " << classes.size() * static_cast<size_t>(poses) << " figures (" << classes.size()
              << " classes x " << poses << " poses, " << n << " vertices) in " << dir << "\n";
    return 0;
}

int cmd_generate(const Args& a) {
    a.allow({"vertices", "pose", "class", "collection", "poses", "classes", "seed"});
    const int n = a.integer("vertices", 5000);
    if (n < 500 || n > 2000000) throw UsageError("--vertices must be between 500 and 2000000");
    if (a.flag("collection")) return generate_collection(a, n);
    a.need(1);
    const Figure fig = make_figure(n, figure_pose(a.integer("pose", 0)), class_proportions(a.str("class", "standard")));
    // Rounded to float, the precision MeshLab 2020.09 works in, so that the tool and MeshLab
    // compute on exactly the same coordinates.
    io::write_ply(a.positional[0], fig.mesh.V.cast<float>().cast<double>(), fig.mesh.F);
    return 0;
}

int cmd_picture(const Args& a) {
    a.need(2);
    a.allow({"points", "canonical", "size"});
    PictureInputs in;
    in.mesh = io::read_mesh(a.positional[1]);
    in.mesh_quality = io::read_ply_quality(a.positional[1]);
    if (a.flag("points")) in.points = io::read_mesh(a.str("points", "")).V;
    if (a.flag("canonical")) {
        in.canonical = io::read_mesh(a.str("canonical", ""));
        in.canonical_quality = io::read_ply_quality(a.str("canonical", ""));
    }
    write_picture(a.positional[0], in, a.integer("size", 420));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
        std::cout << kUsage;
        return argc < 2 ? 2 : 0;
    }
    const std::string cmd = argv[1];
    try {
        if (cmd == "conformal") return cmd_conformal(Args(argc, argv, 2, {"raw", "json"}));
        if (cmd == "features") return cmd_features(Args(argc, argv, 2, {"json"}));
        if (cmd == "canonical") return cmd_canonical(Args(argc, argv, 2, {"json", "quiet"}));
        if (cmd == "views") {
            const Args a(argc, argv, 2, {});
            a.need(2);
            a.allow({"size", "seed"});
            return cli::views_command(a.positional[0], a.positional[1], view_options(a));
        }
        if (cmd == "codebook") {
            const Args a(argc, argv, 2, {"random"});
            a.allow({"words", "seed", "random", "size"});
            if (a.positional.size() < 2) throw UsageError("codebook needs OUT and at least one mesh");
            return cli::codebook_command(a.positional[0], {a.positional.begin() + 1, a.positional.end()},
                                         view_options(a));
        }
        if (cmd == "descriptor") {
            const Args a(argc, argv, 2, {"json"});
            a.need(2);
            a.allow({"codebook", "size", "seed", "json"});
            return cli::descriptor_command(a.positional[0], a.positional[1], view_options(a));
        }
        if (cmd == "distance") {
            const Args a(argc, argv, 2, {});
            a.allow({"threads"});
            if (a.positional.size() < 3) throw UsageError("distance needs OUT and at least two descriptors");
            return cli::distance_command(a.positional[0], {a.positional.begin() + 1, a.positional.end()},
                                         view_options(a));
        }
        if (cmd == "retrieve") {
            const Args a(argc, argv, 2, {});
            a.need(0);
            a.allow({"dataset", "labels", "out", "method", "words", "codebook", "simplify", "noise", "seed", "threads"});
            cli::RetrieveOptions o;
            o.dataset = a.str("dataset", "");
            o.labels = a.str("labels", o.dataset + "/labels.csv");
            o.out = a.str("out", "");
            if (o.dataset.empty() || o.out.empty()) throw UsageError("retrieve needs --dataset and --out");
            std::stringstream ms(a.str("method", "none,euclidean-N"));
            for (std::string m; std::getline(ms, m, ',');)
                if (!m.empty()) o.methods.push_back(m);
            o.words = a.integer("words", o.words);
            o.codebook = a.str("codebook", "");
            o.simplify = a.integer("simplify", 0);
            o.noise = a.num("noise", 0);
            o.seed = static_cast<unsigned long long>(a.integer("seed", 0));
            o.threads = a.integer("threads", 0);
            return cli::retrieve_command(o);
        }
        if (cmd == "grid") {
            const Args a(argc, argv, 2, {});
            a.need(2);
            a.allow({"methods", "class", "columns", "size"});
            cli::GridOptions g;
            g.run = a.positional[1];
            std::stringstream ms(a.str("methods", ""));
            for (std::string m; std::getline(ms, m, ',');)
                if (!m.empty()) g.methods.push_back(m);
            g.cls = a.str("class", "");
            g.columns = a.integer("columns", g.columns);
            g.panel = a.integer("size", g.panel);
            const int n = cli::write_grid(a.positional[0], g);
            std::cerr << "grid: " << n << " models, " << (g.methods.empty() ? std::string("every method") : a.str("methods", ""))
                      << " -> " << a.positional[0] << "\n";
            return 0;
        }
        if (cmd == "evaluate") {
            const Args a(argc, argv, 2, {"json"});
            a.need(1);
            a.allow({"labels", "json", "pr"});
            if (!a.flag("labels")) throw UsageError("evaluate needs --labels labels.csv");
            return cli::evaluate_command(a.positional[0], a.str("labels", ""), a.flag("json"), a.str("pr", ""));
        }
        if (cmd == "simplify") return cmd_simplify(Args(argc, argv, 2, {}));
        if (cmd == "generate") return cmd_generate(Args(argc, argv, 2, {}));
        if (cmd == "picture") return cmd_picture(Args(argc, argv, 2, {}));
        throw UsageError("unknown command '" + cmd + "'");
    } catch (const UsageError& e) {
        std::cerr << "canonform: " << e.what() << "\n" << kUsage;
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "canonform " << cmd << ": error: " << e.what() << "\n";
        return 1;
    }
}
