#include "editor/materials.h"

#include <cstring>
#include <exception>

#include <tiny_gltf.h>

namespace sinew::editor {
namespace {

// Decodes with tinygltf's own loader (stb_image), but an image that does not decode is left
// empty instead of failing the whole document: the mesh is then drawn in its base colour.
bool decodeOrLeaveEmpty(tinygltf::Image* image, const int index, std::string* err,
                        std::string* warn, int req_width, int req_height,
                        const unsigned char* bytes, int size, void* /*user_data*/) {
  std::string ignored;
  if (!tinygltf::LoadImageData(image, index, &ignored, warn, req_width, req_height, bytes, size,
                               nullptr)) {
    image->width = image->height = 0;
    image->image.clear();
  }
  (void)err;
  return true;
}

// TEXCOORD_n as floats: float, or normalised unsigned byte/short, any byte stride. Sparse
// accessors are not read (the caller then draws the mesh untextured and says why).
Result<std::vector<glm::vec2>> readTexcoords(const tinygltf::Model& model, int index) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) {
    return Status::error("accessor " + std::to_string(index) + " does not exist");
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string where = "accessor " + std::to_string(index);
  if (accessor.type != TINYGLTF_TYPE_VEC2) return Status::error(where + " is not VEC2");
  if (accessor.sparse.isSparse) return Status::error(where + " is sparse");
  const int component = accessor.componentType;
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(component));
  if (component != TINYGLTF_COMPONENT_TYPE_FLOAT &&
      component != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      component != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    return Status::error(where + ": texture coordinates must be float, ubyte or ushort");
  }
  std::vector<glm::vec2> out(accessor.count, glm::vec2(0.0f));
  if (accessor.bufferView < 0) return out;  // all zeros, as the spec says
  if (accessor.bufferView >= static_cast<int>(model.bufferViews.size())) {
    return Status::error(where + ": buffer view " + std::to_string(accessor.bufferView) +
                         " does not exist");
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(accessor.bufferView)];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) {
    return Status::error(where + ": its buffer does not exist");
  }
  const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
  const int stride = accessor.ByteStride(view);
  if (stride <= 0) return Status::error(where + ": invalid byte stride");
  const size_t start = view.byteOffset + accessor.byteOffset;
  const size_t element = 2 * static_cast<size_t>(size);
  if (accessor.count > 0 && (view.byteOffset + view.byteLength > data.size() ||
                             start + (accessor.count - 1) * static_cast<size_t>(stride) + element >
                                 view.byteOffset + view.byteLength)) {
    return Status::error(where + " reaches past its buffer view");
  }
  for (size_t i = 0; i < accessor.count; ++i) {
    const unsigned char* p = data.data() + start + i * static_cast<size_t>(stride);
    for (int c = 0; c < 2; ++c) {
      const unsigned char* q = p + c * size;
      if (component == TINYGLTF_COMPONENT_TYPE_FLOAT) {
        float value = 0.0f;
        std::memcpy(&value, q, sizeof value);
        out[i][c] = value;
      } else if (component == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        out[i][c] = static_cast<float>(*q) / 255.0f;
      } else {
        std::uint16_t value = 0;
        std::memcpy(&value, q, sizeof value);
        out[i][c] = static_cast<float>(value) / 65535.0f;
      }
    }
  }
  return out;
}

// The material of one primitive. Texture problems are notes, never failures.
MeshMaterial materialOf(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                        size_t vertices) {
  MeshMaterial material;
  if (primitive.material < 0 || primitive.material >= static_cast<int>(model.materials.size())) {
    return material;
  }
  const tinygltf::PbrMetallicRoughness& pbr =
      model.materials[static_cast<size_t>(primitive.material)].pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() == 4) {
    for (int c = 0; c < 4; ++c) material.base_color[c] = static_cast<float>(pbr.baseColorFactor[c]);
  }
  const int texture = pbr.baseColorTexture.index;
  if (texture < 0) return material;
  if (texture >= static_cast<int>(model.textures.size())) {
    material.note = "base colour texture " + std::to_string(texture) + " does not exist";
    return material;
  }
  const int source = model.textures[static_cast<size_t>(texture)].source;
  if (source < 0 || source >= static_cast<int>(model.images.size())) {
    material.note = "texture " + std::to_string(texture) + " has no image";
    return material;
  }
  const tinygltf::Image& image = model.images[static_cast<size_t>(source)];
  const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  if (image.width <= 0 || image.height <= 0 || image.component < 1 || image.component > 4 ||
      (image.bits != 8 && image.bits != 16) ||
      image.image.size() < pixels * static_cast<size_t>(image.component * image.bits / 8)) {
    material.note = "image " + std::to_string(source) + " '" + image.name + image.uri +
                    "' could not be decoded";
    return material;
  }
  const std::string set = "TEXCOORD_" + std::to_string(pbr.baseColorTexture.texCoord);
  auto attribute = primitive.attributes.find(set);
  if (attribute == primitive.attributes.end()) {
    material.note = "the base colour texture uses " + set + ", which the mesh lacks";
    return material;
  }
  Result<std::vector<glm::vec2>> texcoords = readTexcoords(model, attribute->second);
  if (!texcoords.ok() || texcoords.value().size() != vertices) {
    material.note = set + ": " + (texcoords.ok() ? "wrong count" : texcoords.message());
    return material;
  }
  material.texcoords = std::move(texcoords).value();
  material.width = image.width;
  material.height = image.height;
  material.rgba.resize(pixels * 4);
  const int bytes = image.bits / 8;  // 16-bit images keep their high byte
  for (size_t i = 0; i < pixels; ++i) {
    std::uint8_t rgba[4] = {0, 0, 0, 255};
    for (int c = 0; c < image.component; ++c) {
      const size_t at = (i * static_cast<size_t>(image.component) + static_cast<size_t>(c)) *
                            static_cast<size_t>(bytes) +
                        static_cast<size_t>(bytes - 1);
      rgba[c] = image.image[at];
    }
    if (image.component <= 2) {  // grey (and alpha)
      rgba[3] = image.component == 2 ? rgba[1] : 255;
      rgba[1] = rgba[2] = rgba[0];
    }
    std::memcpy(&material.rgba[i * 4], rgba, 4);
  }
  return material;
}

}  // namespace

Result<std::vector<MeshMaterial>> readMaterials(const motion::MotionAsset& asset) {
  std::vector<MeshMaterial> materials(asset.meshes.size());
  if (!asset.gltf || asset.meshes.empty()) return materials;
  const motion::GltfSource& source = *asset.gltf;
  const std::string file = asset.path.string();
  tinygltf::Model model;
  try {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&decodeOrLeaveEmpty, nullptr);
    std::string err, warn;
    const auto length = static_cast<unsigned>(source.bytes.size());
    const bool parsed =
        source.binary
            ? loader.LoadBinaryFromMemory(
                  &model, &err, &warn, reinterpret_cast<const unsigned char*>(source.bytes.data()),
                  length, source.directory.string())
            : loader.LoadASCIIFromString(&model, &err, &warn, source.bytes.data(), length,
                                         source.directory.string());
    if (!parsed) return Status::error(file + ": materials: " + err);
  } catch (const std::exception& e) {
    return Status::error(file + ": materials: " + e.what());
  }
  // The engine's reader order: nodes in index order, those skinned by skin 0, their triangle
  // primitives with POSITION, JOINTS_0 and WEIGHTS_0.
  size_t next = 0;
  for (const tinygltf::Node& node : model.nodes) {
    if (node.mesh < 0 || node.mesh >= static_cast<int>(model.meshes.size()) || node.skin != 0) {
      continue;
    }
    for (const tinygltf::Primitive& primitive :
         model.meshes[static_cast<size_t>(node.mesh)].primitives) {
      const auto has = [&](const char* name) { return primitive.attributes.count(name) > 0; };
      if (primitive.mode != TINYGLTF_MODE_TRIANGLES || !has("POSITION") || !has("JOINTS_0") ||
          !has("WEIGHTS_0")) {
        continue;
      }
      if (next >= asset.meshes.size()) {
        return Status::error(file + ": materials: more skinned primitives than imported meshes");
      }
      const size_t vertices = asset.meshes[next].positions.size();
      const int position = primitive.attributes.at("POSITION");
      if (position < 0 || position >= static_cast<int>(model.accessors.size()) ||
          model.accessors[static_cast<size_t>(position)].count != vertices) {
        return Status::error(file + ": materials: primitive of mesh '" + asset.meshes[next].name +
                             "' does not match the imported mesh");
      }
      materials[next] = materialOf(model, primitive, vertices);
      ++next;
    }
  }
  if (next != asset.meshes.size()) {
    return Status::error(file + ": materials: found " + std::to_string(next) +
                         " skinned primitives for " + std::to_string(asset.meshes.size()) +
                         " imported meshes");
  }
  return materials;
}

}  // namespace sinew::editor
