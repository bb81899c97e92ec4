#include "gltf_common.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace sinew::motion::gltf {
namespace {

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;
}

bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  // Images stored in a buffer view stay there; only images behind a URI need their bytes kept.
  if (image->bufferView < 0 && bytes != nullptr && size > 0) {
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
  }
  return true;
}

// tinygltf's messages end in newlines and may span lines; users get one line.
std::string oneLine(const std::string& text) {
  std::string line;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!line.empty() && line.back() != ' ') line += "; ";
    } else {
      line += c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  return line;
}

bool finite(const std::vector<double>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

bool isGlb(std::string_view bytes) {
  return bytes.substr(0, 4) == "glTF";
}

Result<tinygltf::Model> parseDocument(std::string_view bytes, bool binary,
                                      const std::filesystem::path& directory,
                                      const std::string& label, ImageBytes images) {
  if (bytes.empty()) return Status::error(label + ": empty file, not a glTF document");
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) {
    return Status::error(label + ": larger than 4 GiB, which tinygltf cannot read");
  }
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(images == ImageBytes::kSkip ? &skipImage : &keepEncodedImage, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  bool ok = false;
  const auto size = static_cast<unsigned int>(bytes.size());
  try {  // tinygltf may throw (allocation, JSON type errors); nothing escapes the engine
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                              reinterpret_cast<const unsigned char*>(bytes.data()),
                                              size, directory.string())
                : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size,
                                             directory.string());
  } catch (const std::exception& e) {
    ok = false;
    err = e.what();
  }
  if (!ok) {
    const std::string reason = oneLine(err);
    return Status::error(label + ": not a valid glTF " + (binary ? "binary (.glb)" : "JSON") +
                         " file: " + (reason.empty() ? "tinygltf refused it" : reason));
  }
  return model;
}

// ---------------------------------------------------------------------------------------------
// Accessors

namespace {

// An accessor with no buffer view is all zeros plus sparse values; nothing bounds its count but
// this, so a hostile file cannot make us allocate gigabytes.
constexpr size_t kMaxUnbackedValues = size_t{1} << 24;

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
  }
  return "an unknown type";
}

int componentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
  }
  return 0;
}

// glTF data is little-endian, as is every machine Sinew builds for.
template <class T>
T load(const unsigned char* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

double readComponent(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double v = load<std::int8_t>(p);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const double v = load<std::uint8_t>(p);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double v = load<std::int16_t>(p);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const double v = load<std::uint16_t>(p);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return load<std::uint32_t>(p);
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load<float>(p);
  }
  return 0.0;
}

// Where an element's numbers sit: matrix columns start on 4-byte boundaries (spec 3.6.2.4).
struct ElementLayout {
  int columns = 1;
  int rows = 1;
  size_t column_stride = 0;
  size_t size = 0;  // bytes per element
};

ElementLayout elementLayout(int type, int component_size) {
  ElementLayout layout;
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      layout.rows = 1;
      break;
    case TINYGLTF_TYPE_VEC2:
      layout.rows = 2;
      break;
    case TINYGLTF_TYPE_VEC3:
      layout.rows = 3;
      break;
    case TINYGLTF_TYPE_VEC4:
      layout.rows = 4;
      break;
    case TINYGLTF_TYPE_MAT2:
      layout.columns = layout.rows = 2;
      break;
    case TINYGLTF_TYPE_MAT3:
      layout.columns = layout.rows = 3;
      break;
    case TINYGLTF_TYPE_MAT4:
      layout.columns = layout.rows = 4;
      break;
    default:
      return {};
  }
  layout.column_stride = static_cast<size_t>(layout.rows * component_size);
  if (layout.columns > 1) layout.column_stride = (layout.column_stride + 3) / 4 * 4;
  layout.size = layout.columns * layout.column_stride;
  return layout;
}

void readElement(const unsigned char* p, const ElementLayout& layout, int component_type,
                 bool normalized, double* out) {
  const int size = componentSize(component_type);
  for (int c = 0; c < layout.columns; ++c) {
    for (int r = 0; r < layout.rows; ++r) {
      *out++ = readComponent(p + c * layout.column_stride + r * size, component_type, normalized);
    }
  }
}

// The bytes [offset, offset + size) of a buffer view, checked against the view and its buffer;
// `what` names the data for the message ("12 elements need bytes 0 to 144 of buffer view 3").
Result<const unsigned char*> viewBytes(const tinygltf::Model& model, int view_index, size_t offset,
                                       size_t size, const std::string& what) {
  const std::string label = "buffer view " + std::to_string(view_index);
  if (view_index < 0 || view_index >= static_cast<int>(model.bufferViews.size())) {
    return Status::error(label + " does not exist");
  }
  const tinygltf::BufferView& view = model.bufferViews[view_index];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) {
    return Status::error(label + ": buffer " + std::to_string(view.buffer) + " does not exist");
  }
  const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
  if (view.byteLength > data.size() || view.byteOffset > data.size() - view.byteLength) {
    return Status::error(label + " (bytes " + std::to_string(view.byteOffset) + " + " +
                         std::to_string(view.byteLength) + ") runs past the end of buffer " +
                         std::to_string(view.buffer) + " (" + std::to_string(data.size()) +
                         " bytes)");
  }
  if (offset > view.byteLength || size > view.byteLength - offset) {
    return Status::error(what + " need bytes " + std::to_string(offset) + " to " +
                         std::to_string(offset + size) + " of " + label + ", which has " +
                         std::to_string(view.byteLength));
  }
  return data.data() + view.byteOffset + offset;
}

}  // namespace

Result<AccessorValues> readAccessor(const tinygltf::Model& model, int index, int expected_type) {
  const std::string label = "accessor " + std::to_string(index);
  auto fail = [&](const std::string& what) { return Status::error(label + ": " + what); };
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) {
    return Status::error(label + " does not exist (the file has " +
                         std::to_string(model.accessors.size()) + ")");
  }
  const tinygltf::Accessor& accessor = model.accessors[index];
  if (accessor.type != expected_type) {
    return fail(std::string("is ") + typeName(accessor.type) + ", expected " +
                typeName(expected_type));
  }
  const int size = componentSize(accessor.componentType);
  if (size == 0) return fail("unknown component type " + std::to_string(accessor.componentType));
  const ElementLayout layout = elementLayout(accessor.type, size);
  AccessorValues out;
  out.components = layout.columns * layout.rows;
  out.count = accessor.count;
  if (accessor.count == 0) return out;

  if (accessor.bufferView >= 0) {
    const tinygltf::BufferView* view =
        accessor.bufferView < static_cast<int>(model.bufferViews.size())
            ? &model.bufferViews[accessor.bufferView]
            : nullptr;
    if (view == nullptr)
      return fail("buffer view " + std::to_string(accessor.bufferView) + " does not exist");
    const size_t stride = view->byteStride != 0 ? view->byteStride : layout.size;
    if (stride < layout.size || stride > 252) {
      return fail("byte stride " + std::to_string(stride) + " does not fit elements of " +
                  std::to_string(layout.size) + " bytes");
    }
    if (accessor.count > view->byteLength) {  // also keeps the product below from overflowing
      return fail("count " + std::to_string(accessor.count) + " exceeds buffer view " +
                  std::to_string(accessor.bufferView) + " (" + std::to_string(view->byteLength) +
                  " bytes)");
    }
    Result<const unsigned char*> bytes =
        viewBytes(model, accessor.bufferView, accessor.byteOffset,
                  (accessor.count - 1) * stride + layout.size,
                  "count " + std::to_string(accessor.count) + ": the elements");
    if (!bytes.ok()) return fail(bytes.message());
    out.values.resize(accessor.count * out.components);
    for (size_t n = 0; n < accessor.count; ++n) {
      readElement(bytes.value() + n * stride, layout, accessor.componentType, accessor.normalized,
                  &out.values[n * out.components]);
    }
  } else {
    if (accessor.count * out.components > kMaxUnbackedValues) {
      return fail("count " + std::to_string(accessor.count) +
                  " without a buffer view is too large");
    }
    out.values.assign(accessor.count * out.components, 0.0);
  }

  if (accessor.sparse.isSparse) {
    const auto& sparse = accessor.sparse;
    const int index_size = componentSize(sparse.indices.componentType);
    if (sparse.count <= 0 || static_cast<size_t>(sparse.count) > accessor.count) {
      return fail("sparse count " + std::to_string(sparse.count) + " is not in 1.." +
                  std::to_string(accessor.count));
    }
    const int index_type = sparse.indices.componentType;
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
      return fail("sparse index component type " + std::to_string(index_type) +
                  " is not an unsigned integer type");
    }
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
      return fail("sparse byte offsets are negative");
    }
    const auto count = static_cast<size_t>(sparse.count);
    Result<const unsigned char*> indices =
        viewBytes(model, sparse.indices.bufferView, static_cast<size_t>(sparse.indices.byteOffset),
                  count * index_size, "the sparse indices");
    if (!indices.ok()) return fail(indices.message());
    Result<const unsigned char*> values =
        viewBytes(model, sparse.values.bufferView, static_cast<size_t>(sparse.values.byteOffset),
                  count * layout.size, "the sparse values");
    if (!values.ok()) return fail(values.message());
    for (size_t k = 0; k < count; ++k) {
      const double target =
          readComponent(indices.value() + k * index_size, sparse.indices.componentType, false);
      if (target >= static_cast<double>(accessor.count)) {
        return fail("sparse index " + std::to_string(static_cast<size_t>(target)) +
                    " is past the accessor's " + std::to_string(accessor.count) + " elements");
      }
      readElement(values.value() + k * layout.size, layout, accessor.componentType,
                  accessor.normalized, &out.values[static_cast<size_t>(target) * out.components]);
    }
  }
  for (double v : out.values) {
    if (!std::isfinite(v)) return fail("holds a number that is not finite");
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Node transforms

glm::dmat4 Trs::matrix() const {
  return glm::translate(glm::dmat4(1.0), translation) * glm::mat4_cast(rotation) *
         glm::scale(glm::dmat4(1.0), scale);
}

Result<Trs> nodeTrs(const tinygltf::Node& node, int index, bool* sheared) {
  const std::string label = "node " + std::to_string(index);
  auto length = [&](const std::vector<double>& values, size_t expected,
                    const char* name) -> Status {
    if (!values.empty() && values.size() != expected) {
      return Status::error(label + ": " + name + " has " + std::to_string(values.size()) +
                           " numbers, expected " + std::to_string(expected));
    }
    if (!finite(values)) return Status::error(label + ": " + name + " is not finite");
    return {};
  };
  for (Status status :
       {length(node.translation, 3, "translation"), length(node.rotation, 4, "rotation"),
        length(node.scale, 3, "scale"), length(node.matrix, 16, "matrix")}) {
    if (!status.ok()) return status;
  }
  *sheared = false;
  Trs trs;
  if (!node.matrix.empty()) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[static_cast<size_t>(c * 4 + r)];
    }
    trs.translation = glm::dvec3(m[3]);
    glm::dmat3 basis(m);
    trs.scale = {glm::length(basis[0]), glm::length(basis[1]), glm::length(basis[2])};
    if (glm::determinant(basis) < 0.0) trs.scale.x = -trs.scale.x;  // a mirror: flip one axis
    if (std::abs(trs.scale.x) > 1e-12 && std::abs(trs.scale.y) > 1e-12 &&
        std::abs(trs.scale.z) > 1e-12) {
      for (int c = 0; c < 3; ++c) basis[c] /= trs.scale[c];
      trs.rotation = glm::normalize(glm::quat_cast(basis));
    }
    const glm::dmat4 back = trs.matrix();
    double worst = 0.0;
    double largest = 1.0;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        worst = std::max(worst, std::abs(back[c][r] - m[c][r]));
        largest = std::max(largest, std::abs(m[c][r]));
      }
    }
    *sheared = worst > 1e-6 * largest;
    return trs;
  }
  if (!node.translation.empty()) {
    trs.translation = {node.translation[0], node.translation[1], node.translation[2]};
  }
  if (!node.rotation.empty()) {
    // glTF stores x, y, z, w; glm's constructor takes w first.
    const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    if (!(glm::length(q) > 1e-12)) return Status::error(label + ": rotation is a zero quaternion");
    trs.rotation = glm::normalize(q);
  }
  if (!node.scale.empty()) trs.scale = {node.scale[0], node.scale[1], node.scale[2]};
  return trs;
}

}  // namespace sinew::motion::gltf
