// glTF import and export. Real files (Fox, RiggedFigure) are checked against their own key data,
// read here independently of the importer; small documents written by the tests cover each
// interpolation and accessor layout; corrupt input must be refused with the file's name; every
// export must re-import to the same motion and pass the Khronos validator.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <numbers>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/motion/anatomy.h"
#include "sinew/motion/bvh.h"
#include "sinew/motion/gltf.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

using nlohmann::json;

std::filesystem::path gltfData(const std::string& name) {
  return test::sharedData() / "gltf" / name;
}

MotionAsset load(const std::filesystem::path& path, const ImportOptions& options = {}) {
  Result<MotionAsset> asset = loadGltf(path, options);
  EXPECT_TRUE(asset.ok()) << asset.message();
  return asset.ok() ? std::move(asset).value() : MotionAsset{};
}

const Clip& clipNamed(const MotionAsset& asset, const std::string& name) {
  const int index = asset.findClip(name);
  EXPECT_GE(index, 0) << "no clip " << name;
  return asset.clips.at(std::max(index, 0));
}

// Angle between two rotations, radians (sign of the quaternion ignored).
double angleBetween(const glm::dquat& a, const glm::dquat& b) {
  return 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(glm::normalize(a), glm::normalize(b)))));
}

// ------------------------------------------------------------------------------------------------
// Reading a GLB here, without the importer: the JSON chunk and the binary chunk.

struct Glb {
  json doc;
  std::string bin;
};

Glb splitGlb(const std::string& bytes) {
  Glb glb;
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, bytes.data() + 12, 4);
  glb.doc = json::parse(bytes.substr(20, json_length));
  const size_t bin_at = 20 + json_length;
  if (bin_at + 8 <= bytes.size()) {
    std::uint32_t bin_length = 0;
    std::memcpy(&bin_length, bytes.data() + bin_at, 4);
    glb.bin = bytes.substr(bin_at + 8, bin_length);
  }
  return glb;
}

// A tightly packed float accessor's numbers (Fox.glb's animation data is stored that way).
std::vector<float> floatAccessor(const Glb& glb, int index) {
  const json& accessor = glb.doc["accessors"][index];
  EXPECT_EQ(accessor["componentType"], 5126);
  const std::string type = accessor["type"];
  const size_t width = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 16;
  const json& view = glb.doc["bufferViews"][accessor["bufferView"].get<int>()];
  EXPECT_FALSE(view.contains("byteStride"));
  const size_t offset =
      view.value("byteOffset", size_t{0}) + accessor.value("byteOffset", size_t{0});
  std::vector<float> values(accessor["count"].get<size_t>() * width);
  std::memcpy(values.data(), glb.bin.data() + offset, values.size() * sizeof(float));
  return values;
}

// The keys of one channel: times, and values of `width` floats each.
struct Keys {
  std::vector<float> times;
  std::vector<float> values;
};

Keys channelKeys(const Glb& glb, const std::string& animation, int node, const std::string& path) {
  for (const json& a : glb.doc["animations"]) {
    if (a["name"] != animation) continue;
    for (const json& channel : a["channels"]) {
      if (channel["target"]["node"] != node || channel["target"]["path"] != path) continue;
      const json& sampler = a["samplers"][channel["sampler"].get<int>()];
      return {floatAccessor(glb, sampler["input"]), floatAccessor(glb, sampler["output"])};
    }
  }
  ADD_FAILURE() << "no " << path << " channel on node " << node << " in " << animation;
  return {};
}

// Slerp written out here (shortest arc), not glm's, so the test does not trust the same code.
glm::dquat referenceSlerp(glm::dquat a, glm::dquat b, double u) {
  a = glm::normalize(a);
  b = glm::normalize(b);
  double cosine = glm::dot(a, b);
  if (cosine < 0.0) {
    b = -b;
    cosine = -cosine;
  }
  const double angle = std::acos(std::min(1.0, cosine));
  const double wa = std::sin((1.0 - u) * angle) / std::sin(angle);
  const double wb = std::sin(u * angle) / std::sin(angle);
  return glm::normalize(glm::dquat(wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y,
                                   wa * a.z + wb * b.z));
}

// ------------------------------------------------------------------------------------------------
// Small documents written by the tests: JSON plus one buffer embedded as a data: URI.

std::string base64(const std::string& bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t n = 0; n < bytes.size(); n += 3) {
    std::uint32_t chunk = static_cast<unsigned char>(bytes[n]) << 16;
    if (n + 1 < bytes.size()) chunk |= static_cast<unsigned char>(bytes[n + 1]) << 8;
    if (n + 2 < bytes.size()) chunk |= static_cast<unsigned char>(bytes[n + 2]);
    out += kDigits[(chunk >> 18) & 63];
    out += kDigits[(chunk >> 12) & 63];
    out += n + 1 < bytes.size() ? kDigits[(chunk >> 6) & 63] : '=';
    out += n + 2 < bytes.size() ? kDigits[chunk & 63] : '=';
  }
  return out;
}

std::string base64Decode(const std::string& text) {
  std::string out;
  std::uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(digits, c);
    if (c == '=' || at == nullptr) break;
    bits = (bits << 6) | static_cast<std::uint32_t>(at - digits);
    if ((count += 6) >= 8) {
      count -= 8;
      out += static_cast<char>((bits >> count) & 0xFF);
    }
  }
  return out;
}

class DocBuilder {
 public:
  json doc = {{"asset", {{"version", "2.0"}}},
              {"bufferViews", json::array()},
              {"accessors", json::array()}};

  template <class T>
  int view(const std::vector<T>& values, int stride = 0) {
    while (bin_.size() % 4 != 0) bin_ += '\0';
    json v = {
        {"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", values.size() * sizeof(T)}};
    if (stride != 0) v["byteStride"] = stride;
    bin_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    doc["bufferViews"].push_back(v);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  int accessor(const json& a) {
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  template <class T>
  int accessorOf(const std::vector<T>& values, int component_type, const char* type, size_t count,
                 bool normalized = false) {
    json a = {{"bufferView", view(values)},
              {"componentType", component_type},
              {"type", type},
              {"count", count}};
    if (normalized) a["normalized"] = true;
    return accessor(a);
  }
  int floats(const std::vector<float>& values, const char* type, size_t width) {
    return accessorOf(values, 5126, type, values.size() / width);
  }
  std::string text() const {
    json out = doc;
    if (!bin_.empty()) {
      out["buffers"] =
          json::array({{{"byteLength", bin_.size()},
                        {"uri", "data:application/octet-stream;base64," + base64(bin_)}}});
    }
    return out.dump();
  }
  std::filesystem::path write(const test::TempDir& dir, const std::string& name) const {
    const std::filesystem::path path = dir / name;
    test::writeText(path, text());
    return path;
  }
  // The same document with its buffer in a separate file beside it.
  std::filesystem::path writeWithExternalBuffer(const test::TempDir& dir, const std::string& name,
                                                const std::string& bin_name) const {
    json out = doc;
    out["buffers"] = json::array({{{"byteLength", bin_.size()}, {"uri", bin_name}}});
    test::writeText(dir / bin_name, bin_);
    test::writeText(dir / name, out.dump());
    return dir / name;
  }

 private:
  std::string bin_;
};

// Two nodes, no skin, one animation using every interpolation: hips translation CUBICSPLINE over
// keys at 0 and 2 s (value 0 -> 1, out-tangent 2, in-tangent -1), knee translation STEP at
// 0, 1, 2 s, hips rotation CUBICSPLINE with zero tangents (identity -> 90 degrees about Y),
// knee rotation LINEAR from normalized shorts at 0.5 and 1.5 s (identity -> 90 degrees about
// X), knee scale LINEAR (1 -> 2 along X).
DocBuilder curvesDocument() {
  DocBuilder b;
  b.doc["nodes"] = json::array({{{"name", "hips"}, {"children", json::array({1})}},
                                {{"name", "knee"}, {"translation", {0.0, -0.5, 0.0}}}});
  b.doc["scenes"] = json::array({{{"nodes", json::array({0})}}});
  b.doc["scene"] = 0;
  const float s = std::sqrt(0.5f);
  const int t02 = b.floats({0, 2}, "SCALAR", 1);
  const int t012 = b.floats({0, 1, 2}, "SCALAR", 1);
  const int t_half = b.floats({0.5f, 1.5f}, "SCALAR", 1);
  const int cubic_t = b.floats({0, 0, 0, 0, 0, 0, 2, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0}, "VEC3", 3);
  const int step_t = b.floats({0, 0, 0, 10, 0, 0, 20, 0, 0}, "VEC3", 3);
  const int cubic_r =
      b.floats({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, s, 0, s, 0, 0, 0, 0}, "VEC4", 4);
  const int short_r =
      b.accessorOf<std::int16_t>({0, 0, 0, 32767, 23170, 0, 0, 23170}, 5122, "VEC4", 2, true);
  const int scale = b.floats({1, 1, 1, 2, 1, 1}, "VEC3", 3);
  auto sampler = [](int input, int output, const char* mode) {
    return json{{"input", input}, {"output", output}, {"interpolation", mode}};
  };
  auto channel = [](int sampler_index, int node, const char* path) {
    return json{{"sampler", sampler_index}, {"target", {{"node", node}, {"path", path}}}};
  };
  b.doc["animations"] = json::array(
      {{{"name", "curves"},
        {"samplers", json::array({sampler(t02, cubic_t, "CUBICSPLINE"),
                                  sampler(t012, step_t, "STEP"),
                                  sampler(t02, cubic_r, "CUBICSPLINE"),
                                  {{"input", t_half}, {"output", short_r}},  // LINEAR by default
                                  sampler(t02, scale, "LINEAR")})},
        {"channels", json::array({channel(0, 0, "translation"), channel(1, 1, "translation"),
                                  channel(2, 0, "rotation"), channel(3, 1, "rotation"),
                                  channel(4, 1, "scale")})}}});
  return b;
}

// A skinned triangle whose vertex data is interleaved (byteStride 20: float position, unsigned
// byte joints, normalized unsigned byte weights), whose third position comes from a sparse
// substitution, whose skin lists the joints in the opposite order to the node tree, and whose
// indices are unsigned bytes. No animation.
DocBuilder interleavedMeshDocument() {
  DocBuilder b;
  b.doc["nodes"] = json::array(
      {{{"name", "root"}, {"children", json::array({1})}},
       {{"name", "tip"}, {"translation", {0.0, 1.0, 0.0}}},
       {{"name", "skin mesh"}, {"mesh", 0}, {"skin", 0}, {"translation", {5.0, 0.0, 0.0}}}});
  b.doc["scenes"] = json::array({{{"nodes", json::array({0, 2})}}});
  b.doc["scene"] = 0;
  std::vector<unsigned char> vertices;
  auto vertex = [&](glm::vec3 p, std::array<unsigned char, 4> joints,
                    std::array<unsigned char, 4> weights) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(&p[0]);
    vertices.insert(vertices.end(), bytes, bytes + 12);
    vertices.insert(vertices.end(), joints.begin(), joints.end());
    vertices.insert(vertices.end(), weights.begin(), weights.end());
  };
  vertex({0, 0, 0}, {1, 0, 0, 0}, {255, 0, 0, 0});
  vertex({0, 1, 0}, {0, 1, 0, 0}, {128, 127, 0, 0});
  vertex({1, 0, 0}, {0, 0, 0, 0}, {0, 255, 0, 0});
  const int interleaved = b.view(vertices, 20);
  const int sparse_indices = b.view(std::vector<unsigned char>{2});
  const int sparse_values = b.view(std::vector<float>{5, 5, 5});
  const int positions =
      b.accessor({{"bufferView", interleaved},
                  {"componentType", 5126},
                  {"type", "VEC3"},
                  {"count", 3},
                  {"sparse",
                   {{"count", 1},
                    {"indices", {{"bufferView", sparse_indices}, {"componentType", 5121}}},
                    {"values", {{"bufferView", sparse_values}}}}}});
  const int joints = b.accessor({{"bufferView", interleaved},
                                 {"byteOffset", 12},
                                 {"componentType", 5121},
                                 {"type", "VEC4"},
                                 {"count", 3}});
  const int weights = b.accessor({{"bufferView", interleaved},
                                  {"byteOffset", 16},
                                  {"componentType", 5121},
                                  {"normalized", true},
                                  {"type", "VEC4"},
                                  {"count", 3}});
  const int indices = b.accessorOf(std::vector<unsigned char>{0, 1, 2}, 5121, "SCALAR", 3);
  std::vector<float> inverse_bind(32, 0.0f);
  for (int d = 0; d < 4; ++d) inverse_bind[d * 5] = inverse_bind[16 + d * 5] = 1.0f;
  inverse_bind[13] = -1.0f;  // the tip (listed first) sits 1 m up in the bind pose
  const int ibm = b.floats(inverse_bind, "MAT4", 16);
  b.doc["skins"] = json::array({{{"joints", json::array({1, 0})}, {"inverseBindMatrices", ibm}}});
  b.doc["meshes"] = json::array(
      {{{"name", "triangle"},
        {"primitives",
         json::array({{{"attributes",
                        {{"POSITION", positions}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}},
                       {"indices", indices}}})}}});
  return b;
}

constexpr const char* kTinyBvh =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "  JOINT LeftLeg\n"
    "  {\n"
    "    OFFSET 10 -5 0\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    End Site\n"
    "    {\n"
    "      OFFSET 0 -85 0\n"
    "    }\n"
    "  }\n"
    "  JOINT Chest\n"
    "  {\n"
    "    OFFSET 0 20 0\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    JOINT Head\n"
    "    {\n"
    "      OFFSET 0 60 0\n"
    "      CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "      End Site\n"
    "      {\n"
    "        OFFSET 0 10 0\n"
    "      }\n"
    "    }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 4\n"
    "Frame Time: 0.0333333\n"
    "0 90 0 0 0 0 10 0 0 0 0 5 0 0 0\n"
    "1 91 2 10 -20 30 20 5 0 10 0 0 -30 10 5\n"
    "2 92 4 170 30 -60 30 10 -5 20 10 0 -60 20 10\n"
    "3 93 6 -170 40 -90 40 15 -10 30 20 5 -90 30 15\n";

MotionAsset tinyBvhAsset() {
  Result<MotionAsset> asset = readBvh(kTinyBvh, "tiny.bvh");
  EXPECT_TRUE(asset.ok()) << asset.message();
  return asset.ok() ? std::move(asset).value() : MotionAsset{};
}

// Largest distance between the joints' world positions of two clips, frame by frame, metres.
double worstPositionError(const MotionAsset& a, const Clip& clip_a, const MotionAsset& b,
                          const Clip& clip_b) {
  EXPECT_EQ(a.skeleton.names, b.skeleton.names);
  EXPECT_EQ(clip_a.frame_count, clip_b.frame_count);
  if (a.skeleton.names != b.skeleton.names || clip_a.frame_count != clip_b.frame_count) return 1e9;
  double worst = 0.0;
  for (int f = 0; f < clip_a.frame_count; ++f) {
    const std::vector<glm::dvec3> pa = worldPositions(a.skeleton, clip_a, f);
    const std::vector<glm::dvec3> pb = worldPositions(b.skeleton, clip_b, f);
    for (size_t j = 0; j < pa.size(); ++j) worst = std::max(worst, glm::length(pa[j] - pb[j]));
  }
  return worst;
}

// ================================================================================================
// Import: real files

TEST(GltfImportTest, FoxSkeletonAnimationsAndFrameTimes) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  const Skeleton& skeleton = fox.skeleton;
  // 24 skin joints plus their one ancestor, the "root" node.
  ASSERT_EQ(skeleton.jointCount(), 25);
  EXPECT_EQ(skeleton.names[0], "root");
  EXPECT_EQ(skeleton.parents[0], kNoParent);
  EXPECT_EQ(skeleton.names[1], "_rootJoint");
  EXPECT_GE(skeleton.findJoint("b_Head_05"), 0);
  EXPECT_TRUE(skeleton.validate().ok());
  ASSERT_EQ(skeleton.channels.size(), 25u);
  EXPECT_EQ(skeleton.channelCount(), 0);
  ASSERT_TRUE(fox.gltf);
  EXPECT_TRUE(fox.gltf->binary);
  EXPECT_EQ(fox.gltf->node_of_joint.size(), 25u);
  EXPECT_EQ(fox.gltf->node_of_joint[0], 0);  // "root" is node 0
  EXPECT_EQ(fox.detection.frame.unit, LengthUnit::kCentimetres);  // GltfUnitsTest says why
  EXPECT_EQ(fox.detection.frame.up, UpAxis::kY);

  ASSERT_EQ(fox.clips.size(), 3u);
  EXPECT_EQ(fox.clips[0].name, "Survey");
  EXPECT_EQ(fox.clips[1].name, "Walk");
  EXPECT_EQ(fox.clips[2].name, "Run");
  // Median key spacing 1/24 s in all three; frames = floor(duration / frame time) + 1.
  for (const Clip& clip : fox.clips) {
    SCOPED_TRACE(clip.name);
    EXPECT_NEAR(clip.frame_time, 1.0 / 24.0, 1e-12);
    EXPECT_TRUE(clip.scales.empty());  // Fox has no scale anywhere
    EXPECT_TRUE(clip.validate(skeleton).ok());
  }
  EXPECT_EQ(fox.clips[0].frame_count, 83);  // 0 .. 3.4167 s
  EXPECT_EQ(fox.clips[1].frame_count, 18);  // 0 .. 0.7083 s
  EXPECT_EQ(fox.clips[2].frame_count, 28);  // 0 .. 1.1583 s, keys uneven: floor(27.8) + 1
}

TEST(GltfImportTest, FoxRotationAtEachKeyTimeIsTheKey) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  const Glb glb = splitGlb(test::readText(gltfData("Fox.glb")));
  const Clip& walk = clipNamed(fox, "Walk");
  int checked = 0;
  for (int j = 0; j < fox.skeleton.jointCount(); ++j) {
    const int node = fox.gltf->node_of_joint[j];
    bool animated = false;
    for (const json& channel : glb.doc["animations"][1]["channels"]) {
      animated = animated ||
                 (channel["target"]["node"] == node && channel["target"]["path"] == "rotation");
    }
    if (!animated) continue;
    const Keys keys = channelKeys(glb, "Walk", node, "rotation");
    ASSERT_EQ(keys.times.size(), 18u);
    for (size_t k = 0; k < keys.times.size(); ++k) {
      // Walk's keys fall on the 24 fps frames: frame k is key k.
      ASSERT_NEAR(keys.times[k], k / 24.0, 1e-6);
      const float* v = &keys.values[4 * k];
      const glm::dquat expected = glm::normalize(glm::dquat(v[3], v[0], v[1], v[2]));
      const glm::dquat& got = walk.rotation(static_cast<int>(k), j);
      const double same_sign = glm::dot(expected, got) < 0 ? -1.0 : 1.0;
      EXPECT_NEAR(got.x, same_sign * expected.x, 1e-12);
      EXPECT_NEAR(got.y, same_sign * expected.y, 1e-12);
      EXPECT_NEAR(got.z, same_sign * expected.z, 1e-12);
      EXPECT_NEAR(got.w, same_sign * expected.w, 1e-12);
    }
    ++checked;
  }
  EXPECT_GE(checked, 20);  // Fox animates the rotation of (almost) every joint
}

TEST(GltfImportTest, FoxRunGapIsInterpolatedBySlerp) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  const Glb glb = splitGlb(test::readText(gltfData("Fox.glb")));
  const Clip& run = clipNamed(fox, "Run");
  const int hip = fox.skeleton.findJoint("b_Hip_01");
  ASSERT_GE(hip, 0);
  const Keys keys = channelKeys(glb, "Run", fox.gltf->node_of_joint[hip], "rotation");
  ASSERT_EQ(keys.times.size(), 25u);
  // The one uneven spacing: 0.2 s between two keys.
  size_t gap = 0;
  for (size_t k = 0; k + 1 < keys.times.size(); ++k) {
    if (keys.times[k + 1] - keys.times[k] > 0.1) gap = k;
  }
  ASSERT_NEAR(keys.times[gap + 1] - keys.times[gap], 0.2, 1e-5);
  const glm::dquat a(keys.values[4 * gap + 3], keys.values[4 * gap], keys.values[4 * gap + 1],
                     keys.values[4 * gap + 2]);
  const glm::dquat b(keys.values[4 * gap + 7], keys.values[4 * gap + 4], keys.values[4 * gap + 5],
                     keys.values[4 * gap + 6]);
  ASSERT_GT(angleBetween(a, b), 0.01);  // the gap spans a real change of pose
  int inside = 0;
  for (int f = 0; f < run.frame_count; ++f) {
    const double t = f * run.frame_time;
    if (t <= keys.times[gap] + 1e-4 || t >= keys.times[gap + 1] - 1e-4) continue;
    const double u = (t - keys.times[gap]) / (keys.times[gap + 1] - keys.times[gap]);
    EXPECT_LT(angleBetween(run.rotation(f, hip), referenceSlerp(a, b, u)), 1e-9)
        << "frame " << f << " at " << t << " s, u = " << u;
    ++inside;
  }
  EXPECT_GE(inside, 4);  // 0.2 s at 24 fps
}

TEST(GltfImportTest, FoxMeshWeightsAndBindPose) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  ASSERT_EQ(fox.meshes.size(), 1u);
  const SkinnedMesh& mesh = fox.meshes[0];
  EXPECT_EQ(mesh.positions.size(), 1728u);
  EXPECT_EQ(mesh.indices.size(), 1728u);  // no index accessor: one vertex per corner
  EXPECT_TRUE(mesh.normals.empty());      // Fox has none
  ASSERT_EQ(mesh.weights.size(), mesh.positions.size());
  ASSERT_EQ(mesh.inverse_bind.size(), 25u);
  for (size_t v = 0; v < mesh.weights.size(); ++v) {
    const glm::vec4& w = mesh.weights[v];
    ASSERT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f) << "vertex " << v;
    for (int k = 0; k < 4; ++k) {
      ASSERT_LT(mesh.joints[v][k], 25);
      if (w[k] > 0.0f) {
        ASSERT_NE(mesh.joints[v][k], 0) << "the root node is not a skin joint";
      }
    }
  }
  // Fox was exported in its bind pose: each skin joint's rest world transform undoes its
  // inverse bind matrix. The root node is not in the skin, so its inverse bind is identity.
  const std::vector<glm::dmat4> rest = restWorldTransforms(fox.skeleton);
  EXPECT_EQ(mesh.inverse_bind[0], glm::dmat4(1.0));
  double worst = 0.0;
  for (int j = 1; j < fox.skeleton.jointCount(); ++j) {
    const glm::dmat4 product = rest[j] * mesh.inverse_bind[j];
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) worst = std::max(worst, std::abs(product[c][r] - (c == r)));
    }
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_EQ(mesh.mesh_to_world, glm::dmat4(1.0));
}

TEST(GltfImportTest, RiggedFigureMatrixNodeAndUnnamedAnimation) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset figure = load(gltfData("RiggedFigure.glb"));
  // 19 skin joints plus the "Z_UP" (a matrix) and "Armature" nodes above them.
  ASSERT_EQ(figure.skeleton.jointCount(), 21);
  EXPECT_EQ(figure.skeleton.names[0], "Z_UP");
  EXPECT_EQ(figure.skeleton.names[1], "Armature");
  EXPECT_EQ(figure.skeleton.names[2], "torso_joint_1");
  // Z_UP's matrix is -90 degrees about X.
  const glm::dquat z_up = glm::angleAxis(-std::numbers::pi / 2, glm::dvec3(1, 0, 0));
  EXPECT_LT(angleBetween(figure.skeleton.rest_rotations[0], z_up), 1e-9);
  EXPECT_NEAR(figure.skeleton.rest_scales[0].x, 1.0, 1e-12);

  ASSERT_EQ(figure.clips.size(), 1u);
  const Clip& clip = figure.clips[0];
  EXPECT_EQ(clip.name, "animation_0");
  EXPECT_NEAR(clip.frame_time, 1.25, 1e-7);  // two keys: at 0 and 1.25 s
  EXPECT_EQ(clip.frame_count, 2);

  ASSERT_EQ(figure.meshes.size(), 1u);
  const SkinnedMesh& mesh = figure.meshes[0];
  EXPECT_EQ(mesh.positions.size(), 370u);
  EXPECT_EQ(mesh.indices.size(), 768u);
  ASSERT_EQ(mesh.normals.size(), 370u);
  for (const glm::vec3& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (const glm::vec4& w : mesh.weights) ASSERT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f);
  // The mesh node hangs under Z_UP, so its world transform is Z_UP's rotation.
  EXPECT_LT(std::abs(mesh.mesh_to_world[1][2] - (-1.0)), 1e-9);
  EXPECT_LT(std::abs(mesh.mesh_to_world[2][1] - 1.0), 1e-9);
}

// ================================================================================================
// Import: synthetic documents

TEST(GltfImportTest, CubicSplineStepLinearAndClamping) {
  test::TempDir dir;
  const std::filesystem::path path = curvesDocument().write(dir, "curves.gltf");
  ImportOptions options;
  options.fps = 4.0;
  const MotionAsset asset = load(path, options);
  ASSERT_EQ(asset.skeleton.jointCount(), 2);  // no skin: the scene's node tree
  EXPECT_EQ(asset.skeleton.names[1], "knee");
  EXPECT_EQ(asset.skeleton.offsets[1], glm::dvec3(0, -0.5, 0));
  EXPECT_FALSE(asset.gltf->binary);
  ASSERT_EQ(asset.clips.size(), 1u);
  const Clip& clip = asset.clips[0];
  EXPECT_EQ(clip.name, "curves");
  EXPECT_DOUBLE_EQ(clip.frame_time, 0.25);
  ASSERT_EQ(clip.frame_count, 9);  // 0 .. 2 s

  // Hermite with tangents scaled by the 2 s key spacing, worked by hand:
  // u = 0.25: 0.84375 * 0 + 2 * 0.140625 * 2 + 0.15625 * 1 + 2 * (-0.046875) * (-1) = 0.8125
  // u = 0.5:  0.5 * 0 + 2 * 0.125 * 2 + 0.5 * 1 + 2 * (-0.125) * (-1) = 1.25
  EXPECT_NEAR(clip.translation(0, 0).x, 0.0, 1e-12);
  EXPECT_NEAR(clip.translation(2, 0).x, 0.8125, 1e-6);
  EXPECT_NEAR(clip.translation(4, 0).x, 1.25, 1e-6);
  EXPECT_NEAR(clip.translation(8, 0).x, 1.0, 1e-12);
  // Cubic rotation with zero tangents, half way: normalised sum = 45 degrees about Y.
  EXPECT_LT(
      angleBetween(clip.rotation(4, 0), glm::angleAxis(std::numbers::pi / 4, glm::dvec3(0, 1, 0))),
      1e-6);
  EXPECT_NEAR(glm::length(clip.rotation(3, 0)), 1.0, 1e-12);

  // STEP holds each key until the next.
  EXPECT_EQ(clip.translation(3, 1).x, 0.0);
  EXPECT_EQ(clip.translation(4, 1).x, 10.0);
  EXPECT_EQ(clip.translation(7, 1).x, 10.0);
  EXPECT_EQ(clip.translation(8, 1).x, 20.0);

  // LINEAR rotation from normalized shorts, keys at 0.5 and 1.5 s: clamped before, slerp within.
  EXPECT_LT(angleBetween(clip.rotation(0, 1), glm::dquat(1, 0, 0, 0)), 1e-9);
  EXPECT_LT(angleBetween(clip.rotation(1, 1), glm::dquat(1, 0, 0, 0)), 1e-9);
  EXPECT_LT(
      angleBetween(clip.rotation(4, 1), glm::angleAxis(std::numbers::pi / 4, glm::dvec3(1, 0, 0))),
      1e-6);
  EXPECT_LT(
      angleBetween(clip.rotation(3, 1), glm::angleAxis(std::numbers::pi / 8, glm::dvec3(1, 0, 0))),
      1e-6);
  EXPECT_LT(
      angleBetween(clip.rotation(8, 1), glm::angleAxis(std::numbers::pi / 2, glm::dvec3(1, 0, 0))),
      1e-9);

  // A scale that is not 1 fills clip.scales; joints without a scale channel keep their rest 1.
  ASSERT_FALSE(clip.scales.empty());
  EXPECT_NEAR(clip.scale(4, 1).x, 1.5, 1e-12);
  EXPECT_EQ(clip.scale(4, 0), glm::dvec3(1.0));

  // Without a requested rate: the median spacing of the merged keys {0, 0.5, 1, 1.5, 2}.
  const MotionAsset native = load(path);
  EXPECT_DOUBLE_EQ(native.clips[0].frame_time, 0.5);
  EXPECT_EQ(native.clips[0].frame_count, 5);
}

TEST(GltfImportTest, InterleavedSparseNormalizedSkinnedMesh) {
  test::TempDir dir;
  const MotionAsset asset = load(interleavedMeshDocument().write(dir, "triangle.gltf"));
  // The skin's joints and their ancestors; the mesh node is neither.
  ASSERT_EQ(asset.skeleton.jointCount(), 2);
  EXPECT_EQ(asset.skeleton.names[0], "root");
  EXPECT_EQ(asset.skeleton.names[1], "tip");
  EXPECT_TRUE(asset.clips.empty());  // no animation in the file
  ASSERT_EQ(asset.meshes.size(), 1u);
  const SkinnedMesh& mesh = asset.meshes[0];
  EXPECT_EQ(mesh.name, "triangle");
  ASSERT_EQ(mesh.positions.size(), 3u);
  EXPECT_EQ(mesh.positions[0], glm::vec3(0, 0, 0));
  EXPECT_EQ(mesh.positions[1], glm::vec3(0, 1, 0));
  EXPECT_EQ(mesh.positions[2], glm::vec3(5, 5, 5));  // sparse substitution
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  // Skin joint 0 is "tip" (skeleton joint 1), skin joint 1 is "root" (skeleton joint 0).
  EXPECT_EQ(mesh.joints[0][0], 0);
  EXPECT_FLOAT_EQ(mesh.weights[0][0], 1.0f);
  EXPECT_EQ(mesh.joints[1][0], 1);
  EXPECT_EQ(mesh.joints[1][1], 0);
  EXPECT_NEAR(mesh.weights[1][0], 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(mesh.weights[1][1], 127.0f / 255.0f, 1e-6f);
  EXPECT_EQ(mesh.joints[2][0], 1);  // the heaviest influence comes first
  EXPECT_FLOAT_EQ(mesh.weights[2][0], 1.0f);
  ASSERT_EQ(mesh.inverse_bind.size(), 2u);
  EXPECT_EQ(mesh.inverse_bind[0], glm::dmat4(1.0));
  EXPECT_EQ(mesh.inverse_bind[1], glm::translate(glm::dmat4(1.0), glm::dvec3(0, -1, 0)));
  EXPECT_EQ(mesh.mesh_to_world, glm::translate(glm::dmat4(1.0), glm::dvec3(5, 0, 0)));
}

TEST(GltfImportTest, NamesAreMadeUniqueAndNonEmpty) {
  DocBuilder b;
  b.doc["nodes"] = json::array({{{"name", "arm"}, {"children", json::array({1, 2, 3})}},
                                {{"name", "arm"}},
                                json::object(),
                                {{"name", "left hand"}}});
  b.doc["scenes"] = json::array({{{"nodes", json::array({0})}}});
  test::TempDir dir;
  const MotionAsset asset = load(b.write(dir, "names.gltf"));
  EXPECT_EQ(asset.skeleton.names,
            (std::vector<std::string>{"arm", "arm_2", "node_2", "left_hand"}));
}

// ================================================================================================
// Import: refusing bad input

void expectRefused(const std::filesystem::path& path, const std::string& phrase,
                   const ImportOptions& options = {}) {
  SCOPED_TRACE(path.filename().string());
  Result<MotionAsset> asset = loadGltf(path, options);
  ASSERT_FALSE(asset.ok());
  EXPECT_NE(asset.message().find(path.string()), std::string::npos) << asset.message();
  EXPECT_NE(asset.message().find(phrase), std::string::npos) << asset.message();
}

// A document whose one animation uses `input` and `output` accessors, targeting node 0.
DocBuilder animationWith(DocBuilder b, int input, int output, const char* interpolation = "LINEAR",
                         int sampler = 0) {
  b.doc["nodes"] = json::array({{{"name", "only"}}});
  b.doc["animations"] = json::array(
      {{{"name", "broken"},
        {"samplers",
         json::array({{{"input", input}, {"output", output}, {"interpolation", interpolation}}})},
        {"channels", json::array({{{"sampler", sampler},
                                   {"target", {{"node", 0}, {"path", "translation"}}}}})}}});
  return b;
}

TEST(GltfCorruptTest, RefusesBadFilesNamingTheFileAndTheField) {
  test::TempDir dir;
  test::writeText(dir / "empty.glb", "");
  expectRefused(dir / "empty.glb", "empty file");
  test::writeText(dir / "garbage.gltf", "{ \"asset\": { \"version\": 2.0 ,,, this is not json");
  expectRefused(dir / "garbage.gltf", "not a valid glTF JSON file");
  test::writeText(dir / "text.glb", "glTF but not really a binary glTF file at all");
  expectRefused(dir / "text.glb", "not a valid glTF binary");
  expectRefused(dir / "missing.glb", "missing.glb");

  {  // an accessor that claims more values than its buffer holds
    DocBuilder b;
    const int view = b.view(std::vector<float>{0, 1});
    const int times = b.accessor(
        {{"bufferView", view}, {"componentType", 5126}, {"type", "SCALAR"}, {"count", 1000}});
    const int values = b.floats({0, 0, 0, 1, 1, 1}, "VEC3", 3);
    const auto path = animationWith(b, times, values).write(dir, "overrun.gltf");
    expectRefused(path, "accessor");
    expectRefused(path, "count 1000");
  }
  {  // keys and values disagree
    DocBuilder b;
    const int times = b.floats({0, 1, 2}, "SCALAR", 1);
    const int values = b.floats({0, 0, 0, 1, 1, 1}, "VEC3", 3);
    expectRefused(
        animationWith(b, times, values).write(dir, "counts.gltf"),
        "animation 'broken', channel 0: sampler 0 output accessor 1 has 2 values for 3 keys");
    expectRefused(animationWith(b, times, values, "CUBICSPLINE").write(dir, "cubic.gltf"),
                  "CUBICSPLINE needs 9");
    expectRefused(animationWith(b, times, values, "SMOOTH").write(dir, "mode.gltf"),
                  "unknown interpolation 'SMOOTH'");
    expectRefused(animationWith(b, times, values, "LINEAR", 7).write(dir, "sampler.gltf"),
                  "channel 0: sampler 7 does not exist");
  }
  {  // time running backwards, and no keys at all
    DocBuilder b;
    const int backwards = b.floats({0, 2, 1}, "SCALAR", 1);
    const int values = b.floats({0, 0, 0, 1, 1, 1, 2, 2, 2}, "VEC3", 3);
    expectRefused(animationWith(b, backwards, values).write(dir, "backwards.gltf"),
                  "key times go backwards at key 2");
    const int none = b.accessor({{"componentType", 5126}, {"type", "SCALAR"}, {"count", 0}});
    expectRefused(animationWith(b, none, values).write(dir, "nokeys.gltf"),
                  "sampler 0 input accessor 2 has 0 keys");
  }
  {  // a clip whose last key is a million seconds on: refused before it asks for gigabytes
    DocBuilder b;
    const int times = b.floats({0.0f, 1.0f / 30, 2.0f / 30, 1e6f}, "SCALAR", 1);
    const int values = b.floats({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3}, "VEC3", 3);
    expectRefused(animationWith(b, times, values).write(dir, "long.gltf"),
                  "fps is too many frames (30000001 of 1 joints");
  }
  {  // a node hierarchy that loops
    DocBuilder b;
    b.doc["nodes"] = json::array({{{"name", "a"}, {"children", json::array({1})}},
                                  {{"name", "b"}, {"children", json::array({0})}}});
    expectRefused(b.write(dir, "cycle.gltf"), "cycle");
    b.doc["nodes"] =
        json::array({{{"children", json::array({1})}}, {{"children", json::array({7})}}});
    expectRefused(b.write(dir, "child.gltf"), "node 1: child 7 does not exist");
  }
  {  // a skin naming a node that is not there
    DocBuilder b;
    b.doc["nodes"] = json::array({json::object()});
    b.doc["skins"] = json::array({{{"joints", json::array({0, 4})}}});
    expectRefused(b.write(dir, "skin.gltf"), "skin 0: joint node 4 does not exist");
  }
  {  // a skin with no joints (was "has no nodes")
    DocBuilder b;
    b.doc["nodes"] = json::array({json::object()});
    b.doc["skins"] = json::array({{{"joints", json::array()}}});
    expectRefused(b.write(dir, "empty_skin.gltf"),
                  "skin 0 has no joints, so there is no skeleton to import");
  }
  ImportOptions options;
  options.fps = 0.0;
  expectRefused(curvesDocument().write(dir, "fps.gltf"), "fps", options);
}

TEST(GltfCorruptTest, TruncatedAndDamagedFilesNeverCrash) {
  // An exported .glb (mesh, skin, animation), cut short and with bytes overwritten: every read
  // either succeeds with a valid skeleton or returns an error naming the file.
  test::TempDir dir;
  const MotionAsset rig = tinyBvhAsset();
  ASSERT_TRUE(saveGltf(dir / "tiny.glb", rig, rig.clips[0]).ok());
  const std::string bytes = test::readText(dir / "tiny.glb");
  std::vector<std::string> variants;
  for (size_t length : {size_t{0}, size_t{4}, size_t{12}, size_t{19}, size_t{20}, size_t{100},
                        bytes.size() / 3, bytes.size() / 2, bytes.size() - 1}) {
    variants.push_back(bytes.substr(0, length));
  }
  std::uint32_t state = 12345;
  for (int n = 0; n < 200; ++n) {
    std::string damaged = bytes;
    for (int k = 0; k < 4; ++k) {
      state = state * 1664525u + 1013904223u;
      damaged[(state >> 8) % damaged.size()] = static_cast<char>(state >> 24);
    }
    variants.push_back(damaged);
  }
  if (test::haveSharedData()) {
    const std::string fox = test::readText(gltfData("Fox.glb"));
    variants.push_back(fox.substr(0, 2000));
    variants.push_back(fox.substr(0, fox.size() / 2));
  }
  int refused = 0;
  for (size_t n = 0; n < variants.size(); ++n) {
    const std::filesystem::path path = dir / ("damaged" + std::to_string(n) + ".glb");
    test::writeText(path, variants[n]);
    Result<MotionAsset> asset = loadGltf(path);
    if (asset.ok()) {
      EXPECT_TRUE(asset.value().skeleton.validate().ok());
      for (const Clip& clip : asset.value().clips) {
        EXPECT_TRUE(clip.validate(asset.value().skeleton).ok());
      }
    } else {
      ++refused;
      EXPECT_NE(asset.message().find(path.string()), std::string::npos) << asset.message();
    }
  }
  EXPECT_GE(refused, 9);  // at least every truncation
}

// ================================================================================================
// Units: glTF states metres, exporters do not always keep to it

// A 170 cm human in centimetre numbers under an "Armature" node scaled 0.01 (what Blender writes
// for an armature scaled to metres): hips 90 cm up, feet on the ground, head and hands above.
// The skinned triangle's node hangs under the armature too, so its vertices are centimetres and
// the inverse bind matrices the bind pose's (inverse joint world times mesh world). One
// animation moves the hips 100 cm forward in 1 s.
DocBuilder armatureDocument() {
  DocBuilder b;
  auto node = [](const char* name, glm::dvec3 t, std::vector<int> children) {
    json n = {{"name", name}, {"translation", {t.x, t.y, t.z}}};
    if (!children.empty()) n["children"] = children;
    return n;
  };
  json armature = {{"name", "Armature"},
                   {"scale", {0.01, 0.01, 0.01}},
                   {"children", json::array({1, 10})}};
  b.doc["nodes"] = json::array(
      {armature, node("Hips", {0, 90, 0}, {2, 4, 6}), node("LeftUpLeg", {10, -5, 0}, {3}),
       node("LeftFoot", {0, -85, 0}, {}), node("RightUpLeg", {-10, -5, 0}, {5}),
       node("RightFoot", {0, -85, 0}, {}), node("Spine", {0, 30, 0}, {7, 8, 9}),
       node("Head", {0, 50, 0}, {}), node("LeftHand", {40, 20, 0}, {}),
       node("RightHand", {-40, 20, 0}, {}), json{{"name", "Body"}, {"mesh", 0}, {"skin", 0}}});
  b.doc["scenes"] = json::array({{{"nodes", json::array({0})}}});
  b.doc["scene"] = 0;
  // Rest world transforms of the nine joints (nodes 1..9), all under the armature's 0.01.
  const glm::dmat4 armature_world = glm::scale(glm::dmat4(1.0), glm::dvec3(0.01));
  std::vector<glm::dmat4> world(10, armature_world);
  std::vector<float> inverse_bind;
  for (int n = 1; n <= 9; ++n) {
    const json& t = b.doc["nodes"][n]["translation"];
    int parent = 0;
    for (int p = 0; p <= 9; ++p) {
      for (const json& c : b.doc["nodes"][p].value("children", json::array()))
        if (c == n) parent = p;
    }
    world[n] = world[parent] * glm::translate(glm::dmat4(1.0), glm::dvec3(t[0], t[1], t[2]));
    const glm::dmat4 m = glm::inverse(world[n]) * armature_world;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) inverse_bind.push_back(static_cast<float>(m[c][r]));
  }
  const int ibm = b.floats(inverse_bind, "MAT4", 16);
  b.doc["skins"] = json::array(
      {{{"joints", json::array({1, 2, 3, 4, 5, 6, 7, 8, 9})}, {"inverseBindMatrices", ibm}}});
  const int positions = b.floats({0, 90, 0, 10, 90, 0, 0, 100, 0}, "VEC3", 3);
  const int joints = b.accessorOf(std::vector<unsigned char>(12, 0), 5121, "VEC4", 3);
  const int weights = b.floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
  b.doc["meshes"] = json::array(
      {{{"name", "body"},
        {"primitives", json::array({{{"attributes", {{"POSITION", positions},
                                                     {"JOINTS_0", joints},
                                                     {"WEIGHTS_0", weights}}}}})}}});
  const int times = b.floats({0, 1}, "SCALAR", 1);
  const int hips = b.floats({0, 90, 0, 0, 90, 100}, "VEC3", 3);
  b.doc["animations"] = json::array(
      {{{"name", "forward"},
        {"samplers", json::array({{{"input", times}, {"output", hips}}})},
        {"channels", json::array({{{"sampler", 0},
                                   {"target", {{"node", 1}, {"path", "translation"}}}}})}}});
  return b;
}

TEST(GltfUnitsTest, ArmatureScaleIsFoldedIntoMetres) {
  test::TempDir dir;
  const MotionAsset asset = load(armatureDocument().write(dir, "armature.gltf"));
  const Skeleton& skeleton = asset.skeleton;
  ASSERT_EQ(skeleton.jointCount(), 10);  // the armature and nine joints
  EXPECT_EQ(asset.detection.frame.unit, LengthUnit::kMetres) << asset.detection.reason;
  EXPECT_NE(asset.detection.reason.find("node scale 0.01 on 'Armature' applied"),
            std::string::npos)
      << asset.detection.reason;
  EXPECT_NEAR(asset.detection.height_m, 1.7, 1e-6);
  // The scale moved into the numbers below it: the armature is unscaled, the bones are metres.
  EXPECT_EQ(skeleton.rest_scales[0], glm::dvec3(1.0));
  const int hips = skeleton.findJoint("Hips"), foot = skeleton.findJoint("LeftFoot");
  EXPECT_NEAR(glm::length(skeleton.offsets[hips] - glm::dvec3(0, 0.9, 0)), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(skeleton.offsets[foot] - glm::dvec3(0, -0.85, 0)), 0.0, 1e-9);
  ASSERT_EQ(asset.clips.size(), 1u);
  const Clip& clip = asset.clips[0];
  EXPECT_TRUE(clip.scales.empty());  // the only scale was the armature's, now folded
  const glm::dvec3 last = clip.translation(clip.frame_count - 1, hips);
  EXPECT_NEAR(glm::length(last - glm::dvec3(0, 0.9, 1.0)), 0.0, 1e-6);
  // The skinned triangle lands where the file puts it, in metres: hips corner at 0.9 m.
  ASSERT_EQ(asset.meshes.size(), 1u);
  const SkinnedMesh& mesh = asset.meshes[0];
  const std::vector<glm::dmat4> rest = restWorldTransforms(skeleton);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec4 p(glm::dvec3(mesh.positions[v]), 1.0);
    const glm::dvec3 skinned(rest[hips] * mesh.inverse_bind[hips] * p);
    const glm::dvec3 placed(mesh.mesh_to_world * p);
    EXPECT_NEAR(glm::length(skinned - placed), 0.0, 1e-6) << "vertex " << v;
    if (v == 0) {
      EXPECT_NEAR(glm::length(skinned - glm::dvec3(0, 0.9, 0)), 0.0, 1e-6);
    }
  }
}

TEST(GltfUnitsTest, ArmatureExportWritesTheFileNumbersBackAndReadsTheSameSize) {
  test::TempDir dir;
  const MotionAsset asset = load(armatureDocument().write(dir, "armature.gltf"));
  const std::filesystem::path path = dir / "back.glb";
  ASSERT_TRUE(saveGltf(path, asset, asset.clips[0]).ok());
  const MotionAsset back = load(path);
  EXPECT_EQ(back.detection.frame.unit, LengthUnit::kMetres) << back.detection.reason;
  EXPECT_NEAR(back.detection.height_m, asset.detection.height_m, 1e-6);
  EXPECT_LT(worstPositionError(asset, asset.clips[0], back, back.clips[0]), 1e-6);
  // The document still holds centimetres under the 0.01 armature, keys included.
  const Glb glb = splitGlb(test::readText(path));
  EXPECT_NEAR(glb.doc["nodes"][0]["scale"][0].get<double>(), 0.01, 1e-9);
  const Keys keys = channelKeys(glb, "forward", 1, "translation");
  ASSERT_FALSE(keys.values.empty());
  EXPECT_NEAR(keys.values[keys.values.size() - 1], 100.0f, 1e-3f);
  EXPECT_NEAR(keys.values[1], 90.0f, 1e-3f);
}

TEST(GltfUnitsTest, UnscaledCentimetreFigureFallsBackToAnatomy) {
  DocBuilder b = armatureDocument();
  b.doc["nodes"][0].erase("scale");  // the same 170 "metre" human, no scale to honour
  test::TempDir dir;
  const MotionAsset asset = load(b.write(dir, "cm.gltf"));
  EXPECT_EQ(asset.detection.frame.unit, LengthUnit::kCentimetres) << asset.detection.reason;
  EXPECT_EQ(asset.detection.reason.rfind("implausible in the file's m; human", 0), 0u)
      << asset.detection.reason;
  // glTF is Y-up by specification and --up is for BVH: the reason offers only --units.
  const std::string& reason = asset.detection.reason;
  EXPECT_EQ(reason.substr(reason.size() - 24), " (override with --units)") << reason;
  EXPECT_EQ(reason.find("--up"), std::string::npos) << reason;
  EXPECT_NE(reason.find(" along Y"), std::string::npos) << reason;
  EXPECT_NEAR(asset.detection.height_m, 1.7, 1e-6);
  EXPECT_NEAR(asset.skeleton.offsets[asset.skeleton.findJoint("Hips")].y, 0.9, 1e-9);
  EXPECT_NEAR(asset.meshes[0].positions[2].y, 1.0f, 1e-6f);  // 100 cm
  // --units overrides: the numbers taken as millimetres make a 17 cm figure.
  ImportOptions options;
  options.unit = LengthUnit::kMillimetres;
  const MotionAsset forced = load(b.write(dir, "cm.gltf"), options);
  EXPECT_EQ(forced.detection.frame.unit, LengthUnit::kMillimetres);
  EXPECT_NEAR(forced.detection.height_m, 0.17, 1e-6);
  EXPECT_EQ(forced.detection.reason.rfind("unit set by the user", 0), 0u);
}

TEST(GltfUnitsTest, FoxIsCentimetresAndFoxSized) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  std::cout << "[ figures  ] Fox: " << unitName(fox.detection.frame.unit) << ", "
            << fox.detection.height_m << " m (" << fox.detection.reason << ")\n";
  EXPECT_EQ(fox.detection.frame.unit, LengthUnit::kCentimetres) << fox.detection.reason;
  EXPECT_EQ(fox.skeleton.source.unit, LengthUnit::kCentimetres);
  // A red fox stands 35-50 cm at the shoulder and is about 1-1.5 m from nose to tail tip.
  const FigureMeasure figure = measureFigure(fox.skeleton, fox.clips[0], 1);
  std::cout << "[ figures  ] Fox: hips " << figure.hip_height << " m up, " << figure.height
            << " m tall, " << familyName(figure.family) << "\n";
  EXPECT_GT(figure.hip_height, 0.3);
  EXPECT_LT(figure.hip_height, 0.6);
  ASSERT_EQ(fox.meshes.size(), 1u);
  glm::dvec3 lo(1e30), hi(-1e30);
  for (const glm::vec3& p : fox.meshes[0].positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  std::cout << "[ figures  ] Fox mesh: " << hi.z - lo.z << " m nose to tail, " << hi.y - lo.y
            << " m tall\n";
  EXPECT_NEAR(hi.z - lo.z, 1.547, 0.005);  // 154.7 cm in the file
  EXPECT_NEAR(hi.y - lo.y, 0.790, 0.005);
}

TEST(GltfUnitsTest, FoxExportReadsBackAtTheSameSize) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  test::TempDir dir;
  // Survey, the first clip: the size is measured on the first clip's first frame.
  ASSERT_TRUE(saveGltf(dir / "fox.glb", fox, clipNamed(fox, "Survey")).ok());
  const MotionAsset back = load(dir / "fox.glb");
  EXPECT_EQ(back.detection.frame.unit, LengthUnit::kCentimetres) << back.detection.reason;
  EXPECT_NEAR(back.detection.height_m, fox.detection.height_m, 1e-6);
  EXPECT_LT(worstPositionError(fox, clipNamed(fox, "Survey"), back, back.clips[0]), 1e-5);
  // The file keeps its centimetres: the hips' keys are tens of units, not tenths.
  const Glb glb = splitGlb(test::readText(dir / "fox.glb"));
  const int hips = back.gltf->node_of_joint[back.skeleton.findJoint("b_Hip_01")];
  const Keys keys = channelKeys(glb, "Survey", hips, "translation");
  ASSERT_GE(keys.values.size(), 3u);
  EXPECT_GT(std::abs(keys.values[1]) + std::abs(keys.values[2]), 10.0f);
}

TEST(GltfUnitsTest, RiggedFigureIsMetresAndPersonSized) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset figure = load(gltfData("RiggedFigure.glb"));
  std::cout << "[ figures  ] RiggedFigure: " << unitName(figure.detection.frame.unit) << ", "
            << figure.detection.height_m << " m (" << figure.detection.reason << ")\n";
  EXPECT_EQ(figure.detection.frame.unit, LengthUnit::kMetres) << figure.detection.reason;
  // Its joints span the ankles to the neck of a 1.45 m mesh (the head top is no joint).
  EXPECT_GT(figure.detection.height_m, 1.0);
  EXPECT_LT(figure.detection.height_m, 1.5);
}

// ================================================================================================
// Export

TEST(GltfExportTest, FoxWalkRoundTripsThroughGlbAndGltf) {
  SINEW_REQUIRE_SHARED_DATA();
  const MotionAsset fox = load(gltfData("Fox.glb"));
  const Clip& walk = clipNamed(fox, "Walk");
  test::TempDir dir;
  for (const char* name : {"walk.glb", "walk.gltf"}) {
    SCOPED_TRACE(name);
    const std::filesystem::path path = dir / name;
    ASSERT_TRUE(saveGltf(path, fox, walk).ok());
    const MotionAsset back = load(path);
    ASSERT_EQ(back.skeleton.jointCount(), 25);
    ASSERT_EQ(back.clips.size(), 1u);
    EXPECT_EQ(back.clips[0].name, "Walk");
    EXPECT_NEAR(back.clips[0].frame_time, walk.frame_time, 1e-12);
    const double error = worstPositionError(fox, walk, back, back.clips[0]);
    std::cout << "[ figures  ] " << name << ": worst joint position error " << error << " m\n";
    EXPECT_LT(error, 1e-5);
    ASSERT_EQ(back.meshes.size(), 1u);
    EXPECT_EQ(back.meshes[0].positions, fox.meshes[0].positions);
    EXPECT_EQ(back.meshes[0].weights, fox.meshes[0].weights);

    // The document keeps the original's mesh, skin, material and texture.
    const std::string bytes = test::readText(path);
    const json doc = std::string(name).ends_with(".glb") ? splitGlb(bytes).doc : json::parse(bytes);
    EXPECT_EQ(doc["animations"].size(), 1u);
    EXPECT_EQ(doc["animations"][0]["channels"].size(), 50u);  // 25 joints x (T, R)
    EXPECT_EQ(doc["skins"][0]["joints"].size(), 24u);
    EXPECT_EQ(doc["images"].size(), 1u);
    EXPECT_TRUE(doc["images"][0].contains("bufferView"));
    EXPECT_EQ(doc["textures"].size(), 1u);
    EXPECT_EQ(doc["materials"].size(), 1u);
    ASSERT_EQ(doc["buffers"].size(), 1u);
    if (std::string(name).ends_with(".gltf")) {
      EXPECT_EQ(doc["buffers"][0]["uri"].get<std::string>().rfind("data:", 0), 0u);
    } else {
      EXPECT_FALSE(doc["buffers"][0].contains("uri"));
    }
  }
}

TEST(GltfExportTest, BvhRigBecomesASkinnedArmature) {
  const MotionAsset rig = tinyBvhAsset();
  const Clip& clip = rig.clips[0];
  test::TempDir dir;
  const std::filesystem::path path = dir / "tiny.glb";
  ASSERT_TRUE(saveGltf(path, rig, clip).ok());
  const MotionAsset back = load(path);
  ASSERT_EQ(back.skeleton.jointCount(), rig.skeleton.jointCount());
  EXPECT_EQ(back.skeleton.parents, rig.skeleton.parents);
  for (int j = 0; j < rig.skeleton.jointCount(); ++j) {
    EXPECT_LT(glm::length(back.skeleton.offsets[j] - rig.skeleton.offsets[j]), 1e-7);
  }
  ASSERT_EQ(back.clips.size(), 1u);
  EXPECT_EQ(back.clips[0].name, "tiny");
  EXPECT_EQ(back.clips[0].frame_count, clip.frame_count);
  EXPECT_NEAR(back.clips[0].frame_time, clip.frame_time, 1e-9);
  EXPECT_LT(worstPositionError(rig, clip, back, back.clips[0]), 1e-5);
  // The bone mesh: octahedra to each child and End Site, rigidly bound, in the rest pose.
  ASSERT_EQ(back.meshes.size(), 1u);
  const SkinnedMesh& mesh = back.meshes[0];
  // 5 bones: Hips to LeftLeg and to Chest, Chest to Head, and the two End Sites.
  EXPECT_EQ(mesh.positions.size(), 5u * 24u);
  EXPECT_EQ(mesh.indices.size(), mesh.positions.size());
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  const std::vector<glm::dmat4> rest = restWorldTransforms(rig.skeleton);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    ASSERT_EQ(mesh.weights[v], glm::vec4(1, 0, 0, 0));
    ASSERT_NEAR(glm::length(mesh.normals[v]), 1.0f, 1e-5f);
  }
  for (int j = 0; j < rig.skeleton.jointCount(); ++j) {
    const glm::dmat4 product = rest[j] * mesh.inverse_bind[j];
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(product[c][r], c == r ? 1.0 : 0.0, 1e-6);
    }
  }
}

TEST(GltfExportTest, RealBvhRoundTripsThroughGlb) {
  SINEW_REQUIRE_SHARED_DATA();
  const std::filesystem::path source =
      test::sharedData() / "bvh" / "bandai_dataset-1_walk_normal_001.bvh";
  Result<MotionAsset> rig = readBvh(test::readText(source), source.string());
  ASSERT_TRUE(rig.ok()) << rig.message();
  const Clip& clip = rig.value().clips[0];
  test::TempDir dir;
  for (const char* name : {"bandai.glb", "bandai.gltf"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(saveGltf(dir / name, rig.value(), clip).ok());
    const MotionAsset back = load(dir / name);
    ASSERT_EQ(back.clips.size(), 1u);
    EXPECT_NEAR(back.clips[0].frame_time, clip.frame_time, 1e-9);  // 0.0333333 stays
    const double error = worstPositionError(rig.value(), clip, back, back.clips[0]);
    std::cout << "[ figures  ] " << name << ": " << clip.frame_count << " frames, "
              << back.meshes[0].indices.size() / 3 << " bone triangles, worst joint position "
              << "error " << error << " m\n";
    EXPECT_LT(error, 1e-5);
  }
}

TEST(GltfExportTest, ExternalBufferAndImageAreEmbedded) {
  // A .gltf whose buffer and image are files beside it exports as one self-contained file with
  // the image's bytes unchanged (not decoded and re-encoded).
  test::TempDir dir;
  const std::string png = base64Decode(
      "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8DwHwAFBQIAX8jx0gAAAABJRU5ErkJg"
      "gg==");
  test::writeText(dir / "pixel one.png", png);
  DocBuilder b = interleavedMeshDocument();
  b.doc["images"] = json::array({{{"uri", "pixel%20one.png"}}});
  const std::filesystem::path source = b.writeWithExternalBuffer(dir, "external.gltf", "data.bin");
  const MotionAsset asset = load(source);
  ASSERT_EQ(asset.meshes.size(), 1u);
  EXPECT_FALSE(asset.gltf->binary);
  EXPECT_EQ(asset.gltf->directory, dir.path());
  test::TempDir out_dir;  // elsewhere, so nothing beside the output could be read by accident
  for (const char* name : {"embedded.gltf", "embedded.glb"}) {
    SCOPED_TRACE(name);
    const std::filesystem::path out = out_dir / name;
    ASSERT_TRUE(saveGltf(out, asset, restClip(asset.skeleton, 2, 1.0 / 30.0)).ok());
    const std::string bytes = test::readText(out);
    const bool binary = std::string(name).ends_with(".glb");
    const Glb glb = binary ? splitGlb(bytes) : Glb{json::parse(bytes), ""};
    ASSERT_EQ(glb.doc["buffers"].size(), 1u);
    std::string data = glb.bin;
    if (!binary) {
      const std::string uri = glb.doc["buffers"][0]["uri"];
      ASSERT_EQ(uri.rfind("data:application/octet-stream;base64,", 0), 0u);
      data = base64Decode(uri.substr(uri.find(',') + 1));
    }
    const json& image = glb.doc["images"][0];
    EXPECT_FALSE(image.contains("uri"));
    EXPECT_EQ(image["mimeType"], "image/png");
    const json& view = glb.doc["bufferViews"][image["bufferView"].get<int>()];
    EXPECT_EQ(data.substr(view.value("byteOffset", size_t{0}), view["byteLength"].get<size_t>()),
              png);
    const MotionAsset back = load(out);
    ASSERT_EQ(back.meshes.size(), 1u);
    EXPECT_EQ(back.meshes[0].positions, asset.meshes[0].positions);
  }
}

// tinygltf writes an object with nothing in it as null, which no reader takes back. A scene
// whose nodes sit under a key the reader does not know (gltf_fuzz found it), a joint node with
// nothing but its place in the tree, and bare samplers, textures and materials must all export
// to a file that reads back with the same joints and frames.
TEST(GltfExportTest, ObjectsWithNothingInThemStillReadBack) {
  DocBuilder b = curvesDocument();
  b.doc["nodes"][1]["children"] = json::array({2});
  b.doc["nodes"].push_back(json::object());
  b.doc["scenes"].push_back({{"nodez", json::array({0})}});  // a second scene, the default first
  b.doc["samplers"] = json::array({json::object()});
  b.doc["textures"] = json::array({json::object()});
  b.doc["materials"] = json::array({json::object()});
  test::TempDir dir;
  const MotionAsset asset = load(b.write(dir, "bare.gltf"));
  ASSERT_EQ(asset.skeleton.jointCount(), 3);
  ASSERT_EQ(asset.clips.size(), 1u);
  for (const char* name : {"bare.glb", "bare_out.gltf"}) {
    SCOPED_TRACE(name);
    const std::filesystem::path out = dir / name;
    ASSERT_TRUE(saveGltf(out, asset, asset.clips[0]).ok());
    const std::string bytes = test::readText(out);
    const json doc = std::string(name).ends_with(".glb") ? splitGlb(bytes).doc : json::parse(bytes);
    for (const char* key : {"scenes", "nodes", "samplers", "textures", "materials"}) {
      ASSERT_TRUE(doc.contains(key)) << key;
      for (const json& object : doc[key]) EXPECT_TRUE(object.is_object()) << key << ": " << object;
    }
    const MotionAsset back = load(out);
    EXPECT_EQ(back.skeleton.names, asset.skeleton.names);
    ASSERT_EQ(back.clips.size(), 1u);
    EXPECT_EQ(back.clips[0].frame_count, asset.clips[0].frame_count);
  }
}

TEST(GltfExportTest, RefusesWhatItCannotWrite) {
  const MotionAsset rig = tinyBvhAsset();
  test::TempDir dir;
  const Status wrong_type = saveGltf(dir / "tiny.obj", rig, rig.clips[0]);
  EXPECT_FALSE(wrong_type.ok());
  EXPECT_NE(wrong_type.message().find("tiny.obj"), std::string::npos);
  Clip short_clip = rig.clips[0];
  short_clip.joint_count = 2;
  const Status mismatch = saveGltf(dir / "tiny.glb", rig, short_clip);
  EXPECT_FALSE(mismatch.ok());
  EXPECT_NE(mismatch.message().find("tiny.glb"), std::string::npos) << mismatch.message();
  EXPECT_FALSE(std::filesystem::exists(dir / "tiny.glb"));
}

// ================================================================================================
// The Khronos validator on every kind of export

TEST(GltfValidatorTest, EveryExportHasNoErrors) {
  const std::filesystem::path tools = test::sourceDir() / "tools";
  if (!std::filesystem::exists(tools / "node_modules" / "gltf-validator")) {
    GTEST_SKIP() << "the glTF validator is not installed (" << (tools / "node_modules")
                 << " is missing); run: npm ci --prefix tools";
  }
  if (test::runCommand("node --version").exit_code != 0) {
    GTEST_SKIP() << "node is not on PATH; the glTF validator needs it";
  }
  test::TempDir dir;
  std::vector<std::filesystem::path> files;
  const MotionAsset tiny = tinyBvhAsset();
  for (const char* name : {"tiny.glb", "tiny.gltf"}) {
    ASSERT_TRUE(saveGltf(dir / name, tiny, tiny.clips[0]).ok());
    files.push_back(dir / name);
  }
  if (test::haveSharedData()) {
    const MotionAsset fox = load(gltfData("Fox.glb"));
    for (const char* name : {"fox_walk.glb", "fox_walk.gltf"}) {
      ASSERT_TRUE(saveGltf(dir / name, fox, clipNamed(fox, "Walk")).ok());
      files.push_back(dir / name);
    }
    ASSERT_TRUE(saveGltf(dir / "fox_run.glb", fox, clipNamed(fox, "Run")).ok());
    files.push_back(dir / "fox_run.glb");
    const MotionAsset figure = load(gltfData("RiggedFigure.glb"));
    ASSERT_TRUE(saveGltf(dir / "figure.glb", figure, figure.clips[0]).ok());
    files.push_back(dir / "figure.glb");
    const std::filesystem::path bvh =
        test::sharedData() / "bvh" / "bandai_dataset-1_walk_normal_001.bvh";
    Result<MotionAsset> bandai = readBvh(test::readText(bvh), bvh.string());
    ASSERT_TRUE(bandai.ok()) << bandai.message();
    for (const char* name : {"bandai.glb", "bandai.gltf"}) {
      ASSERT_TRUE(saveGltf(dir / name, bandai.value(), bandai.value().clips[0]).ok());
      files.push_back(dir / name);
    }
  }
  std::string command = "node " + test::quote(tools / "validate_gltf.mjs");
  for (const auto& file : files) {
    command += ' ';
    command += test::quote(file);
  }
  const test::CommandResult result = test::runCommand(command);
  std::cout << result.out << result.err;
  EXPECT_EQ(result.exit_code, 0);
  for (const auto& file : files) {
    SCOPED_TRACE(file.filename().string());
    const std::regex counts(
        std::regex_replace(file.string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
        R"(: (\d+) errors, (\d+) warnings)");
    std::smatch match;
    ASSERT_TRUE(std::regex_search(result.out, match, counts)) << result.out;
    EXPECT_EQ(match[1], "0");
    // The only warning allowed is RiggedFigure's own: its skinned mesh node has a parent.
    EXPECT_EQ(match[2], file.filename() == "figure.glb" ? "1" : "0");
  }
}

}  // namespace
}  // namespace sinew::motion
