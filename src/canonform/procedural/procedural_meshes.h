// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: procedural test meshes (Eigen and the standard library only).
//
// - make_icosphere: icosahedron, each subdivision splits every triangle in four at the edge
//   midpoints, which are pushed onto the sphere.
// - make_torus:     regular (u, v) grid on the torus of revolution about z, two triangles per cell.
// - make_disc:      concentric rings (ring k has 6k vertices at radius k/K), neighbouring rings
//                   zipped together by angle; a fan around the centre.
// - make_figure:    an articulated humanoid with a tail. Its rest pose is the zero set of a signed
//                   distance function: tapered capsules (hard union within a limb, polynomial
//                   smooth-min between body parts). The surface is extracted once per vertex
//                   target with naive surface nets on a sparse block grid (sign patterns that
//                   would be non-manifold are repaired first), projected onto the zero set,
//                   coarsened to the exact target by shortest-edge collapses (link condition,
//                   no flips) with one vertex pinned on each limb tip, relaxed tangentially and
//                   checked (closed, 2-manifold, one component, genus 0, min angle >= 10 degrees;
//                   otherwise the grid is shifted and the extraction retried). A pose is applied
//                   by linear blend skinning on a 13-bone skeleton (weights: inverse 12th power of
//                   the radius-normalised distance to each bone's capsules, averaged over a small
//                   ball so the joints bend smoothly), so all poses at one vertex target share the
//                   same faces and vertex order.
//
// Conventions: faces are counter-clockwise seen from outside (outward normals). The figure stands
// on z = 0 with z up, about 1.95 units tall, faces -y, and its left side is +x.
#pragma once

#include "canonform/common/mesh.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace canonform::procedural {

/// Icosphere: icosahedron subdivided `subdivisions` (0..9) times, projected on a sphere of
/// `radius` (centre origin). 10*4^s+2 vertices, 20*4^s faces. Throws std::invalid_argument on bad
/// arguments.
Mesh make_icosphere(int subdivisions, double radius = 1.0);

/// Torus about the z axis with major radius R, minor radius r (0 < r < R), n_major x n_minor vertex
/// grid (n_major, n_minor >= 3): closed, genus 1, no boundary, 2 n_major n_minor faces. Vertex
/// i * n_minor + j is at angle 2 pi i / n_major around z and 2 pi j / n_minor around the tube.
Mesh make_torus(int n_major, int n_minor, double R = 1.0, double r = 0.3);

/// Flat disc of radius `radius` in the z = 0 plane, centred at the origin, normals +z. Vertex 0 is
/// the centre; ring k = 1..K has 6k vertices at radius k/K * radius (spacing about radius/K), with
/// K chosen so that 1 + 3K(K+1) is closest to `target_vertices` (>= 7). One boundary loop (ring K).
Mesh make_disc(int target_vertices, double radius = 1.0);

/// Shoulder and elbow angles of one arm, radians. Left and right arms are mirror images: the same
/// values give the mirrored posture. In the rest pose the arm is horizontal (T-pose).
struct ArmPose {
    double shoulder_down = 0.0;     ///< lowers the arm towards the body side (< 0 raises it)
    double shoulder_forward = 0.0;  ///< swings the arm forwards (-y) about z (< 0 backwards)
    double elbow_bend = 0.0;        ///< flexes the forearm forwards/inwards (>= 0 is natural)
};

/// Hip and knee angles of one leg, radians (mirrored like ArmPose). At rest the legs point down
/// and about 15 degrees outwards.
struct LegPose {
    double hip_forward = 0.0;  ///< swings the leg forwards (-y) about the lateral axis (< 0 back)
    double hip_out = 0.0;      ///< swings the leg outwards (abduction, < 0 inwards, crossing)
    double knee_bend = 0.0;    ///< flexes the lower leg backwards (+y) (>= 0 is natural)
};

/// Joint angles of the figure, radians; all zero = rest pose (T-pose, legs apart, tail straight
/// back). Rotations are applied at the joints of the rest skeleton, parent first (hip/shoulder:
/// first the swing out/down, then the forward swing).
struct FigurePose {
    double head_yaw = 0.0;    ///< turns the head about z; > 0 turns the face to the figure's left
    double head_pitch = 0.0;  ///< nods the head forwards (< 0 looks up); pivot at the neck base
    ArmPose left_arm, right_arm;
    LegPose left_leg, right_leg;
    double tail_swing = 0.0;  ///< swings the whole tail sideways at its base; > 0 towards +x
    double tail_curl = 0.0;   ///< bends the tail upwards (< 0 downwards): this angle at the 2
                              ///< inner tail joints, half of it at the base
};

/// Number of named poses of figure_pose() (ids 0 .. kFigureNamedPoses - 1).
constexpr int kFigureNamedPoses = 6;

/// Named poses: 0 = rest, 1 = arms down and relaxed, 2 = arms up with bent elbows, one knee
/// raised, tail curled up, 3 = walking stride with the head turned and the tail swung, 4 = half
/// crouch reaching forwards, 5 = legs crossed, one arm up, one forearm across the front.
/// pose_id >= kFigureNamedPoses: deterministic random pose (std::mt19937 seeded with pose_id,
/// platform independent) with angles in ranges where the limbs clear the body and each other.
/// Throws std::invalid_argument for pose_id < 0.
FigurePose figure_pose(int pose_id);

/// Body proportions of the figure (all 1 = the standard figure). Applied to the rest mesh before
/// posing by linear blend skinning of per-bone affine maps (the same weights as the pose): a bone
/// is stretched by its length factor along its axis and by its girth factor across it, about its
/// joint, and carried to where its parent moved that joint. Connectivity and vertex order stay
/// those of the standard figure, so figures of any proportions and pose at one vertex target
/// correspond vertex by vertex. Factors must lie in [0.5, 2] (std::invalid_argument otherwise).
struct FigureProportions {
    double arm_length = 1.0;    ///< upper and lower arms
    double leg_length = 1.0;    ///< upper and lower legs
    double tail_length = 1.0;   ///< the three tail segments
    double neck_length = 1.0;   ///< neck and head, along the neck (the head gets longer, not wider)
    double torso_length = 1.0;  ///< trunk above the hips
    double limb_girth = 1.0;    ///< thickness of arms, legs and tail
    double torso_girth = 1.0;   ///< thickness of the trunk
};

/// Named body types for labelled procedural collections: "standard", "long-arms", "short-legs",
/// "long-tail", "stocky", "long-neck" (kFigureClasses of them, in this order).
constexpr int kFigureClasses = 6;
std::vector<std::string> figure_class_names();
/// The proportions of a named body type; std::invalid_argument names the known ones otherwise.
FigureProportions figure_class(const std::string& name);

/// A posed figure.
struct Figure {
    Mesh mesh;                               ///< watertight, 2-manifold, one component, genus 0
    std::vector<Eigen::Vector3d> limb_tips;  ///< posed extremities, on the surface: the mesh
                                             ///< vertices limb_tip_vertex (same positions)
    std::vector<std::string> limb_names;     ///< "head","left_hand","right_hand","left_foot",
                                             ///< "right_foot","tail" (same order as limb_tips)
    std::vector<double> limb_radius;         ///< tube radius of the limb at its tip (head: the
                                             ///< head's radius)
    std::vector<int> limb_tip_vertex;        ///< vertex placed exactly on each tip of the rest
                                             ///< pose (same index for every pose)
};

/// Build the figure with `target_vertices` vertices (exactly, for 300 <= target <= 1,000,000;
/// throws std::invalid_argument outside) in the given pose. Faces and vertex order are identical
/// for all poses at the same target: the rest mesh is built once (and cached for the last few
/// targets, thread-safe) and deformed by skinning. Throws std::runtime_error if no valid mesh could
/// be extracted (not observed).
Figure make_figure(int target_vertices, const FigurePose& pose);
/// The same with other body proportions (see FigureProportions): same faces and vertex order.
Figure make_figure(int target_vertices, const FigurePose& pose, const FigureProportions& proportions);

}  // namespace canonform::procedural
