// Linear blend skinning, CPU side: the matrices the skinned-mesh vertex shader blends, the same
// blend for one vertex (for bounds and tests), and the vertex layout the GPU draws. No OpenGL, so
// all of it is tested without a window.
//
// glTF's rule (spec 2.0, "Skins"): a skinned vertex is placed by its joints alone,
//   world = sum_k weight_k * world(joint_k) * inverse_bind(joint_k) * position,
// and the transform of the node holding the mesh is ignored: the inverse bind matrices already
// take the mesh's own space to each joint's space. So in the bind pose the blend gives
// mesh_to_world * position, the mesh where the file puts it (checked on Fox and RiggedFigure,
// whose mesh node carries a Z-up -> Y-up rotation).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "sinew/motion/asset.h"

namespace sinew::editor {

// Writes, per skeleton joint, joint_world[j] * mesh.inverse_bind[j]: a bind-pose vertex to the
// world, metres (the importer made the rig metres: glTF units by anatomy, gltf_units.h).
// `joint_world`: (joints) the pose's world transforms. `out`: (joints).
// Precondition: joint_world.size() == out.size() == mesh.inverse_bind.size().
void skinningMatrices(const motion::SkinnedMesh& mesh, std::span<const glm::dmat4> joint_world,
                      std::span<glm::mat4> out);

// The blended position of vertex `v` under `skinning` (from skinningMatrices), as the vertex
// shader computes it.
glm::vec3 skinPoint(const motion::SkinnedMesh& mesh, std::span<const glm::mat4> skinning, size_t v);

// Grows [lo, hi] by the skinned mesh, sampling at most `max_samples` vertices (evenly spread:
// for framing and the shadow's extent an exact box is not needed on big meshes).
void growSkinnedBounds(const motion::SkinnedMesh& mesh, std::span<const glm::mat4> skinning,
                       size_t max_samples, glm::vec3& lo, glm::vec3& hi);

// One vertex as the GPU reads it (56 bytes, tightly packed).
struct SkinVertex {
  glm::vec3 position{0.0f};                   // bind pose, metres
  glm::vec3 normal{0.0f, 1.0f, 0.0f};         // bind pose, unit
  glm::vec2 uv{0.0f};                         // base colour texture coordinates (0 when untextured)
  glm::u16vec4 joints{0};                     // skeleton joint indices
  glm::vec4 weights{1.0f, 0.0f, 0.0f, 0.0f};  // summing to 1
};

struct SkinGeometry {
  std::vector<SkinVertex> vertices;
  std::vector<std::uint32_t> indices;  // (3 x triangles)
  bool flat = false;  // the file had no normals: faces were split and given their own normal
};

// The mesh as GPU vertices. `texcoords`: (mesh vertices) or empty. A mesh without normals is
// flat shaded, as glTF asks: every triangle gets its own three vertices and its face normal.
SkinGeometry buildSkinGeometry(const motion::SkinnedMesh& mesh,
                               std::span<const glm::vec2> texcoords);

}  // namespace sinew::editor
