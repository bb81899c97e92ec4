// What the viewport shows this frame, built from the editor state without touching OpenGL:
// one capsule per bone (joint to parent, and joint to End Site) for the original clip and for the
// reconstructed model, the original's skinned meshes (glTF) with their skinning matrices, what
// casts shadows, plus the bounds the camera frames and follows.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "editor/editor_state.h"

namespace sinew::editor {

struct CapsuleInstance {
  glm::vec3 a{0.0f};       // one end, metres, world
  float radius = 0.03f;    // metres
  glm::vec3 b{0.0f};       // other end, metres, world
  float pad = 0.0f;        // keeps the GPU layout 16-byte aligned
  glm::vec4 color{1.0f};   // linear RGB and opacity
};

// Drawing many capsules within a bounded cost (a 10,000-joint file took a minute for 30 frames on
// Mesa's software rasteriser, all in capsule triangles): each pass draws at most
// kCapsuleTriangleBudget triangles, with the finest of the capsule meshes (kCapsuleTriangles,
// fine to minimal) that fits, and beyond that only the largest capsules at the minimal mesh.
inline constexpr int kCapsuleDetails = 3;
inline constexpr size_t kCapsuleTriangles[kCapsuleDetails] = {520, 140, 36};
inline constexpr size_t kCapsuleTriangleBudget = 200000;
// The mesh (0 fine .. kCapsuleDetails - 1 minimal) for `count` capsules, `coarsest` or finer
// than it at least (the shadow pass starts one coarser).
int capsuleDetail(size_t count, int coarsest = 0);
// The capsules to draw: all of them when the budget allows, else the largest (length plus
// diameter) that fit at the minimal mesh, copied into `scratch`.
std::span<const CapsuleInstance> capsulesWithinBudget(std::span<const CapsuleInstance> capsules,
                                                      std::vector<CapsuleInstance>& scratch);

// One individual of the population as drawn: its index in the snapshot and the box around its
// capsules, for picking with the mouse.
struct PickBox {
  int individual = -1;
  glm::vec3 lo{0.0f}, hi{0.0f};
};

// One skinned mesh of the original, posed at the playback time.
struct SkinnedDraw {
  int mesh = 0;                     // into the asset's meshes
  std::vector<glm::mat4> skinning;  // (skeleton joints) bind pose -> world, metres, as drawn
};

struct Scene {
  std::vector<CapsuleInstance> opaque;       // the original clip (when drawn as capsules)
  std::vector<CapsuleInstance> translucent;  // the model, then the population: blended, after
  size_t translucent_casters = 0;            // the first N translucent capsules (the model) cast
                                             // shadows; the population's ghosts do not
  std::vector<CapsuleInstance> xray;         // the original's skeleton over its mesh: drawn
                                             // last, in front of everything, translucent
  const motion::MotionAsset* asset = nullptr;  // whose meshes `skinned` poses (the state's;
                                               // valid while the state keeps the asset)
  std::vector<SkinnedDraw> skinned;          // the original as its skinned meshes
  bool shadows = true;                       // the key light casts shadows (a view toggle)
  glm::vec3 bounds_min{0.0f};                // of everything drawn but the population, metres
  glm::vec3 bounds_max{0.0f};
  glm::vec3 root{0.0f};                      // the original's body root (the pelvis, pelvisJoint: a
                                             // massless root above it is not drawn), metres (follow target)
  bool empty = true;
  std::vector<PickBox> individuals;          // the population's runs drawn, best first
};

// The individual whose box the ray (from origin along unit direction) enters first, or -1.
int pickIndividual(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction);
// The scene at the state's playback time.
Scene buildScene(const EditorState& state);

}  // namespace sinew::editor
