#include "sinew/physics/body_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "physics_test_util.h"

namespace sinew::physics {
namespace {

motion::Skeleton twoBoneSkeleton() {
  motion::Skeleton s;
  s.addJoint("Hips", motion::kNoParent, {0.0, 1.0, 0.0});
  s.addJoint("Knee", 0, {0.0, -0.5, 0.0});
  s.end_sites[1] = glm::dvec3(0.0, -0.4, 0.0);
  return s;
}

TEST(BodyPlan, RefusesInvalidInputs) {
  const motion::Skeleton good = twoBoneSkeleton();
  ASSERT_TRUE(buildBodyPlan(good, nullptr).ok()) << buildBodyPlan(good, nullptr).message();

  auto refused = [&](BodyPlanSettings settings, const std::string& field) {
    Result<BodyPlan> plan = buildBodyPlan(good, nullptr, settings);
    EXPECT_FALSE(plan.ok()) << field;
    EXPECT_NE(plan.message().find(field), std::string::npos) << plan.message();
  };
  BodyPlanSettings s;
  s.min_segment_length_m = -1.0;
  refused(s, "min_segment_length_m");
  s = {};
  s.max_lost_displacement = -0.1;
  refused(s, "max_lost_displacement");
  s = {};
  s.hinge_dominance = 1.5;
  refused(s, "hinge_dominance");
  s = {};
  s.human_mass_kg = 0.0;
  refused(s, "human_mass_kg");
  s = {};
  s.radius_thigh = 0.0;
  refused(s, "radius_thigh");
  s = {};
  s.density_kg_m3 = std::nan("");
  refused(s, "density_kg_m3");
  s = {};
  s.reference_size_m = 0.0;
  refused(s, "reference_size_m");

  EXPECT_FALSE(buildBodyPlan(motion::Skeleton{}, nullptr).ok());

  motion::Skeleton two_roots = twoBoneSkeleton();
  two_roots.addJoint("Other", motion::kNoParent, {1.0, 0.0, 0.0});
  Result<BodyPlan> r = buildBodyPlan(two_roots, nullptr);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("Other"), std::string::npos) << r.message();

  motion::Clip wrong = motion::restClip(good, 3, 1.0 / 30.0);
  wrong.joint_count = 5;
  r = buildBodyPlan(good, &wrong);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("observed motion"), std::string::npos) << r.message();

  // A plan edited into an invalid state is refused by validate(), naming the link and field.
  BodyPlan plan = buildBodyPlan(good, nullptr).value();
  BodyPlan bad = plan;
  bad.links[1].mass_kg = 0.0;
  EXPECT_NE(bad.validate().message().find("mass_kg"), std::string::npos);
  bad = plan;
  bad.links[1].parent = 5;
  EXPECT_NE(bad.validate().message().find("parent"), std::string::npos);
  bad = plan;
  bad.links[1].inertia.y = -1.0;
  EXPECT_NE(bad.validate().message().find("inertia"), std::string::npos);
  bad = plan;
  bad.total_mass_kg += 1.0;
  EXPECT_NE(bad.validate().message().find("total_mass_kg"), std::string::npos);
  bad = plan;
  bad.links[1].type = JointType::kHinge;
  bad.links[1].hinge_lower = 1.0;
  bad.links[1].hinge_upper = 0.0;
  EXPECT_NE(bad.validate().message().find("hinge_lower"), std::string::npos);
}

void printPlan(const char* label, const BodyPlan& plan, int joints) {
  int ball = 0, hinge = 0, fixed = 0;
  for (const Link& l : plan.links) {
    ball += l.type == JointType::kBall;
    hinge += l.type == JointType::kHinge;
    fixed += l.type == JointType::kFixed;
  }
  std::printf(
      "%s: %d joints -> %zu links (%d ball, %d hinge, %d fixed), %d DOF, %.2f kg, size %.2f m%s\n",
      label, joints, plan.links.size(), ball, hinge, fixed, plan.dofCount(), plan.total_mass_kg,
      plan.size_m, plan.human ? ", human (de Leva)" : ", by volume");
}

// The links' shapes at water density (what buildBodyPlan gives a figure that is not human,
// before its lightest-link floor), kg: what the rig's size alone says it weighs.
double volumeMassKg(const BodyPlan& plan, double density_kg_m3) {
  double volume = 0.0;
  for (const Link& link : plan.links) {
    const Shape& s = link.shape;
    const double ball = 4.0 / 3.0 * std::numbers::pi * s.radius * s.radius * s.radius;
    if (s.type == ShapeType::kBox)
      volume += 8.0 * s.half_extents.x * s.half_extents.y * s.half_extents.z;
    else if (s.type == ShapeType::kCapsule)
      volume += ball + std::numbers::pi * s.radius * s.radius * 2.0 * s.half_length;
    else
      volume += ball;
  }
  return volume * density_kg_m3;
}

// The real glTF rigs arrive in metres (the Fox's centimetres by anatomy, motion/gltf_units.h),
// so their plans have their bodies' size: the Fox's was 155 m across and 95,537,128 kg.
TEST(BodyPlan, RealGltfRigsHaveTheirBodiesSize) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset fox =
      test_util::loadAsset(sinew::test::sharedData() / "gltf" / "Fox.glb");
  ASSERT_GE(fox.clips.size(), 2u);
  Result<BodyPlan> fox_plan = buildBodyPlan(fox.skeleton, &fox.clips[1]);  // Walk
  ASSERT_TRUE(fox_plan.ok()) << fox_plan.message();
  printPlan("Fox (Walk)", fox_plan.value(), fox.skeleton.jointCount());
  const double fox_volume_kg = volumeMassKg(fox_plan.value(), BodyPlanSettings{}.density_kg_m3);
  std::printf("Fox by its shapes' volume: %.2f kg\n", fox_volume_kg);
  EXPECT_GT(fox_plan.value().size_m, 0.8);  // nose to hind paw in the Walk's first pose
  EXPECT_LT(fox_plan.value().size_m, 1.8);
  // A red fox weighs 3-11 kg. Its UpperArm joints once made it a 70 kg human; anatomy names it
  // a quadruped and weighs it by its trunk (anatomy.h). Its capsules, whose radii are human
  // fractions of the rig's size, would weigh 92 kg by volume: they only share the mass out.
  EXPECT_FALSE(fox_plan.value().human);
  EXPECT_GT(fox_plan.value().total_mass_kg, 4.0);
  EXPECT_LT(fox_plan.value().total_mass_kg, 8.0);
  EXPECT_LT(fox_volume_kg, 100.0);

  const motion::MotionAsset figure =
      test_util::loadAsset(sinew::test::sharedData() / "gltf" / "RiggedFigure.glb");
  ASSERT_FALSE(figure.clips.empty());
  Result<BodyPlan> figure_plan = buildBodyPlan(figure.skeleton, &figure.clips[0]);
  ASSERT_TRUE(figure_plan.ok()) << figure_plan.message();
  printPlan("RiggedFigure", figure_plan.value(), figure.skeleton.jointCount());
  EXPECT_GT(figure_plan.value().size_m, 1.0);  // ankles to neck of a 1.45 m person
  EXPECT_LT(figure_plan.value().size_m, 1.5);
  EXPECT_GT(figure_plan.value().total_mass_kg, 25.0);  // a slight adult or a child
  EXPECT_LT(figure_plan.value().total_mass_kg, 80.0);
}

TEST(BodyPlan, BipedFromAssetHasHumanMassesHingedKneesAndBoxFeet) {
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const motion::Skeleton& skeleton = asset.skeleton;
  Result<BodyPlan> built = buildBodyPlan(skeleton, &asset.clips[0]);
  ASSERT_TRUE(built.ok()) << built.message();
  const BodyPlan& plan = built.value();
  printPlan("biped_walk.bvh", plan, skeleton.jointCount());
  for (const Link& l : plan.links) {
    std::printf("  %-14s parent %2d %-6s mass %6.2f kg shape %d", l.name.c_str(), l.parent,
                jointTypeName(l.type), l.mass_kg, static_cast<int>(l.shape.type));
    if (l.type == JointType::kHinge)
      std::printf(" axis (%.2f %.2f %.2f) [%.0f, %.0f] deg", l.hinge_axis.x, l.hinge_axis.y,
                  l.hinge_axis.z, l.hinge_lower * 57.2958, l.hinge_upper * 57.2958);
    std::printf("\n");
  }
  for (const std::string& note : plan.notes) std::printf("  note: %s\n", note.c_str());

  EXPECT_TRUE(plan.human);
  // 70 kg for 1.75 m at the same body-mass index: its thigh and shank, 0.84 m, make it 1.71 m.
  EXPECT_NEAR(plan.total_mass_kg, 70.0 * std::pow(0.84 / 0.491 / 1.75, 2.0), 0.05);
  EXPECT_LT(static_cast<int>(plan.links.size()), skeleton.jointCount());
  ASSERT_EQ(static_cast<int>(plan.link_of_joint.size()), skeleton.jointCount());
  int feet = 0, knees = 0;
  for (const Link& l : plan.links) {
    if (l.foot) {
      ++feet;
      EXPECT_EQ(l.shape.type, ShapeType::kBox) << l.name;
    }
    if (l.segment == motion::Segment::kShank) {
      ++knees;
      EXPECT_EQ(l.type, JointType::kHinge) << l.name;
      EXPECT_LT(l.hinge_lower, l.hinge_upper);
    }
    EXPECT_GT(l.mass_kg, 0.0);
  }
  EXPECT_EQ(feet, 2);
  EXPECT_EQ(knees, 2);
  // Every joint maps to a link whose pivot joint is itself or one of its ancestors.
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const int pivot =
        plan.links[static_cast<size_t>(plan.link_of_joint[static_cast<size_t>(j)])].joint;
    int a = j;
    while (a != pivot && a != motion::kNoParent) a = skeleton.parents[static_cast<size_t>(a)];
    EXPECT_TRUE(a == pivot || j < pivot) << skeleton.names[static_cast<size_t>(j)];
  }
}

TEST(BodyPlan, LinkPoseReproducesTheClipsLinkRotations) {
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const motion::Skeleton& skeleton = asset.skeleton;
  const motion::Clip& clip = asset.clips[0];
  const BodyPlan plan = buildBodyPlan(skeleton, &clip).value();
  // World rotation of every link frame from link coordinates equals the skeleton's, except for
  // what a hinge drops (the off-axis part of knee motion, small for a clip that made it a hinge).
  const int frame = clip.frame_count / 2;
  const size_t n = static_cast<size_t>(skeleton.jointCount());
  const LinkPose pose =
      linkPoseFromSkeleton(plan, skeleton, std::span(clip.rotations.data() + frame * n, n),
                           std::span(clip.translations.data() + frame * n, n));
  std::vector<glm::dmat4> world(n);
  motion::worldTransforms(skeleton, clip, frame, world);
  std::vector<glm::dquat> link_world(plan.links.size());
  double worst_ball = 0.0;
  for (size_t li = 0; li < plan.links.size(); ++li) {
    const Link& l = plan.links[li];
    link_world[li] = li == 0 ? pose.base_rotation
                             : link_world[static_cast<size_t>(l.parent)] *
                                   linkRelativeRotation(l, pose.rotations[li], pose.angles[li]);
    const glm::dquat expected = glm::quat_cast(glm::dmat3(world[static_cast<size_t>(l.joint)]));
    const double err =
        2.0 * std::acos(std::min(1.0, std::abs(glm::dot(glm::normalize(link_world[li]),
                                                        glm::normalize(expected)))));
    bool hinge_above = false;
    for (int a = static_cast<int>(li); a > 0; a = plan.links[static_cast<size_t>(a)].parent)
      hinge_above = hinge_above || plan.links[static_cast<size_t>(a)].type != JointType::kBall;
    if (!hinge_above) worst_ball = std::max(worst_ball, err);
    EXPECT_LT(err, 0.35) << l.name;
  }
  std::printf("link world rotations vs skeleton (ball-only chains): worst %.2e rad\n", worst_ball);
  EXPECT_LT(worst_ball, 1e-9);
}

TEST(BodyPlan, CmuZeroLengthHipJointsMergeIntoThePelvis) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sharedData() / "bvh" / "cmu_131_01.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const BodyPlan plan = buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
  printPlan("cmu_131_01.bvh", plan, asset.skeleton.jointCount());
  for (const char* name : {"LHipJoint", "RHipJoint"}) {
    const int j = asset.skeleton.findJoint(name);
    if (j < 0) continue;
    EXPECT_EQ(plan.link_of_joint[static_cast<size_t>(j)], 0) << name;
  }
  for (const Link& l : plan.links) EXPECT_EQ(l.name.find("Finger"), std::string::npos) << l.name;
}

// Hips, a Spine at the hips' own point (as the MANN dog's), a Chest 30 cm above it, a Head; two
// legs with feet.
motion::Skeleton spineOnTheHips() {
  motion::Skeleton s;
  s.addJoint("Hips", motion::kNoParent, {0.0, 1.0, 0.0});
  const int spine = s.addJoint("Spine", 0, {0.0, 0.0, 0.0});
  const int chest = s.addJoint("Chest", spine, {0.0, 0.3, 0.0});
  const int head = s.addJoint("Head", chest, {0.0, 0.3, 0.0});
  s.end_sites[static_cast<size_t>(head)] = glm::dvec3(0.0, 0.2, 0.0);
  for (const double side : {1.0, -1.0}) {
    const std::string name = side > 0.0 ? "Left" : "Right";
    const int hip = s.addJoint(name + "UpLeg", 0, {0.1 * side, -0.05, 0.0});
    const int knee = s.addJoint(name + "Leg", hip, {0.0, -0.45, 0.0});
    const int foot = s.addJoint(name + "Foot", knee, {0.0, -0.42, 0.0});
    s.end_sites[static_cast<size_t>(foot)] = glm::dvec3(0.0, -0.08, 0.15);
  }
  return s;
}

// The Spine turning +-15 degrees about `axis` over 60 frames, everything else at rest.
motion::Clip spineTurning(const motion::Skeleton& s, const glm::dvec3& axis) {
  motion::Clip clip = motion::restClip(s, 60, 1.0 / 30.0);
  const int spine = s.findJoint("Spine");
  for (int f = 0; f < clip.frame_count; ++f)
    clip.rotations[static_cast<size_t>(f * clip.joint_count + spine)] =
        glm::angleAxis(0.26 * std::sin(2.0 * std::numbers::pi * f / 60.0), axis);
  return clip;
}

// The largest distance over the clip between the Chest's pivot in the body's pose and in the clip.
double chestPivotError(const BodyPlan& plan, const motion::Skeleton& s, const motion::Clip& clip) {
  const int chest = s.findJoint("Chest");
  const int link = plan.link_of_joint[static_cast<size_t>(chest)];
  EXPECT_EQ(plan.links[static_cast<size_t>(link)].joint, chest);
  std::vector<glm::dmat4> world(static_cast<size_t>(s.jointCount()));
  double worst = 0.0;
  for (int f = 0; f < clip.frame_count; ++f) {
    const auto first = static_cast<std::ptrdiff_t>(f * clip.joint_count);
    const std::vector<glm::dquat> rotations(clip.rotations.begin() + first,
                                            clip.rotations.begin() + first + clip.joint_count);
    const std::vector<glm::dvec3> translations(clip.translations.begin() + first,
                                               clip.translations.begin() + first + clip.joint_count);
    const PoseKinematics body = poseKinematics(plan, linkPoseFromSkeleton(plan, s, rotations, translations));
    motion::worldTransforms(s, clip, f, world);
    worst = std::max(worst, glm::length(body.pivots[static_cast<size_t>(link)] -
                                        glm::dvec3(world[static_cast<size_t>(chest)][3])));
  }
  return worst;
}

// A short joint whose turning carries its children keeps a link of its own. Merged into its
// parent's link, its rotation would turn the children's links about their own pivots, and the
// clip's sway of them would be lost (the MANN dog's forepaws rode 3-5 cm into the ground).
TEST(BodyPlan, AShortJointThatCarriesItsChildrenKeepsALink) {
  const motion::Skeleton s = spineOnTheHips();
  const size_t spine = static_cast<size_t>(s.findJoint("Spine"));
  // Pitched: the chest's pivot sways 0.3 m x 2 sin(7.5 deg) = 7.8 cm either side of its mean.
  const motion::Clip pitched = spineTurning(s, {1.0, 0.0, 0.0});
  const BodyPlan plan = buildBodyPlan(s, &pitched).value();
  EXPECT_NE(plan.link_of_joint[spine], 0);
  EXPECT_LT(chestPivotError(plan, s, pitched), 1e-9);
  // Merged anyway (the rule off), the body's chest misses the clip's by up to the sway.
  BodyPlanSettings merge;
  merge.max_lost_displacement = 1e9;
  const BodyPlan merged = buildBodyPlan(s, &pitched, merge).value();
  EXPECT_EQ(merged.link_of_joint[spine], 0);
  EXPECT_GT(chestPivotError(merged, s, pitched), 0.07);
  // Twisted about the chest's own direction, the Spine moves nothing: it merges as before.
  const motion::Clip twisted = spineTurning(s, {0.0, 1.0, 0.0});
  const BodyPlan twist = buildBodyPlan(s, &twisted).value();
  EXPECT_EQ(twist.link_of_joint[spine], 0);
  EXPECT_LT(chestPivotError(twist, s, twisted), 1e-9);
  // Without a clip nothing is known to move: it merges.
  EXPECT_EQ(buildBodyPlan(s, nullptr).value().link_of_joint[spine], 0);
}

// The user's overrides win over the rules, and a name that is not a link is refused, named.
TEST(BodyPlan, OverridesSetMassesJointTypesAndHingeLimits) {
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const BodyPlan plain = buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
  BodyPlanSettings settings;
  settings.mass_overrides = {{"Head", 6.0}};
  settings.type_overrides = {{"LeftArm", JointType::kFixed}};
  settings.hinge_limit_overrides = {{"LeftLeg", {-0.1, 2.0}}};
  const BodyPlan plan = buildBodyPlan(asset.skeleton, &asset.clips[0], settings).value();
  auto link = [](const BodyPlan& p, const std::string& name) -> const Link& {
    for (const Link& l : p.links)
      if (l.name == name) return l;
    ADD_FAILURE() << name;
    return p.links[0];
  };
  EXPECT_DOUBLE_EQ(link(plan, "Head").mass_kg, 6.0);
  EXPECT_NEAR(plan.total_mass_kg, plain.total_mass_kg + 6.0 - link(plain, "Head").mass_kg, 1e-9);
  EXPECT_GT(link(plan, "Head").inertia.x, link(plain, "Head").inertia.x);
  EXPECT_EQ(link(plan, "LeftArm").type, JointType::kFixed);
  EXPECT_EQ(plan.dofCount(), plain.dofCount() - 3);
  EXPECT_DOUBLE_EQ(link(plan, "LeftLeg").hinge_lower, -0.1);
  EXPECT_DOUBLE_EQ(link(plan, "LeftLeg").hinge_upper, 2.0);
  BodyPlanSettings bad;
  bad.mass_overrides = {{"Tail", 1.0}};
  Result<BodyPlan> refused = buildBodyPlan(asset.skeleton, &asset.clips[0], bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("mass_overrides: no link named 'Tail'"), std::string::npos)
      << refused.message();
  bad = {};
  bad.hinge_limit_overrides = {{"LeftArm", {0.0, 1.0}}};
  EXPECT_NE(buildBodyPlan(asset.skeleton, &asset.clips[0], bad).message().find("no hinge named"),
            std::string::npos);
}

}  // namespace
}  // namespace sinew::physics
