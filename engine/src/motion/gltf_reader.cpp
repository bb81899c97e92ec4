// glTF import: the first skin's joint hierarchy, the meshes it skins, and every animation
// resampled to a fixed frame rate.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <unordered_set>

#include "gltf_common.h"
#include "gltf_units.h"
#include "sinew/core/file_io.h"
#include "sinew/core/text.h"
#include "sinew/motion/gltf.h"

namespace sinew::motion {
namespace {

using gltf::AccessorValues;
using gltf::readAccessor;
using tinygltf::Model;

// Key times are float32, so times closer than about two float ulps cannot be told apart: a
// frame that falls that close to a key takes the key's value exactly.
double keyTolerance(double t) {
  return 1e-6 + 2.4e-7 * std::abs(t);
}

// Frames x joints: 800 MB of poses while reading (rotation, translation and scale), 20 minutes of
// a 70-joint capture at 120 fps. A clip's length comes from its key times, not from the file's
// size, so two keys a million seconds apart must not ask for 5 GB (the fuzzer found that).
constexpr double kMaxClipValues = 1e7;

struct Context {
  const Model& model;
  std::string file;  // the path, for messages
  std::vector<std::string>& warnings;
  Status fail(const std::string& what) const { return Status::error(file + ": " + what); }
};

// ---------------------------------------------------------------------------------------------
// Nodes and the skeleton

struct NodeTree {
  std::vector<int> parent;        // (nodes) parent node, or -1
  std::vector<gltf::Trs> local;   // (nodes) local transform
  std::vector<glm::dmat4> world;  // (nodes) rest world transform
};

Result<NodeTree> readNodeTree(const Context& ctx) {
  const int n = static_cast<int>(ctx.model.nodes.size());
  NodeTree tree;
  tree.parent.assign(n, -1);
  tree.local.resize(n);
  tree.world.assign(n, glm::dmat4(1.0));
  for (int i = 0; i < n; ++i) {
    for (int child : ctx.model.nodes[i].children) {
      if (child < 0 || child >= n) {
        return ctx.fail("node " + std::to_string(i) + ": child " + std::to_string(child) +
                        " does not exist");
      }
      if (child == i) return ctx.fail("node " + std::to_string(i) + " is its own child");
      if (tree.parent[child] != -1) {
        return ctx.fail("node " + std::to_string(child) + " has two parents (nodes " +
                        std::to_string(tree.parent[child]) + " and " + std::to_string(i) +
                        "); the node hierarchy must be a tree");
      }
      tree.parent[child] = i;
    }
    bool sheared = false;
    Result<gltf::Trs> trs = gltf::nodeTrs(ctx.model.nodes[i], i, &sheared);
    if (!trs.ok()) return ctx.fail(trs.message());
    tree.local[i] = trs.value();
    if (sheared) {
      ctx.warnings.push_back("node " + std::to_string(i) + " '" + ctx.model.nodes[i].name +
                             "': its matrix has shear, which a joint cannot hold; dropped");
    }
  }
  // World transforms from the roots down; a node never reached sits on a cycle.
  std::vector<char> reached(n, 0);
  std::vector<int> stack;
  for (int root = 0; root < n; ++root) {
    if (tree.parent[root] != -1) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int node = stack.back();
      stack.pop_back();
      reached[node] = 1;
      const glm::dmat4 local = tree.local[node].matrix();
      tree.world[node] = tree.parent[node] == -1 ? local : tree.world[tree.parent[node]] * local;
      for (int child : ctx.model.nodes[node].children) stack.push_back(child);
    }
  }
  for (int i = 0; i < n; ++i) {
    if (!reached[i]) {
      return ctx.fail("node " + std::to_string(i) + " is part of a cycle in the node hierarchy");
    }
  }
  return tree;
}

// Which nodes become joints: the first skin's joints and their ancestors, or (no skin) the
// default scene's whole tree. Returned in depth-first order, parents before children.
Result<std::vector<int>> selectJointNodes(const Context& ctx, const NodeTree& tree) {
  const Model& model = ctx.model;
  const int n = static_cast<int>(model.nodes.size());
  std::vector<char> member(n, 0);
  auto markWithAncestors = [&](int node) {
    for (int a = node; a != -1 && !member[a]; a = tree.parent[a]) member[a] = 1;
  };
  std::vector<int> scene_roots;
  const int scene = model.defaultScene >= 0 && model.defaultScene < int(model.scenes.size())
                        ? model.defaultScene
                        : (model.scenes.empty() ? -1 : 0);
  if (scene >= 0) {
    for (int root : model.scenes[scene].nodes) {
      if (root < 0 || root >= n) {
        return ctx.fail("scene " + std::to_string(scene) + ": node " + std::to_string(root) +
                        " does not exist");
      }
      scene_roots.push_back(root);
    }
  }
  if (!model.skins.empty()) {
    if (model.skins[0].joints.empty())
      return ctx.fail("skin 0 has no joints, so there is no skeleton to import");
    for (int node : model.skins[0].joints) {
      if (node < 0 || node >= n) {
        return ctx.fail("skin 0: joint node " + std::to_string(node) + " does not exist");
      }
      markWithAncestors(node);
    }
  } else if (scene >= 0) {
    std::vector<int> stack = scene_roots;
    while (!stack.empty()) {
      const int node = stack.back();
      stack.pop_back();
      markWithAncestors(node);
      for (int child : model.nodes[node].children) stack.push_back(child);
    }
  } else {
    std::fill(member.begin(), member.end(), 1);
  }

  std::vector<int> order;
  std::vector<char> placed(n, 0);
  std::vector<int> candidates = scene_roots;
  for (int i = 0; i < n; ++i) candidates.push_back(i);
  for (int root : candidates) {
    if (!member[root] || placed[root] || (tree.parent[root] != -1 && member[tree.parent[root]])) {
      continue;
    }
    std::vector<int> stack{root};
    while (!stack.empty()) {
      const int node = stack.back();
      stack.pop_back();
      placed[node] = 1;
      order.push_back(node);
      const std::vector<int>& children = model.nodes[node].children;
      for (auto it = children.rbegin(); it != children.rend(); ++it) {
        if (member[*it]) stack.push_back(*it);
      }
    }
  }
  if (order.empty()) return ctx.fail("has no nodes, so there is no skeleton to import");
  return order;
}

// A name as UTF-8 text without control characters (a NUL would cut it short in a writer).
std::string printableName(const std::string& raw) {
  std::string name = toUtf8(raw);
  for (char& c : name) {
    if (firstControlCharacter(std::string_view(&c, 1)) >= 0) c = '_';
  }
  return name;
}

// Joint names are unique, non-empty and free of whitespace (BVH export writes them as words).
std::vector<std::string> jointNames(const Model& model, const std::vector<int>& nodes) {
  std::vector<std::string> names;
  std::unordered_set<std::string> taken;
  for (int node : nodes) {
    std::string name = printableName(model.nodes[node].name);
    for (char& c : name) {
      if (std::isspace(static_cast<unsigned char>(c))) c = '_';
    }
    if (name.empty()) name = "node_" + std::to_string(node);
    std::string unique = name;
    for (int suffix = 2; taken.count(unique); ++suffix)
      unique = name + "_" + std::to_string(suffix);
    taken.insert(unique);
    names.push_back(unique);
  }
  return names;
}

// ---------------------------------------------------------------------------------------------
// Meshes

// Whether an (existing) accessor holds unsigned bytes or shorts, or with `allow_int` also
// unsigned ints: the types joint indices and vertex indices must have.
bool isUnsigned(const Model& model, int accessor, bool allow_int) {
  const int type = model.accessors[accessor].componentType;
  return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         (allow_int && type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
}

// Reads one skinned triangle primitive; `skin_to_joint` maps skin joint indices to skeleton
// joints. Returns false (with a warning) for primitives that cannot be drawn skinned.
Result<bool> readPrimitive(const Context& ctx, const tinygltf::Primitive& primitive,
                           const std::string& where, const std::vector<int>& skin_to_joint,
                           SkinnedMesh& mesh) {
  const Model& model = ctx.model;
  if (primitive.mode != TINYGLTF_MODE_TRIANGLES) {
    ctx.warnings.push_back(where + ": mode " + std::to_string(primitive.mode) +
                           " is not triangles; skipped");
    return false;
  }
  auto attribute = [&](const char* name) {
    auto it = primitive.attributes.find(name);
    return it == primitive.attributes.end() ? -1 : it->second;
  };
  if (attribute("POSITION") < 0 || attribute("JOINTS_0") < 0 || attribute("WEIGHTS_0") < 0) {
    ctx.warnings.push_back(where + ": lacks POSITION, JOINTS_0 or WEIGHTS_0; skipped");
    return false;
  }
  if (!primitive.targets.empty()) {
    ctx.warnings.push_back(where + ": morph targets are not imported");
  }
  auto read = [&](const char* name, int type) -> Result<AccessorValues> {
    Result<AccessorValues> values = readAccessor(model, attribute(name), type);
    if (!values.ok()) return ctx.fail(where + ": " + name + " " + values.message());
    return values;
  };
  Result<AccessorValues> positions = read("POSITION", TINYGLTF_TYPE_VEC3);
  if (!positions.ok()) return positions.status();
  const size_t vertices = positions.value().count;
  // Up to two sets of four influences; the four heaviest are kept.
  std::vector<AccessorValues> joint_sets;
  std::vector<AccessorValues> weight_sets;
  for (const char* set : {"0", "1"}) {
    const std::string joints_name = std::string("JOINTS_") + set;
    const std::string weights_name = std::string("WEIGHTS_") + set;
    if (attribute(joints_name.c_str()) < 0 || attribute(weights_name.c_str()) < 0) break;
    Result<AccessorValues> joints = read(joints_name.c_str(), TINYGLTF_TYPE_VEC4);
    Result<AccessorValues> weights = read(weights_name.c_str(), TINYGLTF_TYPE_VEC4);
    if (!joints.ok()) return joints.status();
    if (!weights.ok()) return weights.status();
    if (!isUnsigned(model, attribute(joints_name.c_str()), false)) {
      return ctx.fail(where + ": " + joints_name + " must be unsigned bytes or shorts");
    }
    if (joints.value().count != vertices || weights.value().count != vertices) {
      return ctx.fail(where + ": " + joints_name + "/" + weights_name + " hold " +
                      std::to_string(joints.value().count) + "/" +
                      std::to_string(weights.value().count) + " values for " +
                      std::to_string(vertices) + " vertices");
    }
    joint_sets.push_back(std::move(joints).value());
    weight_sets.push_back(std::move(weights).value());
  }
  mesh.positions.resize(vertices);
  for (size_t v = 0; v < vertices; ++v) mesh.positions[v] = glm::vec3(positions.value().vec4(v));
  if (attribute("NORMAL") >= 0) {
    Result<AccessorValues> normals = read("NORMAL", TINYGLTF_TYPE_VEC3);
    if (!normals.ok()) return normals.status();
    if (normals.value().count != vertices) {
      return ctx.fail(where + ": NORMAL has " + std::to_string(normals.value().count) +
                      " values for " + std::to_string(vertices) + " vertices");
    }
    mesh.normals.resize(vertices);
    for (size_t v = 0; v < vertices; ++v) {
      const glm::dvec3 normal(normals.value().vec4(v));
      const double length = glm::length(normal);
      mesh.normals[v] = length > 1e-12 ? glm::vec3(normal / length) : glm::vec3(0, 1, 0);
    }
  }
  mesh.joints.resize(vertices);
  mesh.weights.resize(vertices);
  size_t unweighted = 0;
  for (size_t v = 0; v < vertices; ++v) {
    std::vector<std::pair<double, double>> influences;  // (weight, skin joint)
    for (size_t set = 0; set < joint_sets.size(); ++set) {
      for (int k = 0; k < 4; ++k) {
        influences.emplace_back(weight_sets[set].vec4(v)[k], joint_sets[set].vec4(v)[k]);
      }
    }
    std::stable_sort(influences.begin(), influences.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    double total = 0.0;
    for (int k = 0; k < 4; ++k) {
      auto [weight, skin_joint] = influences[k];
      if (weight <= 0.0) weight = 0.0;
      if (skin_joint < 0.0 || skin_joint >= static_cast<double>(skin_to_joint.size())) {
        if (weight > 0.0) {
          return ctx.fail(where + ": vertex " + std::to_string(v) + " uses skin joint " +
                          std::to_string(static_cast<long>(skin_joint)) + ", the skin has " +
                          std::to_string(skin_to_joint.size()));
        }
        skin_joint = 0;
      }
      mesh.joints[v][k] =
          static_cast<std::uint16_t>(skin_to_joint[static_cast<size_t>(skin_joint)]);
      mesh.weights[v][k] = static_cast<float>(weight);
      total += weight;
    }
    if (total > 0.0) {
      mesh.weights[v] /= static_cast<float>(total);
    } else {
      mesh.weights[v] = glm::vec4(1, 0, 0, 0);
      ++unweighted;
    }
  }
  if (unweighted > 0) {
    ctx.warnings.push_back(where + ": " + std::to_string(unweighted) +
                           " vertices had no weight; bound to their first joint");
  }
  if (primitive.indices >= 0) {
    Result<AccessorValues> indices = readAccessor(model, primitive.indices, TINYGLTF_TYPE_SCALAR);
    if (!indices.ok()) return ctx.fail(where + ": indices " + indices.message());
    if (!isUnsigned(model, primitive.indices, true)) {
      return ctx.fail(where + ": indices must be unsigned integers");
    }
    mesh.indices.reserve(indices.value().count);
    for (double index : indices.value().values) {
      if (index < 0.0 || index >= static_cast<double>(vertices)) {
        return ctx.fail(where + ": index " + std::to_string(static_cast<long>(index)) +
                        " is past the " + std::to_string(vertices) + " vertices");
      }
      mesh.indices.push_back(static_cast<std::uint32_t>(index));
    }
  } else {
    for (size_t v = 0; v < vertices; ++v) mesh.indices.push_back(static_cast<std::uint32_t>(v));
  }
  if (mesh.indices.size() % 3 != 0) {
    return ctx.fail(where + ": " + std::to_string(mesh.indices.size()) +
                    " indices do not make whole triangles");
  }
  return true;
}

Status readMeshes(const Context& ctx, const NodeTree& tree, const std::vector<int>& joint_of_node,
                  int joint_count, std::vector<SkinnedMesh>& meshes) {
  const Model& model = ctx.model;
  if (model.skins.size() > 1) {
    ctx.warnings.push_back("the file has " + std::to_string(model.skins.size()) +
                           " skins; only the first is imported");
  }
  if (joint_count > 65536) {  // SkinnedMesh::joints holds 16-bit indices
    ctx.warnings.push_back("more than 65536 joints; meshes are not imported");
    return {};
  }
  int unskinned = 0;
  std::vector<int> skin_to_joint;
  std::vector<glm::dmat4> inverse_bind(joint_count, glm::dmat4(1.0));
  if (!model.skins.empty()) {
    const tinygltf::Skin& skin = model.skins[0];
    for (int node : skin.joints) skin_to_joint.push_back(joint_of_node[node]);
    if (skin.inverseBindMatrices >= 0) {
      Result<AccessorValues> matrices =
          readAccessor(model, skin.inverseBindMatrices, TINYGLTF_TYPE_MAT4);
      if (!matrices.ok()) return ctx.fail("skin 0: inverseBindMatrices " + matrices.message());
      if (matrices.value().count < skin.joints.size()) {
        return ctx.fail("skin 0: " + std::to_string(matrices.value().count) +
                        " inverse bind matrices for " + std::to_string(skin.joints.size()) +
                        " joints");
      }
      for (size_t s = 0; s < skin.joints.size(); ++s) {
        glm::dmat4& m = inverse_bind[skin_to_joint[s]];
        for (int c = 0; c < 4; ++c) {
          for (int r = 0; r < 4; ++r) m[c][r] = matrices.value().values[s * 16 + c * 4 + r];
        }
      }
    }
  }
  for (int n = 0; n < static_cast<int>(model.nodes.size()); ++n) {
    const tinygltf::Node& node = model.nodes[n];
    if (node.mesh < 0) continue;
    if (node.mesh >= static_cast<int>(model.meshes.size()) ||
        node.skin >= static_cast<int>(model.skins.size())) {
      return ctx.fail("node " + std::to_string(n) + ": mesh " + std::to_string(node.mesh) +
                      " or skin " + std::to_string(node.skin) + " does not exist");
    }
    if (node.skin != 0) {
      ++unskinned;
      continue;
    }
    const tinygltf::Mesh& source = model.meshes[node.mesh];
    const std::string base =
        source.name.empty() ? "mesh_" + std::to_string(node.mesh) : source.name;
    for (size_t p = 0; p < source.primitives.size(); ++p) {
      SkinnedMesh mesh;
      mesh.name = source.primitives.size() == 1 ? base : base + "_" + std::to_string(p);
      const std::string where = "mesh " + std::to_string(node.mesh) + " '" + source.name +
                                "', primitive " + std::to_string(p);
      Result<bool> read = readPrimitive(ctx, source.primitives[p], where, skin_to_joint, mesh);
      if (!read.ok()) return read.status();
      if (!read.value()) continue;
      mesh.inverse_bind = inverse_bind;
      mesh.mesh_to_world = tree.world[n];
      meshes.push_back(std::move(mesh));
    }
  }
  if (unskinned > 0) {
    ctx.warnings.push_back(std::to_string(unskinned) +
                           " mesh nodes are not skinned by the first skin; not imported");
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
// Animations

enum class Interpolation { kLinear, kStep, kCubicSpline };

struct Curve {
  Interpolation mode = Interpolation::kLinear;
  std::vector<double> times;  // (keys) seconds, non-decreasing
  AccessorValues values;      // (keys), or (3 x keys) in-tangent, value, out-tangent for cubic
  glm::dvec4 key(size_t k) const {
    return values.vec4(mode == Interpolation::kCubicSpline ? 3 * k + 1 : k);
  }
};

// The value at time t, clamped outside the keys. Rotations (x, y, z, w) interpolate along the
// shortest arc and come back unit length.
glm::dvec4 sampleCurve(const Curve& curve, double t, bool rotation) {
  const std::vector<double>& times = curve.times;
  const double tolerance = keyTolerance(t);
  glm::dvec4 value;
  if (t <= times.front() + tolerance) {
    value = curve.key(0);
  } else if (t >= times.back() - tolerance) {
    value = curve.key(times.size() - 1);
  } else {
    const size_t k =
        static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) -
        1;  // times[k] <= t < times[k + 1]
    const double span = times[k + 1] - times[k];
    const double u = (t - times[k]) / span;
    if (t - times[k] <= tolerance) {
      value = curve.key(k);
    } else if (times[k + 1] - t <= tolerance) {
      value = curve.key(k + 1);
    } else if (curve.mode == Interpolation::kStep) {
      value = curve.key(k);
    } else if (curve.mode == Interpolation::kLinear) {
      const glm::dvec4 a = curve.key(k);
      const glm::dvec4 b = curve.key(k + 1);
      if (rotation) {  // keys need not be unit length (normalized shorts are not quite)
        const glm::dquat q = glm::slerp(glm::normalize(glm::dquat(a.w, a.x, a.y, a.z)),
                                        glm::normalize(glm::dquat(b.w, b.x, b.y, b.z)),
                                        u);  // shortest arc
        value = {q.x, q.y, q.z, q.w};
      } else {
        value = glm::mix(a, b, u);
      }
    } else {  // cubic Hermite; tangents are per second, so scale them by the key spacing
      const double u2 = u * u;
      const double u3 = u2 * u;
      value = (2 * u3 - 3 * u2 + 1) * curve.values.vec4(3 * k + 1) +
              span * (u3 - 2 * u2 + u) * curve.values.vec4(3 * k + 2) +
              (-2 * u3 + 3 * u2) * curve.values.vec4(3 * (k + 1) + 1) +
              span * (u3 - u2) * curve.values.vec4(3 * (k + 1));
    }
  }
  return rotation ? glm::normalize(value) : value;
}

// Reads a sampler's key times and (when `output_type` is not 0) its values.
Result<Curve> readCurve(const Context& ctx, const tinygltf::AnimationSampler& sampler,
                        int output_type, const std::string& where) {
  Curve curve;
  if (sampler.interpolation == "STEP") {
    curve.mode = Interpolation::kStep;
  } else if (sampler.interpolation == "CUBICSPLINE") {
    curve.mode = Interpolation::kCubicSpline;
  } else if (sampler.interpolation != "LINEAR") {
    return ctx.fail(where + "unknown interpolation '" + sampler.interpolation + "'");
  }
  Result<AccessorValues> input = readAccessor(ctx.model, sampler.input, TINYGLTF_TYPE_SCALAR);
  if (!input.ok()) return ctx.fail(where + "input " + input.message());
  if (input.value().count == 0) {
    return ctx.fail(where + "input accessor " + std::to_string(sampler.input) + " has 0 keys");
  }
  curve.times = std::move(input.value().values);
  for (size_t k = 1; k < curve.times.size(); ++k) {
    if (curve.times[k] < curve.times[k - 1]) {
      return ctx.fail(where + "key times go backwards at key " + std::to_string(k) + " (" +
                      std::to_string(curve.times[k - 1]) + " s, then " +
                      std::to_string(curve.times[k]) + " s)");
    }
  }
  if (output_type == 0) return curve;
  Result<AccessorValues> output = readAccessor(ctx.model, sampler.output, output_type);
  if (!output.ok()) return ctx.fail(where + "output " + output.message());
  const size_t keys = curve.times.size();
  const size_t expected = curve.mode == Interpolation::kCubicSpline ? 3 * keys : keys;
  if (output.value().count != expected) {
    return ctx.fail(where + "output accessor " + std::to_string(sampler.output) + " has " +
                    std::to_string(output.value().count) + " values for " + std::to_string(keys) +
                    " keys (" + sampler.interpolation + " needs " + std::to_string(expected) + ")");
  }
  curve.values = std::move(output).value();
  if (output_type == TINYGLTF_TYPE_VEC4) {
    for (size_t k = 0; k < keys; ++k) {
      if (!(glm::length(curve.key(k)) > 1e-12)) {
        return ctx.fail(where + "rotation key " + std::to_string(k) + " is a zero quaternion");
      }
    }
  }
  return curve;
}

// A frame time that close to a whole number of frames per second (23.9999993) becomes it.
double wholeRate(double frame_time) {
  const double fps = std::round(1.0 / frame_time);
  if (fps >= 1.0 && std::abs(1.0 / frame_time - fps) <= 2e-7 * fps) return 1.0 / fps;
  return frame_time;
}

// The spacing of keys that are evenly spaced (what every exporter writes, Sinew included): the
// whole span over the key count, when every key lies within float32 rounding of its place on
// that grid; else 0. Late in a long clip float32 times step by 6e-5 s (t = 666 s), so single
// spacings are off by 0.2% while the span stays exact to 1e-9 (20,000 frames at 30 fps).
double uniformSpacing(const std::vector<double>& times) {
  const double step = (times.back() - times.front()) / static_cast<double>(times.size() - 1);
  if (!(step > 0.0)) return 0.0;
  for (size_t k = 0; k < times.size(); ++k) {
    const double expected = times.front() + static_cast<double>(k) * step;
    if (std::abs(times[k] - expected) > keyTolerance(expected)) return 0.0;
  }
  return step;
}

// Seconds per frame: the requested rate, else the median key spacing. Key times are float32,
// which puts each spacing off by up to a few 1e-6 relative, so the median is refined to the mean
// of the spacings that agree with it (over a run of keys that is the run's length over its key
// count, good to ~1e-8), and a rate that close to a whole number of frames per second
// (23.9999993) becomes that number. A real 0.0333333 s (1e-6 away from 1/30) stays as it is.
double frameTimeFor(const std::vector<double>& times, const ImportOptions& options) {
  if (options.fps) return 1.0 / *options.fps;
  if (times.size() < 2) return 1.0 / 30.0;  // a single pose: any rate gives one frame
  if (const double uniform = uniformSpacing(times); uniform > 0.0) return wholeRate(uniform);
  std::vector<double> spacing;
  for (size_t k = 1; k < times.size(); ++k) spacing.push_back(times[k] - times[k - 1]);
  std::sort(spacing.begin(), spacing.end());
  const size_t mid = spacing.size() / 2;
  const double median =
      spacing.size() % 2 == 1 ? spacing[mid] : 0.5 * (spacing[mid - 1] + spacing[mid]);
  double sum = 0.0;
  int agreeing = 0;
  for (double d : spacing) {
    if (std::abs(d - median) <= 1e-3 * median) {
      sum += d;
      ++agreeing;
    }
  }
  return wholeRate(agreeing > 0 ? sum / agreeing : median);
}

Result<Clip> readAnimation(const Context& ctx, int index, const Skeleton& skeleton,
                           const std::vector<int>& joint_of_node, const ImportOptions& options) {
  const tinygltf::Animation& animation = ctx.model.animations[index];
  Clip clip;
  clip.name =
      animation.name.empty() ? "animation_" + std::to_string(index) : printableName(animation.name);
  const std::string label = "animation '" + clip.name + "'";

  struct Track {
    int joint;
    int path;  // 0 translation, 1 rotation, 2 scale
    Curve curve;
  };
  std::vector<Track> tracks;
  std::vector<double> times;
  int elsewhere = 0;
  int morph = 0;
  for (size_t c = 0; c < animation.channels.size(); ++c) {
    const tinygltf::AnimationChannel& channel = animation.channels[c];
    const std::string where = label + ", channel " + std::to_string(c) + ": ";
    if (channel.sampler < 0 || channel.sampler >= static_cast<int>(animation.samplers.size())) {
      return ctx.fail(where + "sampler " + std::to_string(channel.sampler) + " does not exist");
    }
    const std::string sampler_where = where + "sampler " + std::to_string(channel.sampler) + " ";
    const int node = channel.target_node;
    const int joint =
        node >= 0 && node < static_cast<int>(joint_of_node.size()) ? joint_of_node[node] : -1;
    const std::string& path = channel.target_path;
    const int path_index = path == "translation" ? 0
                           : path == "rotation"  ? 1
                           : path == "scale"     ? 2
                                                 : -1;
    if (path == "weights") {
      ++morph;
    } else if (joint < 0 || path_index < 0) {
      ++elsewhere;
    }
    const bool used = joint >= 0 && path_index >= 0;
    const int output_type = !used ? 0 : path_index == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
    Result<Curve> curve =
        readCurve(ctx, animation.samplers[channel.sampler], output_type, sampler_where);
    if (!curve.ok()) return curve.status();
    times.insert(times.end(), curve.value().times.begin(), curve.value().times.end());
    if (used) tracks.push_back({joint, path_index, std::move(curve).value()});
  }
  if (elsewhere > 0) {
    ctx.warnings.push_back(label + ": " + std::to_string(elsewhere) +
                           " channels animate nodes outside the skeleton; ignored");
  }
  if (morph > 0) {
    ctx.warnings.push_back(label + ": " + std::to_string(morph) +
                           " channels animate morph target weights; ignored");
  }
  if (animation.channels.empty()) {
    ctx.warnings.push_back(label + ": has no channels; imported as the rest pose");
  }

  // Distinct key times over all channels.
  std::sort(times.begin(), times.end());
  std::vector<double> distinct;
  for (double t : times) {
    if (distinct.empty() || t - distinct.back() > keyTolerance(t)) distinct.push_back(t);
  }
  const double start = distinct.empty() ? 0.0 : distinct.front();
  const double duration = distinct.empty() ? 0.0 : distinct.back() - start;
  clip.frame_time = frameTimeFor(distinct, options);
  // frameCountFor's slack matters here: float32 key times put the last key a hair early.
  const double frames = frameCountFor(duration, clip.frame_time);
  if (frames * skeleton.jointCount() > kMaxClipValues) {
    return ctx.fail(label + ": " + std::to_string(duration) + " s at " +
                    std::to_string(1.0 / clip.frame_time) + " fps is too many frames (" +
                    std::to_string(static_cast<long long>(frames)) + " of " +
                    std::to_string(skeleton.jointCount()) +
                    " joints; Sinew reads up to 10 million joint poses a clip)");
  }
  clip.frame_count = static_cast<int>(frames);
  clip.joint_count = skeleton.jointCount();
  const size_t size = static_cast<size_t>(clip.frame_count) * clip.joint_count;
  clip.rotations.resize(size);
  clip.translations.resize(size);
  std::vector<glm::dvec3> scales(size);
  for (int f = 0; f < clip.frame_count; ++f) {
    for (int j = 0; j < clip.joint_count; ++j) {
      const size_t n = static_cast<size_t>(f) * clip.joint_count + j;
      clip.rotations[n] = skeleton.rest_rotations[j];
      clip.translations[n] = skeleton.offsets[j];
      scales[n] = skeleton.rest_scales[j];
    }
  }
  for (const Track& track : tracks) {
    for (int f = 0; f < clip.frame_count; ++f) {
      const size_t n = static_cast<size_t>(f) * clip.joint_count + track.joint;
      const glm::dvec4 v = sampleCurve(track.curve, start + f * clip.frame_time, track.path == 1);
      if (track.path == 0) clip.translations[n] = glm::dvec3(v);
      if (track.path == 1) clip.rotations[n] = glm::dquat(v.w, v.x, v.y, v.z);
      if (track.path == 2) scales[n] = glm::dvec3(v);
    }
  }
  // Forward kinematics skips scales when the array is empty; 1 +- 1e-6 is float32 noise.
  for (const glm::dvec3& s : scales) {
    if (std::abs(s.x - 1.0) > 1e-6 || std::abs(s.y - 1.0) > 1e-6 || std::abs(s.z - 1.0) > 1e-6) {
      clip.scales = std::move(scales);
      break;
    }
  }
  if (Status status = clip.validate(skeleton); !status.ok()) return ctx.fail(status.message());
  return clip;
}

// `source` holds the file's bytes; the joints' node indices are added to it.
Result<MotionAsset> importModel(const Model& model, const std::string& file,
                                const ImportOptions& options, GltfSource source) {
  MotionAsset asset;
  const Context ctx{model, file, asset.warnings};
  Result<NodeTree> tree = readNodeTree(ctx);
  if (!tree.ok()) return tree.status();
  Result<std::vector<int>> nodes = selectJointNodes(ctx, tree.value());
  if (!nodes.ok()) return nodes.status();
  const std::vector<int>& node_of_joint = nodes.value();

  Skeleton& skeleton = asset.skeleton;
  std::vector<int> joint_of_node(model.nodes.size(), -1);
  const std::vector<std::string> names = jointNames(model, node_of_joint);
  for (size_t j = 0; j < node_of_joint.size(); ++j) {
    const int node = node_of_joint[j];
    const int parent = tree.value().parent[node];
    const gltf::Trs& local = tree.value().local[node];
    joint_of_node[node] = skeleton.addJoint(
        names[j], parent == -1 ? kNoParent : joint_of_node[parent], local.translation);
    skeleton.rest_rotations[j] = local.rotation;
    skeleton.rest_scales[j] = local.scale;
  }
  if (Status status = skeleton.validate(); !status.ok()) return ctx.fail(status.message());

  if (Status status =
          readMeshes(ctx, tree.value(), joint_of_node, skeleton.jointCount(), asset.meshes);
      !status.ok()) {
    return status;
  }
  std::unordered_set<std::string> clip_names;
  for (int a = 0; a < static_cast<int>(model.animations.size()); ++a) {
    Result<Clip> clip = readAnimation(ctx, a, skeleton, joint_of_node, options);
    if (!clip.ok()) return clip.status();
    // The CLI picks animations by name, so each name must be unique.
    std::string name = clip.value().name;
    for (int suffix = 2; clip_names.count(name); ++suffix) {
      name = clip.value().name + "_" + std::to_string(suffix);
    }
    if (name != clip.value().name) {
      asset.warnings.push_back("two animations are named '" + clip.value().name +
                               "'; the later one is called '" + name + "'");
      clip.value().name = name;
    }
    clip_names.insert(name);
    asset.clips.push_back(std::move(clip).value());
  }
  // Everything so far holds the file's numbers; from here on, metres.
  gltf::toMetres(asset, options, source);
  if (Status status = skeleton.validate(); !status.ok()) return ctx.fail("in metres, " + status.message());
  for (const Clip& clip : asset.clips) {
    if (Status status = clip.validate(skeleton); !status.ok())
      return ctx.fail("animation '" + clip.name + "' in metres: " + status.message());
  }
  source.node_of_joint = node_of_joint;
  source.skin_count = static_cast<int>(model.skins.size());
  asset.gltf = std::make_shared<const GltfSource>(std::move(source));
  return asset;
}

}  // namespace

Result<MotionAsset> readGltf(std::string bytes, const std::filesystem::path& path,
                             const ImportOptions& options) {
  const std::string file = path.string();
  if (options.fps && !(*options.fps > 0.0 && *options.fps <= 1000.0)) {
    return Status::error(file + ": fps must be in (0, 1000], got " + std::to_string(*options.fps));
  }
  const bool binary = gltf::isGlb(bytes);
  // A .gltf is JSON text: a byte-order mark is dropped and Latin-1 text converted, as for every
  // reader (the spec asks for UTF-8; the .glb's JSON chunk is left as it is and refused if not).
  if (!binary) bytes = textAsUtf8(bytes);
  try {  // allocation failure on a huge file, or a tinygltf surprise: an error, never a crash
    Result<Model> model =
        gltf::parseDocument(bytes, binary, path.parent_path(), file, gltf::ImageBytes::kSkip);
    if (!model.ok()) return model.status();
    GltfSource source;
    source.bytes = std::move(bytes);
    source.binary = binary;
    source.directory = path.parent_path();
    Result<MotionAsset> asset = importModel(model.value(), file, options, std::move(source));
    if (asset.ok()) asset.value().path = path;
    return asset;
  } catch (const std::exception& e) {
    return Status::error(file + ": " + e.what());
  }
}

Result<MotionAsset> loadGltf(const std::filesystem::path& path, const ImportOptions& options) {
  Result<std::string> bytes = readFile(path);
  if (!bytes.ok()) return bytes.status();
  return readGltf(std::move(bytes).value(), path, options);
}

}  // namespace sinew::motion
