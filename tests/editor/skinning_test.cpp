// Linear blend skinning on the CPU (the matrices the vertex shader blends): invalid input first,
// then the real rigs. In the bind pose every vertex must land where the file puts the mesh
// (mesh_to_world * position): Fox (identity mesh node, centimetres made metres) and RiggedFigure (a
// Z-up -> Y-up rotation on the mesh node). Posed, a vertex moves rigidly with its joints.
#include <algorithm>
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "editor/skinning.h"
#include "sinew/motion/asset.h"
#include "support/test_support.h"

namespace sinew::editor {
namespace {

motion::MotionAsset loadShared(const std::string& name) {
  Result<motion::MotionAsset> asset = motion::importMotion(test::sharedData() / "gltf" / name);
  EXPECT_TRUE(asset.ok()) << asset.message();
  return asset.ok() ? std::move(asset).value() : motion::MotionAsset{};
}

// The largest extent of the mesh where the file puts it, metres.
double meshExtent(const motion::SkinnedMesh& mesh) {
  glm::dvec3 lo(1e30), hi(-1e30);
  for (const glm::vec3& p : mesh.positions) {
    const glm::dvec3 q(mesh.mesh_to_world * glm::dvec4(glm::dvec3(p), 1.0));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
}

// Worst distance, relative to the mesh's extent, between the bind-pose skinned mesh and
// mesh_to_world * position.
double bindPoseError(const motion::MotionAsset& asset, const motion::SkinnedMesh& mesh) {
  const std::vector<glm::dmat4> rest = motion::restWorldTransforms(asset.skeleton);
  std::vector<glm::mat4> skinning(rest.size());
  skinningMatrices(mesh, rest, skinning);
  double worst = 0.0;
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec3 expected(mesh.mesh_to_world * glm::dvec4(glm::dvec3(mesh.positions[v]), 1.0));
    worst = std::max(worst, glm::length(glm::dvec3(skinPoint(mesh, skinning, v)) - expected));
  }
  return worst / meshExtent(mesh);
}

TEST(EditorSkinning, EmptyAndDegenerateInputDoNothingOrKeepDefaults) {
  motion::SkinnedMesh mesh;  // no vertices, no joints
  std::vector<glm::mat4> out;
  skinningMatrices(mesh, {}, out);
  glm::vec3 lo(1.0f), hi(-1.0f);
  growSkinnedBounds(mesh, out, 100, lo, hi);
  EXPECT_EQ(lo, glm::vec3(1.0f));  // an empty mesh leaves the box alone
  SkinGeometry empty = buildSkinGeometry(mesh, {});
  EXPECT_TRUE(empty.vertices.empty());
  EXPECT_TRUE(empty.indices.empty());

  // A degenerate triangle (all corners at one point) keeps the default normal, not NaN.
  mesh.positions = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f)};
  mesh.joints.assign(3, glm::u16vec4(0));
  mesh.weights.assign(3, glm::vec4(1, 0, 0, 0));
  mesh.indices = {0, 1, 2};
  const SkinGeometry flat = buildSkinGeometry(mesh, {});
  ASSERT_EQ(flat.vertices.size(), 3u);
  for (const SkinVertex& v : flat.vertices) EXPECT_EQ(v.normal, glm::vec3(0, 1, 0));
  // Texture coordinates of the wrong count are ignored rather than read past their end.
  const std::vector<glm::vec2> short_uvs(2, glm::vec2(0.5f));
  const SkinGeometry untextured = buildSkinGeometry(mesh, short_uvs);
  for (const SkinVertex& v : untextured.vertices) EXPECT_EQ(v.uv, glm::vec2(0.0f));
}

TEST(EditorSkinning, MatricesAreWorldTimesInverseBind) {
  motion::SkinnedMesh mesh;
  mesh.inverse_bind = {glm::translate(glm::dmat4(1.0), glm::dvec3(0, -2, 0)),
                       glm::rotate(glm::dmat4(1.0), 0.5, glm::dvec3(0, 0, 1))};
  const std::vector<glm::dmat4> world = {glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)),
                                         glm::rotate(glm::dmat4(1.0), -0.5, glm::dvec3(0, 0, 1))};
  std::vector<glm::mat4> out(2);
  skinningMatrices(mesh, world, out);
  for (size_t j = 0; j < 2; ++j) {
    const glm::dmat4 expected = world[j] * mesh.inverse_bind[j];
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(out[j][c][r], expected[c][r], 1e-7) << j;
    }
  }
  // A vertex split evenly between the two joints lands halfway between their placements.
  mesh.positions = {glm::vec3(1, 0, 0)};
  mesh.joints = {glm::u16vec4(0, 1, 0, 0)};
  mesh.weights = {glm::vec4(0.5f, 0.5f, 0, 0)};
  const glm::vec3 a(out[0] * glm::vec4(1, 0, 0, 1)), b(out[1] * glm::vec4(1, 0, 0, 1));
  const glm::vec3 p = skinPoint(mesh, out, 0);
  EXPECT_NEAR(glm::length(p - 0.5f * (a + b)), 0.0f, 1e-6f);
}

TEST(EditorSkinning, FoxBindPoseGivesTheMeshAsTheFilePlacesIt) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset fox = loadShared("Fox.glb");
  ASSERT_EQ(fox.meshes.size(), 1u);
  const motion::SkinnedMesh& mesh = fox.meshes[0];
  ASSERT_EQ(mesh.positions.size(), 1728u);
  const double error = bindPoseError(fox, mesh);
  std::cout << "Fox bind pose: worst vertex " << error << " of the mesh's " << meshExtent(mesh)
            << " m extent\n";
  EXPECT_LT(error, 1e-4);
  // Centimetres in the file, metres here: nose to tail 155 cm, a fox (with its tail).
  EXPECT_NEAR(meshExtent(mesh), 1.55, 0.01);
}

TEST(EditorSkinning, RiggedFigureBindPoseIgnoresTheMeshNodeAsGltfSays) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset figure = loadShared("RiggedFigure.glb");
  ASSERT_EQ(figure.meshes.size(), 1u);
  const motion::SkinnedMesh& mesh = figure.meshes[0];
  // The mesh node turns Z-up into Y-up: a skinning that applied it again would lay the figure
  // on its back, 2 m off.
  EXPECT_LT(std::abs(mesh.mesh_to_world[1][1]), 1e-6);
  const double error = bindPoseError(figure, mesh);
  std::cout << "RiggedFigure bind pose: worst vertex " << error << " of the extent\n";
  EXPECT_LT(error, 1e-4);
}

// Posed, each vertex bound to one joint keeps its place in that joint's frame, so its distance
// to the joint is the bind pose's; and the whole mesh moves.
TEST(EditorSkinning, FoxWalkMovesVerticesRigidlyWithTheirJoint) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset fox = loadShared("Fox.glb");
  ASSERT_EQ(fox.meshes.size(), 1u);
  const motion::SkinnedMesh& mesh = fox.meshes[0];
  const int walk = fox.findClip("Walk");
  ASSERT_GE(walk, 0);
  const motion::Clip& clip = fox.clips[static_cast<size_t>(walk)];
  const std::vector<glm::dmat4> rest = motion::restWorldTransforms(fox.skeleton);
  std::vector<glm::dmat4> world(rest.size());
  std::vector<glm::mat4> skinning(rest.size());
  int rigid = 0;
  double worst = 0.0, moved = 0.0;
  for (int frame : {0, 5, 11, clip.frame_count - 1}) {
    motion::worldTransforms(fox.skeleton, clip, frame, world);
    skinningMatrices(mesh, world, skinning);
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec3 p = skinPoint(mesh, skinning, v);
      moved = std::max(moved, static_cast<double>(glm::length(p - mesh.positions[v])));
      if (mesh.weights[v][0] < 0.999f) continue;
      const int j = mesh.joints[v][0];
      const double bind = glm::length(glm::dvec3(mesh.positions[v]) - glm::dvec3(rest[j][3]));
      const double posed = glm::length(glm::dvec3(p) - glm::dvec3(world[j][3]));
      worst = std::max(worst, std::abs(posed - bind));
      ++rigid;
    }
  }
  std::cout << "Fox Walk: " << rigid << " single-joint vertex poses, worst change in distance to "
            << "the joint " << worst * 1000.0 << " mm; vertices moved up to " << moved << " m\n";
  EXPECT_GT(rigid, 1000);
  EXPECT_LT(worst, 1e-5);  // metres: float rounding only
  EXPECT_GT(moved, 0.05);  // the walk really moves the mesh (feet swing tens of centimetres)
}

TEST(EditorSkinning, FoxHasNoNormalsSoItIsFlatShaded) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset fox = loadShared("Fox.glb");
  ASSERT_EQ(fox.meshes.size(), 1u);
  const motion::SkinnedMesh& mesh = fox.meshes[0];
  ASSERT_TRUE(mesh.normals.empty());
  const SkinGeometry geometry = buildSkinGeometry(mesh, {});
  EXPECT_TRUE(geometry.flat);
  ASSERT_EQ(geometry.vertices.size(), mesh.indices.size());
  ASSERT_EQ(geometry.indices.size(), mesh.indices.size());
  for (size_t t = 0; t + 2 < geometry.indices.size(); t += 3) {
    const SkinVertex& a = geometry.vertices[geometry.indices[t]];
    const SkinVertex& b = geometry.vertices[geometry.indices[t + 1]];
    const SkinVertex& c = geometry.vertices[geometry.indices[t + 2]];
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.normal, c.normal);
    EXPECT_NEAR(glm::length(a.normal), 1.0f, 1e-5f);
    // Perpendicular to the face's edges (where the face has any size).
    const glm::vec3 e1 = b.position - a.position, e2 = c.position - a.position;
    if (glm::length(glm::cross(e1, e2)) > 1e-3f) {
      EXPECT_NEAR(glm::dot(a.normal, glm::normalize(e1)), 0.0f, 1e-4f);
      EXPECT_NEAR(glm::dot(a.normal, glm::normalize(e2)), 0.0f, 1e-4f);
    }
  }
}

TEST(EditorSkinning, RiggedFigureKeepsItsNormalsAndIndices) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset figure = loadShared("RiggedFigure.glb");
  ASSERT_EQ(figure.meshes.size(), 1u);
  const motion::SkinnedMesh& mesh = figure.meshes[0];
  const SkinGeometry geometry = buildSkinGeometry(mesh, {});
  EXPECT_FALSE(geometry.flat);
  EXPECT_EQ(geometry.vertices.size(), mesh.positions.size());
  EXPECT_EQ(geometry.indices, mesh.indices);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    EXPECT_EQ(geometry.vertices[v].normal, mesh.normals[v]);
    EXPECT_EQ(geometry.vertices[v].joints, mesh.joints[v]);
  }
}

}  // namespace
}  // namespace sinew::editor
