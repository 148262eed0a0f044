# SPDX-License-Identifier: GPL-3.0-or-later
"""Moves the names of one library area from namespace canonform into canonform::AREA, and
qualifies their uses everywhere else (issue 25: one namespace per area, matching its folder).

usage: /usr/bin/python3 tools/rename_namespace.py AREA [FILE ...]

AREA is numerics, surface, canonical, procedural, views or meshlab (or all: each in turn). Without FILEs: every tracked .h/.cpp file of
the repository. In src/canonform/AREA/ the namespace `canonform` becomes `canonform::AREA`; in every
other file a use of one of the area's public names (the list below) becomes `AREA::NAME` (or
`canonform::AREA::NAME` where it was written `canonform::NAME`, also through an alias of
canonform); a .cpp file that says `using
namespace canonform;` (tests, benchmarks) gets `using namespace canonform::AREA;` after it instead. A function name is qualified only
where it is called (followed by '('); a member access (`.name`, `->name`), a name already qualified
by another namespace, string literals, comments, #include lines and TEST() headers are left alone.
views: its names were already in canonform::views, written as two nested namespaces; they become
one `namespace canonform::views {`. meshlab: the MeshLab glue's namespace canonform::plugin (the
filter tables, adapters and both plugins' actions) becomes canonform::meshlab (`plugin::NAME` ->
`meshlab::NAME`), and vcg_bridge.h's names move from canonform into it; a file already in
canonform::AREA is not qualified.
Run it on a branch written before the rename to bring it up to date (then build: the compiler names
what is left).
"""
import os
import re
import subprocess
import sys

TYPES = {
    "numerics": """VertexAdjacency RigidAlignment SparseCholesky LinearSolver kMultigridFrom AmgOptions
        AmgPreconditioner PcgReport SmacofAcceleration kDefaultSmacofAcceleration kDefaultAccelerationDepth
        SmacofOptions SmacofStatistics SmacofResult StressPairs GuttmanAccelerator SmacofSolverOptions
        SmacofSolver MdsMethod MdsOptions MdsResult""",
    "surface": """ConformalFactorOptions ConformalFactorResult FeatureFill FeaturePointOptions FeaturePoints
        GeodesicOptions FastMarching kMaxUnfoldSteps MeshRepairOptions MeshRepair MeshProblem MeshReport
        ValidationOptions""",
    "canonical": """CanonicalVariant EuclideanCanonicalFormOptions EuclideanCanonicalFormResult
        GeodesicCanonicalFormOptions GeodesicCost GeodesicCanonicalFormResult MethodFamily MethodSettings
        MethodContext SummaryValue CanonicalForm CanonicalMethod MethodSpec""",
    "procedural": """ArmPose LegPose FigurePose FigureProportions Figure kFigureClasses kFigureNamedPoses""",
    "views": "",
    "meshlab": """BridgedMesh""",
}
FUNCTIONS = {
    "numerics": """vertex_adjacency connected_components align_rigid use_multigrid linear_solver_names
        parse_smacof_acceleration smacof_acceleration_names smacof_parameters run_guttman mds_parameters
        classical_mds landmark_mds least_squares_mds mds raw_stress portable_atan2""",
    "surface": """conformal_factor normalize_scale normalize_parameter cotan_laplacian feature_point_parameters
        local_maxima feature_points sqrt_count gaussian_curvature all_pairs_geodesic_distances
        all_pairs_geodesic_bytes all_pairs_geodesic_seconds_estimate geodesic_distances_from repair_mesh
        repair_parameter validate_mesh mesh_problems unique_edges boundary_vertices mean_relative_edge_change
        simplify_mesh vertex_areas""",
    "canonical": """euclidean_canonical_form_parameters euclidean_canonical_form euclidean_method
        canonical_form_pairs estimate_geodesic_canonical_form geodesic_canonical_form_parameters geodesic_method
        geodesic_canonical_form canonical_methods canonical_method canonical_methods_of default_method_of
        family_parameters register_canonical_method unregister_canonical_method parse_method_spec""",
    "procedural": """figure_class figure_class_names figure_pose make_disc make_figure make_icosphere make_torus""",
    "views": "",
    "meshlab": """to_eigen write_positions write_quality""",
}
# An area whose names were in another namespace of canonform before: canonform::OLD -> canonform::AREA.
MERGED = {"meshlab": "plugin"}
# Also a nested namespace of the area, where it is written canonform::detail:: (mds.h's
# top_eigenpairs); an unqualified detail:: may be another area's and is left to the compiler.
NESTED = {"numerics": ["detail"]}

TOKEN = re.compile(r'//[^\n]*|/\*.*?\*/|R"\((?:.|\n)*?\)"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'|'
                   r'[A-Za-z_]\w*|::|->|\S|\s+', re.S)


def qualify(text, area, using=False):
    """`using`: the file says `using namespace canonform;` (a test or benchmark): names written
    unqualified stay so and `using namespace canonform::AREA;` is added after it instead."""
    types = set(TYPES[area].split())
    functions = set(FUNCTIONS[area].split())
    nested = set(NESTED.get(area, []))
    # names that stand for canonform: itself and its aliases (namespace cf = canonform;)
    roots = {"canonform"} | set(re.findall(r"namespace\s+(\w+)\s*=\s*canonform\s*;", text))
    toks = TOKEN.findall(text)
    out = []
    line_start = True
    skip_line = False
    for i, t in enumerate(toks):
        if line_start:
            stripped = t.lstrip()
            skip_line = stripped.startswith("#") or stripped.startswith("TEST")
        if "\n" in t:
            line_start = True
            skip_line = False
            out.append(t)
            continue
        if not t.isspace():
            line_start = False
        name = t
        if skip_line or not re.match(r"[A-Za-z_]\w*$", name) or name not in types | functions | nested:
            out.append(t)
            continue
        prev = next((p for p in reversed(out) if not p.isspace()), "")
        nxt = next((n for n in toks[i + 1:] if not n.isspace()), "")
        if name in functions and name not in types and nxt != "(":
            out.append(t)
            continue
        if name in nested and (nxt != "::" or prev != "::"):  # only canonform::detail:: (see above)
            out.append(t)
            continue
        if prev in (".", "->"):
            out.append(t)
            continue
        if using and prev != "::":
            out.append(t)
            continue
        if prev == "::":
            # canonform::NAME -> canonform::AREA::NAME; OTHER::NAME stays
            before = [p for p in out if not p.isspace()]
            if len(before) >= 2 and before[-2] in roots and (len(before) < 3 or before[-3] != "::"):
                out.append(area + "::" + t)
            else:
                out.append(t)
            continue
        out.append(area + "::" + t)
    return "".join(out)


def rename_merged(text, area):
    """canonform::OLD -> canonform::AREA and OLD:: -> AREA:: in code (not in strings or comments)."""
    old = MERGED.get(area)
    if not old:
        return text
    text = text.replace("// namespace canonform::%s\n" % old, "// namespace canonform::%s\n" % area)
    toks = TOKEN.findall(text)
    out = []
    for i, t in enumerate(toks):
        code = [p for p in out if not p.isspace()]
        prev = code[-1] if code else ""
        nxt = next((n for n in toks[i + 1:] if not n.isspace()), "")
        if t == old and prev == "::" and len(code) >= 2 and code[-2] == "canonform":
            t = area  # canonform::OLD
        elif t == old and nxt == "::" and prev != "::":
            t = area  # OLD::NAME
        out.append(t)
    return "".join(out)


def rename_area_file(text, area):
    # two nested namespaces (namespace canonform { namespace AREA {) become one
    text = re.sub(r"namespace canonform \{\n(\s*)namespace %s \{" % area, "namespace canonform::%s {" % area, text)
    text = re.sub(r"\}  // namespace %s\n\}  // namespace canonform\n" % area, "}  // namespace canonform::%s\n" % area, text)
    text = text.replace("namespace canonform {", "namespace canonform::%s {" % area)
    text = text.replace("}  // namespace canonform\n", "}  // namespace canonform::%s\n" % area)
    return text


def main():
    if len(sys.argv) < 2 or sys.argv[1] not in list(TYPES) + ["all"]:
        sys.exit(__doc__)
    for area in (TYPES if sys.argv[1] == "all" else [sys.argv[1]]):
        rename(area, sys.argv[2:])


def rename(area, args):
    root = subprocess.run(["git", "rev-parse", "--show-toplevel"], capture_output=True, text=True,
                          check=True).stdout.strip()
    files = args or [f for f in subprocess.run(["git", "-C", root, "ls-files"], capture_output=True,
                                                        text=True, check=True).stdout.split()
                             if f.endswith((".h", ".cpp")) and not f.startswith("external/")]
    changed = 0
    for rel in files:
        path = os.path.join(root, rel) if not os.path.isabs(rel) else rel
        text = open(path, encoding="utf-8").read()
        relpath = os.path.relpath(path, root).replace(os.sep, "/")
        text0 = text
        text = rename_merged(text, area)
        inside = f"src/canonform/{area}/" in relpath + "/"
        declares = f"namespace canonform::{area} {{" in text  # e.g. a plugin's actions in canonform::meshlab
        using = relpath.endswith(".cpp") and re.search(r"^using namespace canonform;$", text, re.M) is not None
        using = using or re.search(r"^\s*using namespace canonform::%s;$" % area, text, re.M) is not None
        if inside:
            new = rename_area_file(text, area)
        elif declares:
            new = text
        else:
            new = qualify(text, area, using)
            already = re.search(r"^using namespace canonform::%s;$" % area, new, re.M)
            if using and not already and qualify(text, area) != new:  # it uses the area's names unqualified
                lines = new.split("\n")
                last = max(i for i, l in enumerate(lines) if re.match(r"using namespace canonform(::\w+)*;$", l))
                lines.insert(last + 1, f"using namespace canonform::{area};")
                new = "\n".join(lines)
        if new != text0:
            open(path, "w", encoding="utf-8").write(new)
            changed += 1
    print(f"rename_namespace: {area}: {changed} files changed")


if __name__ == "__main__":
    main()
