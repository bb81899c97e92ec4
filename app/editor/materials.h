// How each skinned mesh of a glTF asset looks: its material's base colour factor and, when it has
// one, the base colour texture (decoded) with the mesh's texture coordinates. The engine's import
// keeps neither (it never decodes pixels), so the editor reads them from the asset's original
// bytes, walking nodes and primitives in the same order as the engine's reader. No OpenGL here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/asset.h"

namespace sinew::editor {

struct MeshMaterial {
  glm::vec4 base_color{0.8f, 0.8f, 0.8f, 1.0f};  // glTF baseColorFactor (default white in glTF;
                                                 // 0.8 grey when the mesh has no material)
  std::vector<glm::vec2> texcoords;              // (mesh vertices) for the texture, or empty
  int width = 0;                                 // texture size, pixels; 0 when untextured
  int height = 0;
  std::vector<std::uint8_t> rgba;  // (height x width x 4) texture pixels, first row at the top
  std::string note;                // why a texture the file names is not used, or empty

  bool textured() const { return width > 0 && height > 0 && !texcoords.empty(); }
};

// One material per asset.meshes entry, in order. Fails (with the file's name) when the file's
// bytes no longer parse or its primitives do not match the imported meshes; an asset that did not
// come from glTF gets the default grey for every mesh.
Result<std::vector<MeshMaterial>> readMaterials(const motion::MotionAsset& asset);

}  // namespace sinew::editor
