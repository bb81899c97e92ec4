#include "editor/skinning.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace sinew::editor {

void skinningMatrices(const motion::SkinnedMesh& mesh, std::span<const glm::dmat4> joint_world,
                      std::span<glm::mat4> out) {
  const size_t joints = std::min({joint_world.size(), mesh.inverse_bind.size(), out.size()});
  for (size_t j = 0; j < joints; ++j) {
    out[j] = glm::mat4(joint_world[j] * mesh.inverse_bind[j]);
  }
}

glm::vec3 skinPoint(const motion::SkinnedMesh& mesh, std::span<const glm::mat4> skinning,
                    size_t v) {
  const glm::vec4 p(mesh.positions[v], 1.0f);
  glm::vec3 sum(0.0f);
  for (int k = 0; k < 4; ++k) {
    const float w = mesh.weights[v][k];
    if (w != 0.0f) sum += w * glm::vec3(skinning[mesh.joints[v][k]] * p);
  }
  return sum;
}

void growSkinnedBounds(const motion::SkinnedMesh& mesh, std::span<const glm::mat4> skinning,
                       size_t max_samples, glm::vec3& lo, glm::vec3& hi) {
  const size_t n = mesh.positions.size();
  if (n == 0 || max_samples == 0) return;
  const size_t step = std::max<size_t>(1, (n + max_samples - 1) / max_samples);
  for (size_t v = 0; v < n; v += step) {
    const glm::vec3 p = skinPoint(mesh, skinning, v);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
}

SkinGeometry buildSkinGeometry(const motion::SkinnedMesh& mesh,
                               std::span<const glm::vec2> texcoords) {
  SkinGeometry geometry;
  const bool textured = texcoords.size() == mesh.positions.size();
  auto vertex = [&](std::uint32_t v) {
    SkinVertex out;
    out.position = mesh.positions[v];
    if (!mesh.normals.empty()) out.normal = mesh.normals[v];
    if (textured) out.uv = texcoords[v];
    out.joints = mesh.joints[v];
    out.weights = mesh.weights[v];
    return out;
  };
  if (!mesh.normals.empty()) {
    geometry.vertices.reserve(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      geometry.vertices.push_back(vertex(static_cast<std::uint32_t>(v)));
    }
    geometry.indices = mesh.indices;
    return geometry;
  }
  // Flat: one vertex per triangle corner, the face normal on all three. A degenerate triangle
  // keeps the default normal (it covers no pixels anyway).
  geometry.flat = true;
  geometry.vertices.reserve(mesh.indices.size());
  geometry.indices.reserve(mesh.indices.size());
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    SkinVertex corners[3] = {vertex(mesh.indices[t]), vertex(mesh.indices[t + 1]),
                             vertex(mesh.indices[t + 2])};
    const glm::vec3 n = glm::cross(corners[1].position - corners[0].position,
                                   corners[2].position - corners[0].position);
    const float length = glm::length(n);
    for (SkinVertex& corner : corners) {
      if (length > 0.0f) corner.normal = n / length;
      geometry.indices.push_back(static_cast<std::uint32_t>(geometry.vertices.size()));
      geometry.vertices.push_back(corner);
    }
  }
  return geometry;
}

}  // namespace sinew::editor
