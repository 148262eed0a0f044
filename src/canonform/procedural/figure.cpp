// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: posing the figure and its body types. See procedural_meshes.h.
#include "canonform/procedural/body_model.h"
#include "canonform/procedural/mesh_building.h"
#include "canonform/procedural/procedural_meshes.h"
#include "canonform/procedural/rest_figure.h"
#include "canonform/surface/mesh_topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iterator>
#include <limits>
#include <list>
#include <memory>
#include <mutex>
#include <queue>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace canonform::procedural {

using namespace detail;

namespace {

Matrix3d rot(const Vector3d& axis, double angle) {
    return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

/// Local joint rotations (rest frame) for a pose; right limbs are the mirror images of left ones.
std::array<Matrix3d, kNumBones> joint_rotations(const FigurePose& p) {
    const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
    const Matrix3d M = Vector3d(-1, 1, 1).asDiagonal();
    std::array<Matrix3d, kNumBones> R;
    R.fill(Matrix3d::Identity());
    R[kHead] = rot(Z, p.head_yaw) * rot(X, p.head_pitch);
    // A limb's upper and lower rotations; right limbs mirror the left ones' (M R M).
    auto limb = [&](Matrix3d ru, Matrix3d rl, int upper, int lower, bool right) {
        if (right) {
            ru = M * ru * M;
            rl = M * rl * M;
        }
        R[static_cast<size_t>(upper)] = ru;
        R[static_cast<size_t>(lower)] = rl;
    };
    auto arm = [&](const ArmPose& a, int upper, int lower, bool right) {
        limb(rot(Z, -a.shoulder_forward) * rot(Y, a.shoulder_down), rot(Z, -a.elbow_bend), upper, lower,
             right);
    };
    auto leg = [&](const LegPose& l, int upper, int lower, bool right) {
        limb(rot(X, -l.hip_forward) * rot(Y, -l.hip_out), rot(X, l.knee_bend), upper, lower, right);
    };
    arm(p.left_arm, kLUpperArm, kLLowerArm, false);
    arm(p.right_arm, kRUpperArm, kRLowerArm, true);
    leg(p.left_leg, kLUpperLeg, kLLowerLeg, false);
    leg(p.right_leg, kRUpperLeg, kRLowerLeg, true);
    R[kTail1] = rot(Z, -p.tail_swing) * rot(X, 0.5 * p.tail_curl);
    R[kTail2] = rot(X, p.tail_curl);
    R[kTail3] = rot(X, p.tail_curl);
    return R;
}

struct Rigid {
    Matrix3d R = Matrix3d::Identity();
    Vector3d t = Vector3d::Zero();
};

std::array<Rigid, kNumBones> bone_transforms(const Body& body, const FigurePose& pose) {
    const std::array<Matrix3d, kNumBones> local = joint_rotations(pose);
    std::array<Rigid, kNumBones> G;
    for (int b = 0; b < kNumBones; ++b) {
        const Bone& bone = body.bones[static_cast<size_t>(b)];
        const Matrix3d& r = local[static_cast<size_t>(b)];
        Rigid l;  // x -> j + r (x - j)
        l.R = r;
        l.t = bone.joint - r * bone.joint;
        if (bone.parent < 0) {
            G[static_cast<size_t>(b)] = l;
        } else {
            const Rigid& p = G[static_cast<size_t>(bone.parent)];
            G[static_cast<size_t>(b)].R = p.R * l.R;
            G[static_cast<size_t>(b)].t = p.R * l.t + p.t;
        }
    }
    return G;
}

Vector3d skin(const std::array<Rigid, kNumBones>& G, const Vector3d& p,
              const std::array<int, kInfluences>& bones, const std::array<double, kInfluences>& w) {
    Vector3d q = Vector3d::Zero();
    for (int i = 0; i < kInfluences; ++i) {
        const Rigid& g = G[static_cast<size_t>(bones[static_cast<size_t>(i)])];
        q += w[static_cast<size_t>(i)] * (g.R * p + g.t);
    }
    return q;
}

// Deterministic uniform double in [lo, hi) from mt19937 (whose output is fully specified).
double uniform(std::mt19937& rng, double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0);
}

}  // namespace

FigurePose figure_pose(int pose_id) {
    if (pose_id < 0) throw std::invalid_argument("figure_pose: pose_id must be >= 0");
    FigurePose p;
    switch (pose_id) {
        case 0:  // rest
            break;
        case 1:  // arms down, relaxed
            p.left_arm = {deg(65), deg(10), deg(20)};
            p.right_arm = {deg(65), deg(10), deg(20)};
            p.left_leg = {0.0, deg(-6), deg(5)};
            p.right_leg = {0.0, deg(-6), deg(5)};
            p.head_pitch = deg(15);
            p.tail_curl = deg(10);
            break;
        case 2:  // arms up with bent elbows, left knee raised, tail curled up
            p.left_arm = {deg(-40), deg(10), deg(70)};
            p.right_arm = {deg(-35), deg(-10), deg(50)};
            p.left_leg = {deg(40), 0.0, deg(60)};
            p.right_leg = {deg(-5), deg(5), deg(5)};
            p.head_yaw = deg(-30);
            p.tail_curl = deg(45);
            break;
        case 3:  // walking stride, head turned, tail swung
            p.left_arm = {deg(55), deg(35), deg(30)};
            p.right_arm = {deg(55), deg(-25), deg(10)};
            p.left_leg = {deg(30), deg(-5), deg(25)};
            p.right_leg = {deg(-20), 0.0, deg(10)};
            p.head_yaw = deg(40);
            p.tail_swing = deg(30);
            p.tail_curl = deg(20);
            break;
        case 4:  // half crouch reaching forwards, looking up
            p.left_arm = {deg(35), deg(45), deg(70)};
            p.right_arm = {deg(35), deg(45), deg(70)};
            p.left_leg = {deg(45), deg(10), deg(70)};
            p.right_leg = {deg(45), deg(10), deg(70)};
            p.head_pitch = deg(-20);
            p.tail_curl = deg(15);
            break;
        case 5:  // legs crossed, left arm up, right forearm across the front
            p.left_arm = {deg(-60), 0.0, deg(30)};
            p.right_arm = {deg(40), deg(40), deg(90)};
            p.left_leg = {deg(20), deg(-25), deg(10)};
            p.right_leg = {deg(-12), deg(-20), deg(10)};
            p.head_pitch = deg(20);
            p.head_yaw = deg(-45);
            p.tail_swing = deg(-40);
            p.tail_curl = deg(50);
            break;
        default: {
            std::mt19937 rng(static_cast<std::uint32_t>(pose_id));
            auto arm = [&](ArmPose* a) {
                a->shoulder_down = uniform(rng, -0.7, 1.1);
                a->shoulder_forward = uniform(rng, -0.4, 0.7);
                a->elbow_bend = uniform(rng, 0.0, 1.3);
            };
            auto leg = [&](LegPose* l) {
                l->hip_forward = uniform(rng, -0.3, 0.6);
                l->hip_out = uniform(rng, -0.1, 0.35);
                l->knee_bend = uniform(rng, 0.0, 1.0);
            };
            arm(&p.left_arm);
            arm(&p.right_arm);
            leg(&p.left_leg);
            leg(&p.right_leg);
            p.head_yaw = uniform(rng, -0.8, 0.8);
            p.head_pitch = uniform(rng, -0.3, 0.4);
            p.tail_swing = uniform(rng, -0.4, 0.4);
            p.tail_curl = uniform(rng, -0.2, 0.5);
            break;
        }
    }
    return p;
}

Figure make_figure(int target_vertices, const FigurePose& pose) {
    return make_figure(target_vertices, pose, FigureProportions());
}

std::vector<std::string> figure_class_names() {
    return {"standard", "long-arms", "short-legs", "long-tail", "stocky", "long-neck"};
}

FigureProportions figure_class(const std::string& name) {
    FigureProportions p;
    if (name == "standard") return p;
    if (name == "long-arms") {
        p.arm_length = 1.4;
    } else if (name == "short-legs") {
        p.leg_length = 0.65;
    } else if (name == "long-tail") {
        p.tail_length = 1.7;
    } else if (name == "stocky") {
        p.limb_girth = 1.45;
        p.torso_girth = 1.35;
        p.leg_length = 0.85;
        p.arm_length = 0.85;
    } else if (name == "long-neck") {
        p.neck_length = 1.5;
        p.torso_length = 1.15;
    } else {
        std::string known;
        for (const auto& n : figure_class_names()) known += (known.empty() ? "" : ", ") + n;
        throw std::invalid_argument("unknown figure class '" + name + "' (known: " + known + ")");
    }
    return p;
}

namespace {

/// Affine map x -> A x + c.
struct Affine {
    Matrix3d A = Matrix3d::Identity();
    Vector3d c = Vector3d::Zero();
    Vector3d operator()(const Vector3d& x) const { return A * x + c; }
};

/// Per-bone shape maps of FigureProportions (parents before children): bone b maps x to
/// S_parent(j_b) + M_b (x - j_b), M_b = length d d^T + girth (I - d d^T), d = the bone's axis.
std::array<Affine, kNumBones> shape_maps(const Body& body, const FigureProportions& p) {
    const Vector3d Z = Vector3d::UnitZ();
    std::array<Vector3d, kNumBones> axis;
    axis.fill(Z);
    std::array<double, kNumBones> length, girth;
    length.fill(1.0);
    girth.fill(1.0);
    auto set = [&](int b, const Vector3d& to, double l, double g) {
        axis[static_cast<size_t>(b)] = (to - body.bones[static_cast<size_t>(b)].joint).normalized();
        length[static_cast<size_t>(b)] = l;
        girth[static_cast<size_t>(b)] = g;
    };
    const auto joint = [&](int b) { return body.bones[static_cast<size_t>(b)].joint; };
    length[kRoot] = p.torso_length;
    girth[kRoot] = p.torso_girth;
    set(kHead, joint(kHead) + Z, p.neck_length, 1.0);
    set(kLUpperArm, joint(kLLowerArm), p.arm_length, p.limb_girth);
    set(kLLowerArm, body.tips[1], p.arm_length, p.limb_girth);
    set(kRUpperArm, joint(kRLowerArm), p.arm_length, p.limb_girth);
    set(kRLowerArm, body.tips[2], p.arm_length, p.limb_girth);
    set(kLUpperLeg, joint(kLLowerLeg), p.leg_length, p.limb_girth);
    set(kLLowerLeg, body.tips[3], p.leg_length, p.limb_girth);
    set(kRUpperLeg, joint(kRLowerLeg), p.leg_length, p.limb_girth);
    set(kRLowerLeg, body.tips[4], p.leg_length, p.limb_girth);
    set(kTail1, joint(kTail2), p.tail_length, p.limb_girth);
    set(kTail2, joint(kTail3), p.tail_length, p.limb_girth);
    set(kTail3, body.tips[5], p.tail_length, p.limb_girth);
    std::array<Affine, kNumBones> S;
    for (int b = 0; b < kNumBones; ++b) {
        const size_t k = static_cast<size_t>(b);
        const Vector3d& d = axis[k];
        const Matrix3d M =
            length[k] * d * d.transpose() + girth[k] * (Matrix3d::Identity() - d * d.transpose());
        const Vector3d j = body.bones[k].joint;
        const Vector3d moved = body.bones[k].parent < 0 ? j : S[static_cast<size_t>(body.bones[k].parent)](j);
        S[k].A = M;
        S[k].c = moved - M * j;
    }
    return S;
}

}  // namespace

Figure make_figure(int target_vertices, const FigurePose& pose, const FigureProportions& proportions) {
    if (target_vertices < 300 || target_vertices > 1000000)
        throw std::invalid_argument("make_figure: target_vertices must be in [300, 1000000]");
    for (double f :
         {proportions.arm_length, proportions.leg_length, proportions.tail_length, proportions.neck_length,
          proportions.torso_length, proportions.limb_girth, proportions.torso_girth})
        if (!(f >= 0.5 && f <= 2.0))
            throw std::invalid_argument("make_figure: proportions must lie in [0.5, 2]");
    const Body& standard = the_body();
    const std::shared_ptr<const RestFigure> rest = rest_figure(target_vertices);
    const std::array<Affine, kNumBones> S = shape_maps(standard, proportions);
    // The body with its joints where the shape maps put them (the pose rotates about those).
    Body body = standard;
    for (int b = 0; b < kNumBones; ++b) {
        Bone& bone = body.bones[static_cast<size_t>(b)];
        bone.joint = bone.parent < 0 ? bone.joint : S[static_cast<size_t>(bone.parent)](bone.joint);
    }
    const std::array<Rigid, kNumBones> G = bone_transforms(body, pose);

    const bool standard_shape = proportions.arm_length == 1 && proportions.leg_length == 1 &&
                                proportions.tail_length == 1 && proportions.neck_length == 1 &&
                                proportions.torso_length == 1 && proportions.limb_girth == 1 &&
                                proportions.torso_girth == 1;
    Figure fig;
    std::vector<Vector3d> posed(rest->V.size());
    for (size_t i = 0; i < rest->V.size(); ++i) {
        if (standard_shape) {  // exactly the standard figure (no round-off from the identity maps)
            posed[i] = skin(G, rest->V[i], rest->bone[i], rest->weight[i]);
            continue;
        }
        Vector3d shaped = Vector3d::Zero();
        for (int k = 0; k < kInfluences; ++k)
            shaped += rest->weight[i][static_cast<size_t>(k)] *
                      S[static_cast<size_t>(rest->bone[i][static_cast<size_t>(k)])](rest->V[i]);
        posed[i] = skin(G, shaped, rest->bone[i], rest->weight[i]);
    }
    fig.mesh = to_trimesh(posed, rest->F);
    for (size_t t = 0; t < body.tips.size(); ++t)
        fig.limb_tips.push_back(posed[static_cast<size_t>(rest->tip_vertex[t])]);
    fig.limb_names = body.tip_names;
    fig.limb_radius = body.tip_radius;
    const double limb_girth[] = {1.0,
                                 proportions.limb_girth,
                                 proportions.limb_girth,
                                 proportions.limb_girth,
                                 proportions.limb_girth,
                                 proportions.limb_girth};
    for (size_t t = 0; t < fig.limb_radius.size() && t < 6; ++t) fig.limb_radius[t] *= limb_girth[t];
    fig.limb_tip_vertex = rest->tip_vertex;
    return fig;
}

}  // namespace canonform::procedural
