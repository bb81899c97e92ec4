// The glTF plumbing under the reader and writer: parsing a document with tinygltf, reading
// accessors safely, and a node's local transform. Internal to the engine.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <tiny_gltf.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

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

// An accessor's elements as doubles: normalized integers mapped to [0, 1] or [-1, 1] as the
// spec says, other integers as their values (exact in a double).
struct AccessorValues {
  int components = 0;                // numbers per element
  size_t count = 0;                  // elements
  std::vector<double> values;        // (count x components), matrices column by column
  glm::dvec4 vec4(size_t n) const {  // the first (up to) four numbers of element n
    glm::dvec4 v(0.0);
    for (int c = 0; c < components && c < 4; ++c) v[c] = values[n * components + c];
    return v;
  }
};

// Reads any accessor of the expected type (TINYGLTF_TYPE_*): byteStride, normalized integers,
// matrix column padding, a missing buffer view (zeros) and sparse substitution, every range
// checked. Messages start with "accessor N".
Result<AccessorValues> readAccessor(const tinygltf::Model& model, int index, int expected_type);

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
