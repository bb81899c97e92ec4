// What the viewport shows this frame, built from the editor state without touching OpenGL:
// one capsule per bone (joint to parent, and joint to End Site) for the original clip and for the
// reconstructed model, plus the bounds the camera frames and follows.
#pragma once

#include <vector>

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

// One individual of the population as drawn: its index in the snapshot and the box around its
// capsules, for picking with the mouse.
struct PickBox {
  int individual = -1;
  glm::vec3 lo{0.0f}, hi{0.0f};
};

struct Scene {
  std::vector<CapsuleInstance> opaque;       // the original clip
  std::vector<CapsuleInstance> translucent;  // the model, drawn after, blended
  glm::vec3 bounds_min{0.0f};                // of everything drawn, metres
  glm::vec3 bounds_max{0.0f};
  glm::vec3 root{0.0f};                      // the original's root joint, metres (follow target)
  bool empty = true;
  std::vector<PickBox> individuals;          // the population's runs drawn, best first
};

// The individual whose box the ray (from origin along unit direction) enters first, or -1.
int pickIndividual(const Scene& scene, const glm::vec3& origin, const glm::vec3& direction);

// The scene at the state's playback time.
Scene buildScene(const EditorState& state);

}  // namespace sinew::editor
