// The editor's reading of glTF materials: refusals name the file; Fox's base colour texture and
// texture coordinates; RiggedFigure's plain base colour; BVH assets get the default grey.
#include <gtest/gtest.h>

#include "editor/materials.h"
#include "sinew/motion/asset.h"
#include "support/test_support.h"

namespace sinew::editor {
namespace {

motion::MotionAsset loadShared(const std::string& name) {
  Result<motion::MotionAsset> asset = motion::importMotion(test::sharedData() / "gltf" / name);
  EXPECT_TRUE(asset.ok()) << asset.message();
  return asset.ok() ? std::move(asset).value() : motion::MotionAsset{};
}

TEST(EditorMaterials, RefusesBytesThatDoNotParseOrMeshesThatDoNotMatch) {
  motion::MotionAsset asset;
  asset.path = "broken.glb";
  asset.meshes.resize(1);
  asset.meshes[0].positions.resize(3);
  auto source = std::make_shared<motion::GltfSource>();
  source->bytes = "glTF this is not a GLB";
  source->binary = true;
  asset.gltf = source;
  Result<std::vector<MeshMaterial>> read = readMaterials(asset);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.message().find("broken.glb: materials:"), std::string::npos) << read.message();

  // A document with no skinned primitive for the imported mesh.
  source->binary = false;
  source->bytes =
      R"({"asset": {"version": "2.0"}, "nodes": [{"name": "a"}], "scenes": [{"nodes": [0]}]})";
  read = readMaterials(asset);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.message().find("found 0 skinned primitives for 1 imported meshes"),
            std::string::npos)
      << read.message();
}

TEST(EditorMaterials, AssetsWithoutGltfGetTheDefaultGrey) {
  Result<motion::MotionAsset> walk =
      motion::importMotion(test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_TRUE(walk.ok()) << walk.message();
  Result<std::vector<MeshMaterial>> read = readMaterials(walk.value());
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_TRUE(read.value().empty());  // no meshes
}

TEST(EditorMaterials, FoxIsTexturedWithItsOrangeCoat) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset fox = loadShared("Fox.glb");
  Result<std::vector<MeshMaterial>> read = readMaterials(fox);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read.value().size(), 1u);
  const MeshMaterial& material = read.value()[0];
  EXPECT_TRUE(material.textured());
  EXPECT_TRUE(material.note.empty()) << material.note;
  EXPECT_EQ(material.base_color, glm::vec4(1.0f));  // glTF's default factor
  EXPECT_EQ(material.texcoords.size(), 1728u);
  ASSERT_GT(material.width, 0);
  ASSERT_EQ(material.rgba.size(), static_cast<size_t>(material.width) * material.height * 4);
  // What the mesh shows: the texture under its texture coordinates, mostly orange (red over
  // green over blue).
  int orange = 0;
  for (const glm::vec2& uv : material.texcoords) {
    EXPECT_GE(uv.x, -1e-3f);
    EXPECT_LE(uv.x, 1.001f);
    const int x = std::clamp(static_cast<int>(uv.x * material.width), 0, material.width - 1);
    const int y = std::clamp(static_cast<int>(uv.y * material.height), 0, material.height - 1);
    const std::uint8_t* p = &material.rgba[(static_cast<size_t>(y) * material.width + x) * 4];
    if (p[0] > 150 && p[0] > p[1] + 30 && p[1] > p[2] + 20) ++orange;
  }
  std::cout << "Fox: " << material.width << "x" << material.height << " texture, " << orange
            << " of 1728 vertices on orange\n";
  EXPECT_GT(orange, 1728 / 3);
}

TEST(EditorMaterials, RiggedFigureHasAPlainBaseColour) {
  SINEW_REQUIRE_SHARED_DATA();
  const motion::MotionAsset figure = loadShared("RiggedFigure.glb");
  Result<std::vector<MeshMaterial>> read = readMaterials(figure);
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_EQ(read.value().size(), 1u);
  const MeshMaterial& material = read.value()[0];
  EXPECT_FALSE(material.textured());
  EXPECT_NEAR(material.base_color.r, 0.8f, 1e-6f);
  EXPECT_NEAR(material.base_color.a, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace sinew::editor
