#include "editor/renderer.h"

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "sinew/core/file_io.h"

namespace sinew::editor {
namespace {

const glm::vec3 kBackground{0.105f, 0.112f, 0.125f};
const glm::vec3 kLightDir{0.45f, 0.80f, 0.40f};  // towards the light, world

Result<std::string> readShader(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    return Status::error(path.string() + ": shader file not found");
  }
  return readFile(path);
}

Result<GLuint> compile(GLenum stage, const std::filesystem::path& path) {
  Result<std::string> source = readShader(path);
  if (!source.ok()) return source.status();
  const GLuint shader = glCreateShader(stage);
  const char* text = source.value().c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_FALSE) {
    char info[1024] = {};
    glGetShaderInfoLog(shader, sizeof info, nullptr, info);
    glDeleteShader(shader);
    return Status::error(path.string() + ": does not compile: " + info);
  }
  return shader;
}

Result<GLuint> link(const std::filesystem::path& dir, const std::string& name) {
  Result<GLuint> vs = compile(GL_VERTEX_SHADER, dir / (name + ".vert"));
  if (!vs.ok()) return vs.status();
  Result<GLuint> fs = compile(GL_FRAGMENT_SHADER, dir / (name + ".frag"));
  if (!fs.ok()) {
    glDeleteShader(vs.value());
    return fs.status();
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs.value());
  glAttachShader(program, fs.value());
  glLinkProgram(program);
  glDeleteShader(vs.value());
  glDeleteShader(fs.value());
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == GL_FALSE) {
    char info[1024] = {};
    glGetProgramInfoLog(program, sizeof info, nullptr, info);
    glDeleteProgram(program);
    return Status::error((dir / name).string() + ": shaders do not link: " + info);
  }
  return program;
}

// A unit capsule: a sphere split at its equator. Each vertex is a unit direction (Y along the
// bone) and which end (0: a, 1: b) it belongs to; the vertex shader places it.
struct CapsuleVertex {
  glm::vec3 dir;
  float end;
};

void capsuleMesh(std::vector<CapsuleVertex>& vertices, std::vector<unsigned>& indices) {
  const int slices = 20;
  const int half_rings = 6;  // rings per hemisphere, pole excluded
  // Rings from the bottom pole (end 0) to the top pole (end 1); the equator appears twice.
  std::vector<std::pair<float, float>> rings;  // (latitude, end)
  for (int r = 0; r <= half_rings; ++r) rings.push_back({-1.5707963f * (1.0f - float(r) / half_rings), 0.0f});
  for (int r = 0; r <= half_rings; ++r) rings.push_back({1.5707963f * float(r) / half_rings, 1.0f});
  for (const auto& [lat, end] : rings) {
    for (int s = 0; s <= slices; ++s) {
      const float lon = 6.2831853f * float(s) / slices;
      vertices.push_back({glm::vec3(std::cos(lat) * std::cos(lon), std::sin(lat),
                                    std::cos(lat) * std::sin(lon)),
                          end});
    }
  }
  const unsigned row = slices + 1;
  for (unsigned r = 0; r + 1 < rings.size(); ++r) {
    for (unsigned s = 0; s < static_cast<unsigned>(slices); ++s) {
      const unsigned a = r * row + s, b = a + row;
      indices.insert(indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
}

void setVec3(GLuint program, const char* name, const glm::vec3& v) {
  glUniform3fv(glGetUniformLocation(program, name), 1, glm::value_ptr(v));
}
void setMat4(GLuint program, const char* name, const glm::mat4& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, glm::value_ptr(m));
}

}  // namespace

Renderer::~Renderer() { release(); }

void Renderer::release() {
  if (capsule_program_ != 0) glDeleteProgram(capsule_program_);
  if (grid_program_ != 0) glDeleteProgram(grid_program_);
  const GLuint buffers[] = {capsule_vbo_, capsule_ebo_, instance_vbo_};
  for (GLuint b : buffers)
    if (b != 0) glDeleteBuffers(1, &b);
  const GLuint arrays[] = {capsule_vao_, grid_vao_};
  for (GLuint a : arrays)
    if (a != 0) glDeleteVertexArrays(1, &a);
  capsule_program_ = grid_program_ = capsule_vbo_ = capsule_ebo_ = instance_vbo_ = 0;
  capsule_vao_ = grid_vao_ = 0;
  ready_ = false;
}

Status Renderer::init(const std::filesystem::path& shader_dir) {
  release();
  Result<GLuint> capsule = link(shader_dir, "capsule");
  if (!capsule.ok()) return capsule.status();
  capsule_program_ = capsule.value();
  Result<GLuint> grid = link(shader_dir, "grid");
  if (!grid.ok()) {
    release();
    return grid.status();
  }
  grid_program_ = grid.value();

  std::vector<CapsuleVertex> vertices;
  std::vector<unsigned> indices;
  capsuleMesh(vertices, indices);
  capsule_index_count_ = static_cast<GLsizei>(indices.size());
  glGenVertexArrays(1, &capsule_vao_);
  glBindVertexArray(capsule_vao_);
  glGenBuffers(1, &capsule_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, capsule_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(CapsuleVertex)),
               vertices.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(CapsuleVertex), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(CapsuleVertex),
                        reinterpret_cast<const void*>(offsetof(CapsuleVertex, end)));
  glGenBuffers(1, &capsule_ebo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, capsule_ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(unsigned)),
               indices.data(), GL_STATIC_DRAW);
  glGenBuffers(1, &instance_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
  const GLsizei stride = sizeof(CapsuleInstance);
  glEnableVertexAttribArray(2);  // a, radius
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(CapsuleInstance, a)));
  glEnableVertexAttribArray(3);  // b
  glVertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(CapsuleInstance, b)));
  glEnableVertexAttribArray(4);  // colour
  glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(offsetof(CapsuleInstance, color)));
  for (GLuint attribute = 2; attribute <= 4; ++attribute) glVertexAttribDivisor(attribute, 1);
  glBindVertexArray(0);

  glGenVertexArrays(1, &grid_vao_);  // the grid's quad comes from gl_VertexID
  ready_ = true;
  return {};
}

void Renderer::drawCapsules(std::span<const CapsuleInstance> capsules, const glm::mat4& view_proj,
                            const glm::vec3& eye, bool translucent) {
  if (capsules.empty()) return;
  glUseProgram(capsule_program_);
  setMat4(capsule_program_, "u_view_proj", view_proj);
  setVec3(capsule_program_, "u_eye", eye);
  setVec3(capsule_program_, "u_light_dir", glm::normalize(kLightDir));
  setVec3(capsule_program_, "u_background", kBackground);
  glBindVertexArray(capsule_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capsules.size_bytes()), capsules.data(),
               GL_STREAM_DRAW);
  const auto count = static_cast<GLsizei>(capsules.size());
  if (translucent) {
    // Depth first, then colour where the depth matches: one clean translucent surface.
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDrawElementsInstanced(GL_TRIANGLES, capsule_index_count_, GL_UNSIGNED_INT, nullptr, count);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDrawElementsInstanced(GL_TRIANGLES, capsule_index_count_, GL_UNSIGNED_INT, nullptr, count);
    glDisable(GL_BLEND);
    glDepthFunc(GL_LESS);
  } else {
    glDrawElementsInstanced(GL_TRIANGLES, capsule_index_count_, GL_UNSIGNED_INT, nullptr, count);
  }
  glBindVertexArray(0);
}

void Renderer::draw(const ViewportRect& rect, const OrbitCamera& camera, const Scene& scene,
                    bool grid) {
  glViewport(rect.x, rect.y, rect.width, rect.height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(rect.x, rect.y, rect.width, rect.height);
  glClearColor(kBackground.r, kBackground.g, kBackground.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (!ready_) {
    glDisable(GL_SCISSOR_TEST);
    return;
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  const glm::mat4 view_proj =
      camera.projection(float(rect.width) / float(std::max(rect.height, 1))) * camera.view();
  const glm::vec3 eye = camera.eye();

  drawCapsules(scene.opaque, view_proj, eye, false);
  if (grid) {
    glUseProgram(grid_program_);
    setMat4(grid_program_, "u_view_proj", view_proj);
    setVec3(grid_program_, "u_eye", eye);
    setVec3(grid_program_, "u_centre", glm::vec3(camera.target.x, 0.0f, camera.target.z));
    setVec3(grid_program_, "u_background", kBackground);
    glUniform1f(glGetUniformLocation(grid_program_, "u_extent"),
                std::max(30.0f, camera.distance * 12.0f));
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glBindVertexArray(grid_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glBindVertexArray(0);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  drawCapsules(scene.translucent, view_proj, eye, true);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace sinew::editor
