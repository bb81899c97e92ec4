// What the glTF reader and writer share: parsing a document with tinygltf, and a node's local
// transform. Internal to the engine.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <tiny_gltf.h>

#include "sinew/core/status.h"

namespace sinew::motion::gltf {

// What happens to image files while parsing. Import never looks at pixels, so decoding them
// would only cost time; export writes images back, and must write the original encoded bytes
// (re-encoding a JPEG loses quality), so it keeps them in Image::image with Image::as_is set.
enum class ImageBytes { kSkip, kKeepEncoded };

// True when `bytes` start with the GLB magic "glTF".
bool isGlb(std::string_view bytes);

// Parses a .glb (binary) or .gltf (JSON) document held in memory; `directory` is where external
// buffers and images are looked up. Errors are "<label>: <tinygltf's message>".
Result<tinygltf::Model> parseDocument(std::string_view bytes, bool binary,
                                      const std::filesystem::path& directory,
                                      const std::string& label, ImageBytes images);

// A node's local transform as translation, rotation and scale (glTF applies T * R * S).
struct Trs {
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};

  glm::dmat4 matrix() const;
};

// The node's TRS; a `matrix` is decomposed (shear, which TRS cannot hold, is dropped and
// reported through `sheared`). Fails on wrong array lengths or non-finite numbers, naming the
// node ("node 4: rotation has 3 numbers, expected 4").
Result<Trs> nodeTrs(const tinygltf::Node& node, int index, bool* sheared);

}  // namespace sinew::motion::gltf
