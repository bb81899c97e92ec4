// The scene the viewport draws, built without a window: rigs in metres (the Fox's centimetres
// made metres by the importer), and a glTF character's skinned mesh posed exactly as its capsules are.
#include <algorithm>
#include <iostream>

#include <gtest/gtest.h>

#include "editor/scene.h"
#include "editor/skinning.h"
#include "support/test_support.h"

namespace sinew::editor {
namespace {

EditorState stateWith(const std::filesystem::path& path, const std::string& clip) {
  EditorState state;
  Result<motion::MotionAsset> asset = motion::importMotion(path);
  EXPECT_TRUE(asset.ok()) << asset.message();
  if (!asset.ok()) return state;
  state.asset = std::move(asset).value();
  state.clip_index = clip.empty() ? 0 : state.asset->findClip(clip);
  EXPECT_GE(state.clip_index, 0);
  state.view.show_model = false;  // no analysis here
  return state;
}

TEST(EditorScene, NothingLoadedIsAnEmptySceneWithoutMeshes) {
  const EditorState state;
  const Scene scene = buildScene(state);
  EXPECT_TRUE(scene.empty);
  EXPECT_TRUE(scene.skinned.empty());
  EXPECT_EQ(scene.asset, nullptr);
}

TEST(EditorScene, MetreRigsAreDrawnAsTheyAre) {
  const EditorState walk = stateWith(test::sourceDir() / "assets" / "biped_walk.bvh", "");
  ASSERT_TRUE(walk.asset);
  const Scene scene = buildScene(walk);
  EXPECT_TRUE(scene.skinned.empty());
  EXPECT_FALSE(scene.opaque.empty());
  EXPECT_GT(scene.bounds_max.y - scene.bounds_min.y, 1.4f);  // a person, in metres
}

TEST(EditorScene, FoxIsReadAsCentimetresAndDrawnAboutAMetreLong) {
  SINEW_REQUIRE_SHARED_DATA();
  EditorState fox = stateWith(test::sharedData() / "gltf" / "Fox.glb", "Walk");
  ASSERT_TRUE(fox.asset);
  // The importer made the file's centimetres metres (gltf_units.h): no display scale.
  EXPECT_EQ(fox.asset->detection.frame.unit, motion::LengthUnit::kCentimetres);
  const Scene scene = buildScene(fox);
  ASSERT_EQ(scene.skinned.size(), 1u);
  EXPECT_EQ(scene.asset, &*fox.asset);
  EXPECT_TRUE(scene.opaque.empty());  // the mesh stands for the capsules
  const glm::vec3 size = scene.bounds_max - scene.bounds_min;
  std::cout << "Fox drawn: " << size.x << " x " << size.y << " x " << size.z << " m\n";
  EXPECT_GT(std::max(size.x, size.z), 1.0f);
  EXPECT_LT(std::max(size.x, size.z), 2.0f);
  EXPECT_GT(size.y, 0.5f);
  EXPECT_LT(size.y, 1.2f);
  EXPECT_GT(scene.bounds_min.y, -0.05f);  // standing on the ground, not under it

  fox.view.show_mesh = false;
  const Scene capsules = buildScene(fox);
  EXPECT_TRUE(capsules.skinned.empty());
  EXPECT_FALSE(capsules.opaque.empty());
  fox.view.show_mesh = true;
  fox.view.show_skeleton = true;
  const Scene both = buildScene(fox);
  EXPECT_EQ(both.skinned.size(), 1u);
  EXPECT_EQ(both.xray.size(), capsules.opaque.size());
}

// Bandai's joint_Root stays at the origin while the Hips walk 7-10 m away: no bone is drawn from
// it (a pole across the scene), and the bounds the camera frames hold the character only.
TEST(EditorScene, MasslessRootIsNotDrawnAndNotFramed) {
  SINEW_REQUIRE_SHARED_DATA();
  EditorState walk =
      stateWith(test::sharedData() / "bvh" / "bandai_dataset-1_walk_normal_001.bvh", "");
  ASSERT_TRUE(walk.asset);
  const motion::Skeleton& skeleton = walk.asset->skeleton;
  ASSERT_EQ(skeleton.names[0], "joint_Root");
  const int hips = skeleton.findJoint("Hips");
  ASSERT_EQ(motion::pelvisJoint(skeleton), hips);
  walk.playback.time_s = 5.0;  // metres from the origin by now
  const Scene scene = buildScene(walk);
  const std::vector<glm::dvec3> world =
      motion::worldPositions(skeleton, walk.asset->clips[0], static_cast<int>(5.0 / walk.asset->clips[0].frame_time));
  const glm::vec3 root(world[0]);
  const glm::vec3 pelvis(world[static_cast<size_t>(hips)]);
  ASSERT_GT(glm::length(pelvis - root), 2.0f);
  for (const CapsuleInstance& c : scene.opaque) {
    EXPECT_GT(glm::length(c.a - root), 1.0f);  // nothing drawn at the origin
    EXPECT_GT(glm::length(c.b - root), 1.0f);
  }
  EXPECT_LT(glm::length(scene.root - pelvis), 0.05f);  // the camera follows the hips
  const glm::vec3 size = scene.bounds_max - scene.bounds_min;
  std::cout << "Bandai walk drawn: " << size.x << " x " << size.y << " x " << size.z << " m\n";
  EXPECT_LT(std::max(size.x, size.z), 1.5f);  // a person, not a person and a pole
  EXPECT_GT(size.y, 1.4f);
}

// The mesh follows the capsules: at several playback times (between frames too), every vertex
// bound to one joint keeps its bind-pose distance to that joint, the joint's position taken from
// the capsules the same scene draws.
TEST(EditorScene, FoxMeshFollowsTheCapsulesPose) {
  SINEW_REQUIRE_SHARED_DATA();
  EditorState fox = stateWith(test::sharedData() / "gltf" / "Fox.glb", "Walk");
  ASSERT_TRUE(fox.asset);
  fox.view.show_skeleton = true;
  fox.view.show_end_sites = false;
  const motion::Skeleton& skeleton = fox.asset->skeleton;
  const motion::SkinnedMesh& mesh = fox.asset->meshes.at(0);
  const std::vector<glm::dmat4> rest = motion::restWorldTransforms(skeleton);
  double worst = 0.0;
  int checked = 0;
  for (double t : {0.0, 0.13, 0.29, 0.5}) {
    fox.playback.time_s = t;
    const Scene scene = buildScene(fox);
    ASSERT_EQ(scene.skinned.size(), 1u);
    // Joint positions from the capsules: the body root's ball (the pelvis; the joints above it
    // are not drawn), then per joint the end `b` of the bone from its parent (bones of no length
    // have no capsule).
    std::vector<glm::vec3> joint(static_cast<size_t>(skeleton.jointCount()), glm::vec3(NAN));
    std::vector<bool> above(static_cast<size_t>(skeleton.jointCount()), false);
    for (int j = skeleton.parents[motion::pelvisJoint(skeleton)]; j != motion::kNoParent;
         j = skeleton.parents[j]) {
      above[static_cast<size_t>(j)] = true;
    }
    size_t capsule = 0;
    for (int j = 0; j < skeleton.jointCount(); ++j) {
      if (above[static_cast<size_t>(j)]) continue;
      const int parent = skeleton.parents[j];
      if (parent == motion::kNoParent || above[static_cast<size_t>(parent)]) {
        joint[j] = scene.xray.at(capsule++).a;
      } else if (glm::length(glm::dvec3(rest[j][3]) - glm::dvec3(rest[parent][3])) > 1e-4) {
        joint[j] = scene.xray.at(capsule++).b;
      }
    }
    ASSERT_EQ(capsule, scene.xray.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      if (mesh.weights[v][0] < 0.999f) continue;
      const int j = mesh.joints[v][0];
      if (std::isnan(joint[j].x)) continue;
      const glm::vec3 p = skinPoint(mesh, scene.skinned[0].skinning, v);
      const double bind = glm::length(glm::dvec3(mesh.positions[v]) - glm::dvec3(rest[j][3]));
      worst = std::max(worst, std::abs(glm::length(glm::dvec3(p - joint[j])) - bind));
      ++checked;
    }
  }
  std::cout << "Fox mesh against its capsules: " << checked << " vertex poses, worst "
            << worst * 1000.0 << " mm\n";
  EXPECT_GT(checked, 1000);
  EXPECT_LT(worst, 1e-5);  // metres: float rounding only, between frames too
}

// Many capsules stay within the triangle budget: coarser meshes first, then the largest only.
TEST(SceneTest, ManyCapsulesAreDrawnWithinTheTriangleBudget) {
  EXPECT_EQ(capsuleDetail(16 * 15), 0);     // 16 characters of 15 bodies: the fine capsule
  EXPECT_EQ(capsuleDetail(16 * 15, 1), 1);  // the shadow pass starts coarse
  EXPECT_EQ(capsuleDetail(1000), 1);
  EXPECT_EQ(capsuleDetail(5000), 2);
  std::vector<CapsuleInstance> capsules(10000);
  for (size_t i = 0; i < capsules.size(); ++i) {
    capsules[i].a = glm::vec3(0.0f);
    capsules[i].b = glm::vec3(0.0f, 0.001f * static_cast<float>(i % 997), 0.0f);
    capsules[i].radius = 0.01f;
  }
  capsules[1234].b.y = 50.0f;  // the largest: always kept
  std::vector<CapsuleInstance> scratch;
  const std::span<const CapsuleInstance> drawn = capsulesWithinBudget(capsules, scratch);
  const size_t triangles = drawn.size() * kCapsuleTriangles[capsuleDetail(drawn.size())];
  std::cout << capsules.size() << " capsules: " << drawn.size() << " drawn, " << triangles
            << " triangles (budget " << kCapsuleTriangleBudget << ")\n";
  EXPECT_LE(triangles, kCapsuleTriangleBudget);
  EXPECT_GT(drawn.size(), 5000u);
  EXPECT_NE(std::find_if(drawn.begin(), drawn.end(),
                         [](const CapsuleInstance& c) { return c.b.y == 50.0f; }),
            drawn.end());
  const std::vector<CapsuleInstance> few(100);
  EXPECT_EQ(capsulesWithinBudget(few, scratch).size(), 100u);
}

}  // namespace
}  // namespace sinew::editor
