// Draws the viewport with OpenGL 3.3 core: the key light's shadow map first (capsules and skinned
// meshes cast), then shaded capsules (instanced, one per bone) and skinned meshes (GPU linear
// blend skinning, joint matrices in a float texture), the ground grid, the translucent model, and
// the skeleton over the mesh. Shaders are read at init from a folder; a missing or broken shader
// is an error value, and a renderer that failed to init draws nothing.
// Only the UI thread may call it (it owns the GL context).
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "editor/camera.h"
#include "editor/editor_state.h"
#include "editor/frame_stats.h"
#include "editor/gl.h"
#include "editor/scene.h"
#include "sinew/core/status.h"

namespace sinew::editor {

struct ViewportRect {  // framebuffer pixels, origin bottom-left (as glViewport)
  int x = 0, y = 0, width = 1, height = 1;
};

// Shadow-map texels across (16-bit depth: on llvmpipe, sampling a 24-bit map of this size cost
// three times as much). 1024 over a character's few metres is 2-3 mm per texel, finer than the
// screen's pixels at the usual framing; 2048 costs twice as much (see docs/editor.md).
inline constexpr int kShadowMapSize = 1024;

class Renderer {
 public:
  Renderer() = default;
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Compiles the shaders in `shader_dir` and creates the meshes. Needs a current GL context.
  Status init(const std::filesystem::path& shader_dir);
  bool ready() const { return ready_; }

  // Renders the shadow map, then clears `rect` and draws the scene into it (the grid when
  // `grid`). Uploads the scene's meshes the first time it shows them.
  void draw(const ViewportRect& rect, const OrbitCamera& camera, const Scene& scene, bool grid);

  // What the renderer has to say since the last call (meshes uploaded, materials it could not
  // use), for the Log.
  std::vector<LogLine> takeMessages();

  // While set (the benchmark), draw() finishes the GL work of the shadow pass and of the 3D view
  // (glFinish: llvmpipe rasterises when the work is flushed) and marks both stages in `profile`.
  void setProfile(StageProfile* profile) { profile_ = profile; }

 private:
  struct GpuMesh {
    GLuint vao = 0, vbo = 0, ebo = 0, texture = 0;
    GLsizei index_count = 0;
    glm::vec4 base_color{1.0f};
  };
  struct Light {
    glm::mat4 view_proj{1.0f};
    float texel = 0.0f;    // metres per shadow-map texel
    glm::vec3 ground[8];   // where shadows can fall on the ground (y = 0): a convex polygon,
    int ground_count = 0;  // its corners in order, metres
  };
  // The shader programs. Lit ones come twice, without and with shadows (see lighting.glsl).
  enum Program {
    kCapsule,
    kCapsuleShadowed,
    kSkinned,
    kSkinnedShadowed,
    kGrid,
    kShadowFloor,
    kCapsuleDepth,
    kSkinnedDepth,
    kProgramCount
  };

  void syncMeshes(const Scene& scene);
  void releaseMeshes();
  Light fitLight(const Scene& scene) const;
  void renderShadowMap(const Scene& scene, const Light& light);
  void drawView(const ViewportRect& rect, const OrbitCamera& camera, const Scene& scene, bool grid,
                bool shadows, const Light& light);
  void setLighting(GLuint program, const OrbitCamera& camera, const Light& light);
  void drawCapsules(GLuint program, std::span<const CapsuleInstance> capsules,
                    const glm::mat4& view_proj, bool translucent, int coarsest = 0);
  void drawSkinned(GLuint program, const Scene& scene, const glm::mat4& view_proj, bool shade);
  void release();

  bool ready_ = false;
  GLuint programs_[kProgramCount] = {};
  GLuint capsule_vao_ = 0;
  GLuint capsule_vbo_ = 0;
  GLuint capsule_ebo_ = 0;
  GLuint instance_vbo_ = 0;
  // Per level of detail (scene.h: fine, coarse, minimal), where its indices start in the index
  // buffer and how many there are.
  GLsizei capsule_first_[kCapsuleDetails] = {};
  GLsizei capsule_index_count_[kCapsuleDetails] = {};
  std::vector<CapsuleInstance> capsule_scratch_;  // the capsules drawn when not all fit
  GLuint grid_vao_ = 0;
  GLuint shadow_fbo_ = 0;
  GLuint shadow_texture_ = 0;    // DEPTH_COMPONENT16, kShadowMapSize squared, compare mode
  GLuint skinning_texture_ = 0;  // RGBA32F, 4 x joints: the current mesh's skinning matrices
  int skinning_rows_ = 0;        // its allocated height
  std::vector<GpuMesh> meshes_;  // (asset meshes) uploaded for meshes_source_
  std::shared_ptr<const motion::GltfSource> meshes_source_;  // whose meshes are uploaded
  const motion::MotionAsset* meshes_asset_ = nullptr;
  std::vector<LogLine> messages_;
  StageProfile* profile_ = nullptr;
};

}  // namespace sinew::editor
