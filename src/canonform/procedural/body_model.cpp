// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the figure's body: bones, tapered capsules and its signed distance. See body_model.h.
#include "canonform/procedural/body_model.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace canonform::procedural {
namespace detail {
namespace {

Vector3d mirror_x(const Vector3d& p) {
    return Vector3d(-p.x(), p.y(), p.z());
}

Body build_body() {
    Body b;
    auto add_chain = [&](std::vector<Capsule> caps) { b.chains.push_back(Chain{std::move(caps)}); };
    // Trunk (root bone): torso, shoulder girdle, hips.
    add_chain({{{0, 0, 0.92}, {0, 0, 1.40}, 0.19, 0.19, kRoot}});
    add_chain({{{-0.26, 0, 1.44}, {0.26, 0, 1.44}, 0.10, 0.10, kRoot}});
    add_chain({{{-0.12, 0, 0.90}, {0.12, 0, 0.90}, 0.13, 0.13, kRoot}});
    // Neck and head; the head is elongated front-back so that turning it changes the shape.
    add_chain({{{0, 0, 1.45}, {0, 0, 1.70}, 0.065, 0.065, kHead}});
    add_chain({{{0, 0.03, 1.82}, {0, -0.05, 1.82}, 0.14, 0.14, kHead}});
    // Arms (T-pose): shoulder, elbow, wrist.
    const Vector3d sh(0.26, 0, 1.44), el(0.60, 0, 1.44), wr(0.93, 0, 1.44);
    const double r_sh = 0.065, r_el = 0.055, r_wr = 0.045;
    add_chain({{sh, el, r_sh, r_el, kLUpperArm}, {el, wr, r_el, r_wr, kLLowerArm}});
    add_chain({{mirror_x(sh), mirror_x(el), r_sh, r_el, kRUpperArm},
               {mirror_x(el), mirror_x(wr), r_el, r_wr, kRLowerArm}});
    // Legs, spread outwards: hip, knee, ankle.
    const Vector3d hp(0.12, 0, 0.88), kn(0.23, 0, 0.48), an(0.34, 0, 0.07);
    const double r_hp = 0.08, r_kn = 0.068, r_an = 0.052;
    add_chain({{hp, kn, r_hp, r_kn, kLUpperLeg}, {kn, an, r_kn, r_an, kLLowerLeg}});
    add_chain({{mirror_x(hp), mirror_x(kn), r_hp, r_kn, kRUpperLeg},
               {mirror_x(kn), mirror_x(an), r_kn, r_an, kRLowerLeg}});
    // Tail, straight back from the lower back.
    const Vector3d t0(0, 0.10, 0.86), t1(0, 0.40, 0.74), t2(0, 0.68, 0.70), t3(0, 0.92, 0.74);
    add_chain(
        {{t0, t1, 0.060, 0.052, kTail1}, {t1, t2, 0.052, 0.045, kTail2}, {t2, t3, 0.045, 0.040, kTail3}});

    b.bones.resize(kNumBones);
    b.bones[kRoot] = {-1, Vector3d(0, 0, 0.9)};
    b.bones[kHead] = {kRoot, Vector3d(0, 0, 1.50)};
    b.bones[kLUpperArm] = {kRoot, sh};
    b.bones[kLLowerArm] = {kLUpperArm, el};
    b.bones[kRUpperArm] = {kRoot, mirror_x(sh)};
    b.bones[kRLowerArm] = {kRUpperArm, mirror_x(el)};
    b.bones[kLUpperLeg] = {kRoot, hp};
    b.bones[kLLowerLeg] = {kLUpperLeg, kn};
    b.bones[kRUpperLeg] = {kRoot, mirror_x(hp)};
    b.bones[kRLowerLeg] = {kRUpperLeg, mirror_x(kn)};
    b.bones[kTail1] = {kRoot, t0};
    b.bones[kTail2] = {kTail1, t1};
    b.bones[kTail3] = {kTail2, t2};

    const Vector3d foot_dir = (an - kn).normalized(), tail_dir = (t3 - t2).normalized();
    b.tip_names = {"head", "left_hand", "right_hand", "left_foot", "right_foot", "tail"};
    const Vector3d head_top(0, -0.01, 1.82 + 0.14), hand = wr + r_wr * Vector3d::UnitX(),
                                                    foot = an + r_an * foot_dir;
    b.tips = {head_top, hand, mirror_x(hand), foot, mirror_x(foot), t3 + 0.040 * tail_dir};
    b.tip_radius = {0.14, r_wr, r_wr, r_an, r_an, 0.040};

    for (Chain& ch : b.chains) {
        Eigen::AlignedBox3d bb;
        for (const Capsule& c : ch.caps) bb.extend(c.a).extend(c.b);
        ch.centre = bb.center();
        for (const Capsule& c : ch.caps)
            ch.radius =
                std::max({ch.radius, (c.a - ch.centre).norm() + c.ra, (c.b - ch.centre).norm() + c.rb});
    }
    b.box.setEmpty();
    b.min_radius = std::numeric_limits<double>::infinity();
    for (const Chain& ch : b.chains) {
        for (const Capsule& c : ch.caps) {
            b.caps.push_back(c);
            b.box.extend(c.a - Vector3d::Constant(c.ra));
            b.box.extend(c.a + Vector3d::Constant(c.ra));
            b.box.extend(c.b - Vector3d::Constant(c.rb));
            b.box.extend(c.b + Vector3d::Constant(c.rb));
            b.min_radius = std::min({b.min_radius, c.ra, c.rb});
        }
    }
    // The smooth min moves the surface outwards by at most k/4.
    b.box.min() -= Vector3d::Constant(0.25 * b.blend + 1e-3);
    b.box.max() += Vector3d::Constant(0.25 * b.blend + 1e-3);
    return b;
}

}  // namespace

const Body& the_body() {
    static const Body body = build_body();
    return body;
}

}  // namespace detail
}  // namespace canonform::procedural
