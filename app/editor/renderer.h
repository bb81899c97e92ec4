// Draws the viewport with OpenGL 3.3 core: shaded capsules (instanced, one per bone), the
// translucent model after them, and a ground grid. Shaders are read at init from a folder;
// a missing or broken shader is an error value, and a renderer that failed to init draws nothing.
// Only the UI thread may call it (it owns the GL context).
#pragma once

#include <filesystem>
#include <span>

#include <glm/mat4x4.hpp>

#include "editor/camera.h"
#include "editor/gl.h"
#include "editor/scene.h"
#include "sinew/core/status.h"

namespace sinew::editor {

struct ViewportRect {  // framebuffer pixels, origin bottom-left (as glViewport)
  int x = 0, y = 0, width = 1, height = 1;
};

class Renderer {
 public:
  Renderer() = default;
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Compiles the shaders in `shader_dir` and creates the meshes. Needs a current GL context.
  Status init(const std::filesystem::path& shader_dir);
  bool ready() const { return ready_; }

  // Clears `rect` and draws the scene into it.
  void draw(const ViewportRect& rect, const OrbitCamera& camera, const Scene& scene, bool grid);

 private:
  void drawCapsules(std::span<const CapsuleInstance> capsules, const glm::mat4& view_proj,
                    const glm::vec3& eye, bool translucent);
  void release();

  bool ready_ = false;
  GLuint capsule_program_ = 0;
  GLuint grid_program_ = 0;
  GLuint capsule_vao_ = 0;
  GLuint capsule_vbo_ = 0;
  GLuint capsule_ebo_ = 0;
  GLuint instance_vbo_ = 0;
  GLsizei capsule_index_count_ = 0;
  GLuint grid_vao_ = 0;
};

}  // namespace sinew::editor
