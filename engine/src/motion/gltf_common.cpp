#include "gltf_common.h"

#include <cmath>
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

bool isGlb(std::string_view bytes) { return bytes.substr(0, 4) == "glTF"; }

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
    ok = binary ? loader.LoadBinaryFromMemory(
                      &model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
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
  for (Status status : {length(node.translation, 3, "translation"),
                        length(node.rotation, 4, "rotation"), length(node.scale, 3, "scale"),
                        length(node.matrix, 16, "matrix")}) {
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
