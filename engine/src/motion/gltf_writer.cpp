// glTF export: the clip as the one animation of the original glTF document (meshes, skin,
// materials and textures kept), or of a new document holding the joint hierarchy, a skin and a
// simple bone mesh, so that DCC tools and engines import an armature they can show.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <span>
#include <sstream>

#include <glm/gtc/matrix_inverse.hpp>

#include "gltf_common.h"
#include "gltf_units.h"
#include "sinew/core/file_io.h"
#include "sinew/core/text.h"
#include "sinew/motion/gltf.h"

namespace sinew::motion {
namespace {

using tinygltf::Model;

// Builds the document's single buffer: every piece starts on a 4-byte boundary, which every
// component type needs, and gets its own buffer view.
class BufferBuilder {
 public:
  explicit BufferBuilder(Model& model) : model_(model) {}

  int addView(const unsigned char* data, size_t size, int target) {
    bytes_.resize((bytes_.size() + 3) / 4 * 4, 0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes_.size();
    view.byteLength = size;
    view.target = target;
    bytes_.insert(bytes_.end(), data, data + size);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  // A tightly packed accessor over `values` (`type`'s component count per element). With
  // `bounds` it records min and max, which POSITION and animation inputs require.
  template <class T>
  int addAccessor(std::span<const T> values, int component_type, int type, int target,
                  bool bounds) {
    const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(type));
    tinygltf::Accessor accessor;
    accessor.bufferView =
        addView(reinterpret_cast<const unsigned char*>(values.data()), values.size_bytes(), target);
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = values.size() / components;
    if (bounds && !values.empty()) {
      accessor.minValues.assign(components, std::numeric_limits<double>::max());
      accessor.maxValues.assign(components, std::numeric_limits<double>::lowest());
      for (size_t n = 0; n < values.size(); ++n) {
        double& low = accessor.minValues[n % components];
        double& high = accessor.maxValues[n % components];
        low = std::min(low, static_cast<double>(values[n]));
        high = std::max(high, static_cast<double>(values[n]));
      }
    }
    model_.accessors.push_back(accessor);
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  int addFloats(std::span<const float> values, int type, int target = 0, bool bounds = false) {
    return addAccessor(values, TINYGLTF_COMPONENT_TYPE_FLOAT, type, target, bounds);
  }

  // Stores the bytes as buffer 0, the only buffer (the GLB binary chunk, or one data: URI).
  void finish() {
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes_);
    model_.buffers = {std::move(buffer)};
  }

 private:
  Model& model_;
  std::vector<unsigned char> bytes_;
};

void pushVec(std::vector<float>& out, const glm::dvec3& v) {
  out.insert(out.end(),
             {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)});
}

// The clip as one animation: LINEAR translation and rotation (and scale, when the clip has
// scales) samplers for every joint, sharing one time accessor.
void addAnimation(Model& model, BufferBuilder& buffer, const Clip& clip,
                  const std::vector<int>& node_of_joint) {
  std::vector<float> times(clip.frame_count);
  for (int f = 0; f < clip.frame_count; ++f) times[f] = static_cast<float>(f * clip.frame_time);
  const int input = buffer.addFloats(times, TINYGLTF_TYPE_SCALAR, 0, true);
  tinygltf::Animation animation;
  animation.name = clip.name.empty() ? "animation" : clip.name;
  auto addChannel = [&](int output, int joint, const char* path) {
    tinygltf::AnimationSampler sampler;
    sampler.input = input;
    sampler.output = output;
    sampler.interpolation = "LINEAR";
    animation.samplers.push_back(sampler);
    tinygltf::AnimationChannel channel;
    channel.sampler = static_cast<int>(animation.samplers.size()) - 1;
    channel.target_node = node_of_joint[joint];
    channel.target_path = path;
    animation.channels.push_back(channel);
  };
  for (int j = 0; j < clip.joint_count; ++j) {
    std::vector<float> translations;
    std::vector<float> rotations;
    std::vector<float> scales;
    glm::dquat previous(1.0, 0.0, 0.0, 0.0);
    for (int f = 0; f < clip.frame_count; ++f) {
      pushVec(translations, clip.translation(f, j));
      // Unit length (the validator checks), and signs continuous so that tools that blend
      // quaternion components rather than slerp take the short way too.
      glm::dquat q = glm::normalize(clip.rotation(f, j));
      if (f > 0 && glm::dot(q, previous) < 0.0) q = -q;
      previous = q;
      rotations.insert(rotations.end(), {static_cast<float>(q.x), static_cast<float>(q.y),
                                         static_cast<float>(q.z), static_cast<float>(q.w)});
      if (!clip.scales.empty()) pushVec(scales, clip.scale(f, j));
    }
    addChannel(buffer.addFloats(translations, TINYGLTF_TYPE_VEC3), j, "translation");
    addChannel(buffer.addFloats(rotations, TINYGLTF_TYPE_VEC4), j, "rotation");
    if (!scales.empty()) addChannel(buffer.addFloats(scales, TINYGLTF_TYPE_VEC3), j, "scale");
  }
  model.animations = {std::move(animation)};
}

std::string imageMimeType(const tinygltf::Image& image) {
  if (!image.mimeType.empty()) return image.mimeType;
  const std::vector<unsigned char>& b = image.image;
  if (b.size() >= 4 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G')
    return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  return "";
}

// Calls visit(int&) on every accessor index the kept parts of a document hold.
template <class Visit>
void forEachAccessorRef(Model& model, Visit visit) {
  for (tinygltf::Mesh& mesh : model.meshes) {
    for (tinygltf::Primitive& primitive : mesh.primitives) {
      for (auto& attribute : primitive.attributes) visit(attribute.second);
      for (auto& target : primitive.targets) {
        for (auto& attribute : target) visit(attribute.second);
      }
      visit(primitive.indices);
    }
  }
  for (tinygltf::Skin& skin : model.skins) visit(skin.inverseBindMatrices);
}

// Copies what the document still uses into `buffer`: without the old animations their
// accessors and views would be unused objects (validator warnings). Images stored behind URIs
// move into the buffer too, so the output is one self-contained file. Extensions may point at
// accessors or views by index in ways tinygltf cannot see, so with extensions nothing is dropped
// or renumbered.
Status repackBuffers(Model& model, BufferBuilder& buffer, const std::string& file) {
  const bool prune = model.extensionsUsed.empty();
  const int accessor_count = static_cast<int>(model.accessors.size());
  std::vector<int> accessor_map(accessor_count, prune ? -1 : 0);
  int missing = -1;
  forEachAccessorRef(model, [&](int& accessor) {
    if (accessor >= accessor_count) missing = accessor;
    if (accessor >= 0 && accessor < accessor_count) accessor_map[accessor] = 0;
  });
  if (missing >= 0) {
    return Status::error(file + ": accessor " + std::to_string(missing) + " does not exist");
  }
  std::vector<tinygltf::Accessor> accessors;
  for (int a = 0; a < accessor_count; ++a) {
    if (accessor_map[a] < 0) continue;
    accessor_map[a] = static_cast<int>(accessors.size());
    accessors.push_back(std::move(model.accessors[a]));
  }
  model.accessors = std::move(accessors);
  forEachAccessorRef(model, [&](int& accessor) {
    if (accessor >= 0) accessor = accessor_map[accessor];
  });

  // Views: copied in their original order when used, each to a fresh 4-byte boundary.
  const int view_count = static_cast<int>(model.bufferViews.size());
  std::vector<int> view_map(view_count, -1);
  std::vector<char> view_used(view_count, prune ? 0 : 1);
  std::vector<int*> view_refs;
  for (tinygltf::Accessor& accessor : model.accessors) {
    view_refs.push_back(&accessor.bufferView);
    if (accessor.sparse.isSparse) {
      view_refs.push_back(&accessor.sparse.indices.bufferView);
      view_refs.push_back(&accessor.sparse.values.bufferView);
    }
  }
  for (tinygltf::Image& image : model.images) view_refs.push_back(&image.bufferView);
  for (int* ref : view_refs) {
    if (*ref >= view_count) {
      return Status::error(file + ": buffer view " + std::to_string(*ref) + " does not exist");
    }
    if (*ref >= 0) view_used[*ref] = 1;
  }
  const std::vector<tinygltf::BufferView> old_views = std::move(model.bufferViews);
  model.bufferViews.clear();
  for (int v = 0; v < view_count; ++v) {
    if (!view_used[v]) continue;
    const tinygltf::BufferView& view = old_views[v];
    const std::vector<unsigned char>* data =
        view.buffer >= 0 && view.buffer < static_cast<int>(model.buffers.size())
            ? &model.buffers[view.buffer].data
            : nullptr;
    if (data == nullptr || view.byteLength > data->size() ||
        view.byteOffset > data->size() - view.byteLength) {
      return Status::error(file + ": buffer view " + std::to_string(v) +
                           " lies outside its buffer");
    }
    view_map[v] = buffer.addView(data->data() + view.byteOffset, view.byteLength, view.target);
    tinygltf::BufferView& copy = model.bufferViews.back();
    copy.byteStride = view.byteStride;
    copy.name = view.name;
    copy.extras = view.extras;
    copy.extensions = view.extensions;
  }
  for (int* ref : view_refs) {
    if (*ref >= 0) *ref = view_map[*ref];
  }
  for (tinygltf::Image& image : model.images) {
    const std::string mime = imageMimeType(image);
    if (image.bufferView < 0 && !image.image.empty() && !mime.empty()) {
      image.bufferView = buffer.addView(image.image.data(), image.image.size(), 0);
      image.mimeType = mime;
      image.uri.clear();
    }
    image.image.clear();
    image.as_is = false;
  }
  model.buffers.clear();
  return {};
}

// The original document with the clip as its only animation.
Result<Model> withNewAnimation(const GltfSource& source, const Skeleton& skeleton, const Clip& clip,
                               const std::string& file) {
  Result<Model> parsed =
      gltf::parseDocument(source.bytes, source.binary, source.directory,
                          file + " (the imported original)", gltf::ImageBytes::kKeepEncoded);
  if (!parsed.ok()) return parsed.status();
  Model& model = parsed.value();
  if (source.node_of_joint.size() != static_cast<size_t>(skeleton.jointCount())) {
    return Status::error(file + ": the skeleton has " + std::to_string(skeleton.jointCount()) +
                         " joints, the original glTF rig " +
                         std::to_string(source.node_of_joint.size()));
  }
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const int node = source.node_of_joint[j];
    if (node < 0 || node >= static_cast<int>(model.nodes.size())) {
      return Status::error(file + ": joint '" + skeleton.names[j] +
                           "' has no node in the original");
    }
    // Animated nodes must use TRS, not a matrix (glTF 2.0, 3.7.2.1); the rest values are the
    // matrix's decomposition.
    tinygltf::Node& target = model.nodes[node];
    // A name the reader had to clean or make (a control character, a NUL that cuts it short, not
    // UTF-8, none at all) is written as the joint's name, so the file reads back with the same
    // skeleton; a node with nothing else in it would otherwise be written as null.
    if (target.name.empty() || firstControlCharacter(target.name) >= 0 ||
        !isValidUtf8(target.name))
      target.name = skeleton.names[j];
    if (!target.matrix.empty()) {
      const glm::dvec3 t = gltf::translationToFile(source, j, skeleton.offsets[j]);
      const glm::dquat& r = skeleton.rest_rotations[j];
      const glm::dvec3 s = gltf::scaleToFile(source, j, skeleton.rest_scales[j]);
      target.matrix.clear();
      target.translation = {t.x, t.y, t.z};
      target.rotation = {r.x, r.y, r.z, r.w};
      target.scale = {s.x, s.y, s.z};
    }
  }
  // tinygltf writes an object with nothing in it as null, which no reader takes back (materials
  // and samplers it guards itself; joint nodes are named above). A scene whose nodes the reader
  // could not use (a key it did not know; found by fuzzing) and a bare texture get a name.
  for (tinygltf::Scene& scene : model.scenes)
    if (scene.name.empty() && scene.nodes.empty()) scene.name = "Scene";
  for (tinygltf::Texture& texture : model.textures)
    if (texture.name.empty() && texture.sampler < 0 && texture.source < 0) texture.name = "Texture";
  model.animations.clear();
  BufferBuilder buffer(model);
  if (Status status = repackBuffers(model, buffer, file); !status.ok()) return status;
  // The original's nodes hold the file's numbers (centimetres under no scale, or under an
  // armature's 0.01), so the animation is written in them too.
  addAnimation(model, buffer, gltf::clipToFile(clip, source), source.node_of_joint);
  buffer.finish();
  model.asset.generator = "Sinew";
  return parsed;
}

// A bone mesh in the bind pose: an elongated octahedron from each joint to each child (and End
// Site), rigidly bound to the joint; a small diamond marks a joint with no bone. Flat shaded,
// so three vertices per triangle.
struct BoneMesh {
  std::vector<float> positions;       // (vertices x 3) metres
  std::vector<float> normals;         // (vertices x 3)
  std::vector<std::uint16_t> joints;  // (vertices x 4)
  std::vector<float> weights;         // (vertices x 4)

  // Adds a triangle facing away from `inside`.
  void addTriangle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, const glm::dvec3& inside, int joint) {
    glm::dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
    if (glm::dot(normal, (a + b + c) / 3.0 - inside) < 0.0) {
      std::swap(b, c);
      normal = -normal;
    }
    for (const glm::dvec3& p : {a, b, c}) {
      pushVec(positions, p);
      pushVec(normals, normal);
      joints.insert(joints.end(), {static_cast<std::uint16_t>(joint), 0, 0, 0});
      weights.insert(weights.end(), {1.0f, 0.0f, 0.0f, 0.0f});
    }
  }

  // Eight faces around `centre`: tips at `tip0` and `tip1`, a square ring of `ring` points.
  void addOctahedron(const glm::dvec3& tip0, const glm::dvec3& tip1,
                     const std::array<glm::dvec3, 4>& ring, const glm::dvec3& centre, int joint) {
    for (int k = 0; k < 4; ++k) {
      addTriangle(tip0, ring[k], ring[(k + 1) % 4], centre, joint);
      addTriangle(tip1, ring[(k + 1) % 4], ring[k], centre, joint);
    }
  }
};

BoneMesh boneMesh(const Skeleton& skeleton, const Clip& clip,
                  const std::vector<glm::dmat4>& world) {
  BoneMesh mesh;
  const int count = skeleton.jointCount();
  glm::dvec3 low(std::numeric_limits<double>::max());
  glm::dvec3 high(std::numeric_limits<double>::lowest());
  for (const glm::dmat4& m : world) {
    low = glm::min(low, glm::dvec3(m[3]));
    high = glm::max(high, glm::dvec3(m[3]));
  }
  const double marker = std::max(0.01 * glm::length(high - low), 0.002);
  std::vector<char> drawn(count, 0);
  auto addBone = [&](int joint, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 d = b - a;
    const double length = glm::length(d);
    if (length < 1e-6) return;
    const glm::dvec3 axis = d / length;
    const glm::dvec3 helper = std::abs(axis.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(axis, helper)) * (0.1 * length);
    const glm::dvec3 v = glm::cross(axis, u);
    const glm::dvec3 mid = a + 0.15 * d;
    mesh.addOctahedron(a, b, {mid + u, mid + v, mid - u, mid - v}, mid, joint);
    drawn[joint] = 1;
  };
  // A bone is rigid on its parent joint, so it only shows the motion truly when the child stays
  // at its offset. A child that travels (a hips joint under a ground-level root) would leave a
  // long spike behind; such a child gets no bone from its parent.
  auto travels = [&](int j) {
    const double slack = 0.05 * glm::length(skeleton.offsets[j]) + 1e-4;
    for (int f = 0; f < clip.frame_count; ++f) {
      if (glm::length(clip.translation(f, j) - skeleton.offsets[j]) > slack) return true;
    }
    return false;
  };
  for (int j = 0; j < count; ++j) {
    const glm::dvec3 here(world[j][3]);
    const int parent = skeleton.parents[j];
    if (parent != kNoParent && !travels(j)) addBone(parent, glm::dvec3(world[parent][3]), here);
    if (skeleton.end_sites[j])
      addBone(j, here, glm::dvec3(world[j] * glm::dvec4(*skeleton.end_sites[j], 1.0)));
  }
  for (int j = 0; j < count; ++j) {
    if (drawn[j]) continue;
    const glm::dvec3 p(world[j][3]);
    const glm::dvec3 x(marker, 0, 0);
    const glm::dvec3 z(0, 0, marker);
    mesh.addOctahedron(p + glm::dvec3(0, marker, 0), p - glm::dvec3(0, marker, 0),
                       {p + x, p + z, p - x, p - z}, p, j);
  }
  return mesh;
}

// A new document: one node per joint, a skin in the rest pose, the bone mesh and a material.
Model newRig(const Skeleton& skeleton, const Clip& clip) {
  Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Sinew";
  BufferBuilder buffer(model);
  const int count = skeleton.jointCount();
  std::vector<int> node_of_joint(count);
  tinygltf::Scene scene;
  for (int j = 0; j < count; ++j) {
    tinygltf::Node node;
    node.name = skeleton.names[j];
    const glm::dvec3& t = skeleton.offsets[j];
    const glm::dquat r = glm::normalize(skeleton.rest_rotations[j]);
    const glm::dvec3& s = skeleton.rest_scales[j];
    node.translation = {t.x, t.y, t.z};
    if (r != glm::dquat(1.0, 0.0, 0.0, 0.0)) node.rotation = {r.x, r.y, r.z, r.w};
    if (s != glm::dvec3(1.0)) node.scale = {s.x, s.y, s.z};
    model.nodes.push_back(node);
    node_of_joint[j] = j;
    if (skeleton.parents[j] == kNoParent) {
      scene.nodes.push_back(j);
    } else {
      model.nodes[skeleton.parents[j]].children.push_back(j);
    }
  }

  const std::vector<glm::dmat4> world = restWorldTransforms(skeleton);
  std::vector<float> inverse_bind;
  for (const glm::dmat4& m : world) {
    glm::dmat4 inverse = glm::affineInverse(m);
    inverse[0][3] = inverse[1][3] = inverse[2][3] = 0.0;  // exactly affine, as the spec asks
    inverse[3][3] = 1.0;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) inverse_bind.push_back(static_cast<float>(inverse[c][r]));
    }
  }
  tinygltf::Skin skin;
  skin.name = "skeleton";
  skin.joints = node_of_joint;
  skin.inverseBindMatrices = buffer.addFloats(inverse_bind, TINYGLTF_TYPE_MAT4);
  if (scene.nodes.size() == 1) skin.skeleton = scene.nodes[0];
  model.skins.push_back(skin);

  const BoneMesh bones = boneMesh(skeleton, clip, world);
  const size_t vertices = bones.positions.size() / 3;
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.material = 0;
  primitive.attributes["POSITION"] =
      buffer.addFloats(bones.positions, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
  primitive.attributes["NORMAL"] =
      buffer.addFloats(bones.normals, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.attributes["JOINTS_0"] =
      buffer.addAccessor<std::uint16_t>(bones.joints, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                        TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER, false);
  primitive.attributes["WEIGHTS_0"] =
      buffer.addFloats(bones.weights, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  std::vector<std::uint32_t> indices(vertices);
  for (size_t v = 0; v < vertices; ++v) indices[v] = static_cast<std::uint32_t>(v);
  if (vertices <= 65535) {
    const std::vector<std::uint16_t> short_indices(indices.begin(), indices.end());
    primitive.indices = buffer.addAccessor<std::uint16_t>(
        short_indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
        TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
  } else {
    primitive.indices = buffer.addAccessor<std::uint32_t>(
        indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
        TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
  }
  tinygltf::Mesh mesh;
  mesh.name = "bones";
  mesh.primitives.push_back(primitive);
  model.meshes.push_back(mesh);

  tinygltf::Material material;
  material.name = "bone";
  material.pbrMetallicRoughness.baseColorFactor = {0.8, 0.8, 0.78, 1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.6;
  model.materials.push_back(material);

  // The skinned mesh node sits at the scene root: glTF ignores a skinned mesh node's own
  // transform, and validators warn when it has a parent.
  tinygltf::Node mesh_node;
  mesh_node.name = "bones";
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  model.nodes.push_back(mesh_node);
  scene.nodes.push_back(count);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  addAnimation(model, buffer, clip, node_of_joint);
  buffer.finish();
  return model;
}

// glTF key times are float32: frames whose times round to the same float (a long clip at a very
// high rate) would be read back as fewer frames, so such a clip is refused before writing.
// Validated clips keep every other value within float range (kMaxLength_m, kMaxScale).
Status floatTimesDistinct(const Clip& clip) {
  float previous = 0.0f;
  for (int f = 1; f < clip.frame_count; ++f) {
    const float t = static_cast<float>(f * clip.frame_time);
    if (!(t > previous)) {
      return Status::error("frames " + std::to_string(f - 1) + " and " + std::to_string(f) +
                           " fall on the same float32 key time (" + std::to_string(t) +
                           " s): too many frames at this rate for glTF");
    }
    previous = t;
  }
  return {};
}

}  // namespace

Status saveGltf(const std::filesystem::path& path, const MotionAsset& asset, const Clip& clip) {
  const std::string file = path.string();
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".glb" && ext != ".gltf") {
    return Status::error(file + ": expected a .glb or .gltf file name");
  }
  const bool binary = ext == ".glb";
  if (Status status = asset.skeleton.validate(); !status.ok()) {
    return Status::error(file + ": cannot export: " + status.message());
  }
  if (Status status = clip.validate(asset.skeleton); !status.ok()) {
    return Status::error(file + ": cannot export: " + status.message());
  }
  if (Status status = floatTimesDistinct(clip); !status.ok()) {
    return Status::error(file + ": cannot export: " + status.message());
  }
  std::string bytes;
  try {  // tinygltf or an allocation may throw; nothing escapes the engine
    Model model;
    if (asset.gltf) {
      Result<Model> rebuilt = withNewAnimation(*asset.gltf, asset.skeleton, clip, file);
      if (!rebuilt.ok()) return rebuilt.status();
      model = std::move(rebuilt).value();
    } else {
      model = newRig(asset.skeleton, clip);
    }
    tinygltf::TinyGLTF writer;
    writer.SetImageWriter(nullptr, nullptr);  // images are already encoded bytes in the buffer
    std::ostringstream out;
    if (!writer.WriteGltfSceneToStream(&model, out, !binary, binary)) {
      return Status::error(file + ": tinygltf could not serialise the document");
    }
    bytes = out.str();
  } catch (const std::exception& e) {
    return Status::error(file + ": cannot export: " + e.what());
  }
  return writeFileAtomically(path, bytes);
}

}  // namespace sinew::motion
