#include "editor/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "editor/materials.h"
#include "editor/skinning.h"
#include "sinew/core/file_io.h"

namespace sinew::editor {
namespace {

const glm::vec3 kBackground{0.105f, 0.112f, 0.125f};
// Towards the key light, world: high (52 degrees) and from the right of the default camera, so
// that characters are lit on the side the camera sees and their shadows fall visibly to the left.
const glm::vec3 kLightDir{0.62f, 0.80f, 0.00f};

// The population's ghosts are drawn with the coarse capsule (140 triangles, not 520): 16 of them
// at the fine one took 316 ms a frame on llvmpipe, at the coarse one 228 ms (docs/editor.md).
constexpr int kPopulationDetail = 1;

// Texture units: the base colour texture, the shadow map, the skinning matrices.
constexpr GLint kBaseTextureUnit = 0;
constexpr GLint kShadowUnit = 1;
constexpr GLint kSkinningUnit = 2;
const float kFloorShadowStrength = 0.6f;  // a full shadow keeps 40% of the floor's brightness

static_assert(sizeof(SkinVertex) == 56, "SkinVertex is read by the GPU as 56 packed bytes");
static_assert(sizeof(glm::mat4) == 16 * sizeof(float), "skinning rows are 16 packed floats");

Result<std::string> readShader(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    return Status::error(path.string() + ": shader file not found");
  }
  return readFile(path);
}

// The shader's text with each line `#include "NAME"` replaced by the file NAME from the same
// folder (one level; GLSL 3.30 has no include). #line directives keep the compiler's line
// numbers right: source 0 is the shader's own file, source 1 the included one.
Result<std::string> expandIncludes(const std::filesystem::path& path, const std::string& text) {
  std::istringstream in(text);
  std::string out, line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string directive = "#include \"";
    if (line.rfind(directive, 0) == 0 && line.size() > directive.size() + 1 && line.back() == '"') {
      const std::string name = line.substr(directive.size(), line.size() - directive.size() - 1);
      Result<std::string> included = readShader(path.parent_path() / name);
      if (!included.ok()) {
        return Status::error(path.string() + ":" + std::to_string(number) + ": " +
                             included.message());
      }
      out += "#line 1 1\n" + included.value() + "\n#line " + std::to_string(number + 1) + " 0\n";
    } else {
      out += line + '\n';
    }
  }
  return out;
}

// Compiles one stage with SINEW_SHADOWS defined as 0 or 1 (after the #version line, which GLSL
// wants first).
Result<GLuint> compile(GLenum stage, const std::filesystem::path& path, bool shadows) {
  Result<std::string> file = readShader(path);
  if (!file.ok()) return file.status();
  Result<std::string> source = expandIncludes(path, file.value());
  if (!source.ok()) return source.status();
  const size_t first_line = source.value().find('\n');
  if (first_line != std::string::npos) {
    source.value().insert(first_line + 1, std::string("#define SINEW_SHADOWS ") +
                                              (shadows ? "1" : "0") + "\n#line 2 0\n");
  }
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

// Links `vertex`.vert with `fragment`.frag from `dir`.
Result<GLuint> link(const std::filesystem::path& dir, const std::string& vertex,
                    const std::string& fragment, bool shadows) {
  Result<GLuint> vs = compile(GL_VERTEX_SHADER, dir / (vertex + ".vert"), shadows);
  if (!vs.ok()) return vs.status();
  Result<GLuint> fs = compile(GL_FRAGMENT_SHADER, dir / (fragment + ".frag"), shadows);
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
    return Status::error((dir / vertex).string() + ".vert + " + fragment +
                         ".frag: shaders do not link: " + info);
  }
  return program;
}

// A unit capsule: a sphere split at its equator. Each vertex is a unit direction (Y along the
// bone) and which end (0: a, 1: b) it belongs to; the vertex shader places it.
struct CapsuleVertex {
  glm::vec3 dir;
  float end;
};

// Appends a capsule of `slices` around and `half_rings` per hemisphere (pole excluded); its
// indices count from the vertices already there.
void capsuleMesh(int slices, int half_rings, std::vector<CapsuleVertex>& vertices,
                 std::vector<unsigned>& indices) {
  const auto base = static_cast<unsigned>(vertices.size());
  // Rings from the bottom pole (end 0) to the top pole (end 1); the equator appears twice.
  std::vector<std::pair<float, float>> rings;  // (latitude, end)
  for (int r = 0; r <= half_rings; ++r)
    rings.push_back({-1.5707963f * (1.0f - float(r) / half_rings), 0.0f});
  for (int r = 0; r <= half_rings; ++r) rings.push_back({1.5707963f * float(r) / half_rings, 1.0f});
  for (const auto& [lat, end] : rings) {
    for (int s = 0; s <= slices; ++s) {
      const float lon = 6.2831853f * float(s) / slices;
      vertices.push_back(
          {glm::vec3(std::cos(lat) * std::cos(lon), std::sin(lat), std::cos(lat) * std::sin(lon)),
           end});
    }
  }
  const unsigned row = slices + 1;
  for (unsigned r = 0; r + 1 < rings.size(); ++r) {
    for (unsigned s = 0; s < static_cast<unsigned>(slices); ++s) {
      const unsigned a = base + r * row + s, b = a + row;
      indices.insert(indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
}

void setVec3(GLuint program, const char* name, const glm::vec3& v) {
  glUniform3fv(glGetUniformLocation(program, name), 1, glm::value_ptr(v));
}
void setVec4(GLuint program, const char* name, const glm::vec4& v) {
  glUniform4fv(glGetUniformLocation(program, name), 1, glm::value_ptr(v));
}
void setMat4(GLuint program, const char* name, const glm::mat4& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, glm::value_ptr(m));
}
void setFloat(GLuint program, const char* name, float value) {
  glUniform1f(glGetUniformLocation(program, name), value);
}
void setInt(GLuint program, const char* name, GLint value) {
  glUniform1i(glGetUniformLocation(program, name), value);
}

// The convex hull of `points`, counter-clockwise seen from above (Andrew's monotone chain; at
// most as many points as given, collinear ones dropped).
std::vector<glm::vec2> convexHull(std::vector<glm::vec2> points) {
  std::sort(points.begin(), points.end(), [](const glm::vec2& a, const glm::vec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  if (points.size() < 3) return points;
  auto turn = [](const glm::vec2& o, const glm::vec2& a, const glm::vec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::vec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {  // lower chain
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0f) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0f) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);  // the last point is the first again
  return hull;
}

// "1,728": counts in messages, as the docs write them.
std::string thousands(size_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace

Renderer::~Renderer() {
  release();
}

void Renderer::releaseMeshes() {
  for (GpuMesh& mesh : meshes_) {
    if (mesh.vbo != 0) glDeleteBuffers(1, &mesh.vbo);
    if (mesh.ebo != 0) glDeleteBuffers(1, &mesh.ebo);
    if (mesh.vao != 0) glDeleteVertexArrays(1, &mesh.vao);
    if (mesh.texture != 0) glDeleteTextures(1, &mesh.texture);
  }
  meshes_.clear();
  meshes_source_.reset();
  meshes_asset_ = nullptr;
}

void Renderer::release() {
  releaseMeshes();
  for (GLuint& program : programs_) {
    if (program != 0) glDeleteProgram(program);
    program = 0;
  }
  const GLuint buffers[] = {capsule_vbo_, capsule_ebo_, instance_vbo_};
  for (GLuint b : buffers)
    if (b != 0) glDeleteBuffers(1, &b);
  const GLuint arrays[] = {capsule_vao_, grid_vao_};
  for (GLuint a : arrays)
    if (a != 0) glDeleteVertexArrays(1, &a);
  const GLuint textures[] = {shadow_texture_, skinning_texture_};
  for (GLuint t : textures)
    if (t != 0) glDeleteTextures(1, &t);
  if (shadow_fbo_ != 0) glDeleteFramebuffers(1, &shadow_fbo_);

  capsule_vbo_ = capsule_ebo_ = instance_vbo_ = 0;
  capsule_vao_ = grid_vao_ = 0;
  shadow_texture_ = skinning_texture_ = shadow_fbo_ = 0;
  skinning_rows_ = 0;
  ready_ = false;
}

Status Renderer::init(const std::filesystem::path& shader_dir) {
  release();
  struct ProgramSpec {
    Program program;
    const char* vertex;
    const char* fragment;
    bool shadows;
  };
  const ProgramSpec programs[] = {
      {kCapsule, "capsule", "capsule", false},
      {kCapsuleShadowed, "capsule", "capsule", true},
      {kSkinned, "skinned", "skinned", false},
      {kSkinnedShadowed, "skinned", "skinned", true},
      {kGrid, "grid", "grid", false},
      {kShadowFloor, "shadow_floor", "shadow_floor", true},
      {kCapsuleDepth, "capsule", "depth", false},
      {kSkinnedDepth, "skinned", "depth", false},
  };
  for (const ProgramSpec& spec : programs) {
    Result<GLuint> program = link(shader_dir, spec.vertex, spec.fragment, spec.shadows);
    if (!program.ok()) {
      release();
      return program.status();
    }
    programs_[spec.program] = program.value();
  }

  // The capsule as drawn (520 triangles), a coarse one (140) for the shadow map and for many
  // capsules, and a minimal one (36) for very many (scene.h's budget): the driver bins every
  // triangle on the UI thread, and a shadow needs no smooth outline. The coarser capsules lie
  // inside the fine one, so they never shadow the surface they stand for.
  std::vector<CapsuleVertex> vertices;
  std::vector<unsigned> indices;
  const int detail_mesh[kCapsuleDetails][2] = {{20, 6}, {10, 3}, {6, 1}};
  for (int d = 0; d < kCapsuleDetails; ++d) {
    capsule_first_[d] = static_cast<GLsizei>(indices.size());
    capsuleMesh(detail_mesh[d][0], detail_mesh[d][1], vertices, indices);
    capsule_index_count_[d] = static_cast<GLsizei>(indices.size()) - capsule_first_[d];
  }
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

  // The shadow map: depth only, compared in the sampler (LINEAR gives 2x2 filtered comparisons).
  glGenTextures(1, &shadow_texture_);
  glBindTexture(GL_TEXTURE_2D, shadow_texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT16, kShadowMapSize, kShadowMapSize, 0,
               GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glBindTexture(GL_TEXTURE_2D, 0);
  glGenFramebuffers(1, &shadow_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_texture_, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  const GLenum complete = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (complete != GL_FRAMEBUFFER_COMPLETE) {
    release();
    char code[32];
    std::snprintf(code, sizeof code, "0x%04x", complete);
    return Status::error(std::string("the shadow map's framebuffer is incomplete (status ") + code +
                         ")");
  }
  glGenTextures(1, &skinning_texture_);
  glBindTexture(GL_TEXTURE_2D, skinning_texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  ready_ = true;
  return {};
}

std::vector<LogLine> Renderer::takeMessages() {
  std::vector<LogLine> out;
  out.swap(messages_);
  return out;
}

// Uploads the asset's meshes (and their materials) when the scene shows another asset's.
void Renderer::syncMeshes(const Scene& scene) {
  if (scene.asset == nullptr) return;
  const motion::MotionAsset& asset = *scene.asset;
  if (&asset == meshes_asset_ && asset.gltf == meshes_source_) return;
  releaseMeshes();
  meshes_asset_ = &asset;
  meshes_source_ = asset.gltf;
  const std::string file = asset.path.filename().string();
  Result<std::vector<MeshMaterial>> read = readMaterials(asset);
  std::vector<MeshMaterial> materials(asset.meshes.size());
  if (read.ok()) {
    materials = std::move(read).value();
  } else {
    messages_.push_back({LogLevel::kWarning, 0.0, read.message() + "; the meshes are drawn grey"});
  }
  size_t vertex_total = 0, triangle_total = 0, textured = 0, flat = 0;
  for (size_t m = 0; m < asset.meshes.size(); ++m) {
    const MeshMaterial& material = materials[m];
    if (!material.note.empty()) {
      messages_.push_back({LogLevel::kWarning, 0.0,
                           file + ": mesh '" + asset.meshes[m].name + "': " + material.note +
                               "; drawn in its base colour"});
    }
    const SkinGeometry geometry = buildSkinGeometry(asset.meshes[m], material.texcoords);
    vertex_total += asset.meshes[m].positions.size();
    triangle_total += geometry.indices.size() / 3;
    flat += geometry.flat ? 1 : 0;
    GpuMesh gpu;
    gpu.base_color = material.base_color;
    gpu.index_count = static_cast<GLsizei>(geometry.indices.size());
    glGenVertexArrays(1, &gpu.vao);
    glBindVertexArray(gpu.vao);
    glGenBuffers(1, &gpu.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, gpu.vbo);
    glBufferData(GL_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(geometry.vertices.size() * sizeof(SkinVertex)),
                 geometry.vertices.data(), GL_STATIC_DRAW);
    const GLsizei stride = sizeof(SkinVertex);
    auto offset = [](size_t bytes) { return reinterpret_cast<const void*>(bytes); };
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, offset(offsetof(SkinVertex, position)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, offset(offsetof(SkinVertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, offset(offsetof(SkinVertex, uv)));
    glEnableVertexAttribArray(3);
    glVertexAttribIPointer(3, 4, GL_UNSIGNED_SHORT, stride, offset(offsetof(SkinVertex, joints)));
    glEnableVertexAttribArray(4);
    glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, stride, offset(offsetof(SkinVertex, weights)));
    glGenBuffers(1, &gpu.ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(geometry.indices.size() * sizeof(std::uint32_t)),
                 geometry.indices.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    if (material.textured()) {
      ++textured;
      glGenTextures(1, &gpu.texture);
      glBindTexture(GL_TEXTURE_2D, gpu.texture);
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, material.width, material.height, 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, material.rgba.data());
      glGenerateMipmap(GL_TEXTURE_2D);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
      glBindTexture(GL_TEXTURE_2D, 0);
    }
    meshes_.push_back(gpu);
  }
  std::string line = file + ": " + std::to_string(asset.meshes.size()) + " skinned mesh" +
                     (asset.meshes.size() == 1 ? "" : "es") + ", " + thousands(vertex_total) +
                     " vertices, " + thousands(triangle_total) + " triangles";
  if (flat > 0) line += ", flat shaded (no normals in the file)";
  if (textured > 0) line += ", textured";
  messages_.push_back({LogLevel::kInfo, 0.0, line});
  // The importer chose the unit (anatomy, gltf_units.h); say so when it is not the file's metres.
  if (asset.detection.frame.unit != motion::LengthUnit::kMetres) {
    messages_.push_back({LogLevel::kInfo, 0.0,
                         file + ": read as " +
                             std::string(motion::unitName(asset.detection.frame.unit)) + " (" +
                             asset.detection.reason + ")"});
  }
}

// An orthographic view along the key light that holds everything that casts (the scene's bounds:
// the original and its model) and the ground their shadows fall on. Its centre moves in whole
// texels and its size in 15% steps, so the shadow's edges do not crawl as the character walks.
Renderer::Light Renderer::fitLight(const Scene& scene) const {
  const glm::vec3 to_light = glm::normalize(kLightDir);
  const glm::vec3 centre = 0.5f * (scene.bounds_min + scene.bounds_max);
  float radius = std::max(0.5f * glm::length(scene.bounds_max - scene.bounds_min), 0.25f);
  radius = std::pow(1.15f, std::ceil(std::log(radius) / std::log(1.15f)));
  const glm::vec3 up = std::abs(to_light.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::mat4 view = glm::lookAt(glm::vec3(0.0f), -to_light, up);
  Light light;
  light.texel = 2.0f * radius / static_cast<float>(kShadowMapSize);
  glm::vec3 c = glm::vec3(view * glm::vec4(centre, 1.0f));
  c.x = std::round(c.x / light.texel) * light.texel;
  c.y = std::round(c.y / light.texel) * light.texel;
  // View-space z is minus the distance along the light; the ground a shadow reaches lies at
  // most (height + radius) / sin(elevation) beyond the centre.
  const float depth = -c.z;
  const float ground = (std::max(centre.y, 0.0f) + radius) / std::max(to_light.y, 0.2f);
  const float near_d = depth - radius - 0.05f * radius;
  const float far_d = depth + radius + ground + 0.05f * radius;
  light.view_proj =
      glm::ortho(c.x - radius, c.x + radius, c.y - radius, c.y + radius, near_d, far_d) * view;
  // Where shadows can fall on the ground: the convex hull of the casters' box (a few texels
  // larger, for the filter) projected down along the light. Only this patch of floor runs the
  // shadow taps.
  const float margin = 4.0f * light.texel;
  std::vector<glm::vec2> points;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? scene.bounds_max.x + margin : scene.bounds_min.x - margin,
                      std::max((corner & 2) ? scene.bounds_max.y + margin : 0.0f, 0.0f),
                      (corner & 4) ? scene.bounds_max.z + margin : scene.bounds_min.z - margin);
    const glm::vec3 g = p - to_light * (p.y / std::max(to_light.y, 0.2f));
    points.emplace_back(g.x, g.z);
  }
  const std::vector<glm::vec2> hull = convexHull(points);
  light.ground_count = static_cast<int>(hull.size());
  for (size_t i = 0; i < hull.size(); ++i) light.ground[i] = glm::vec3(hull[i].x, 0.0f, hull[i].y);
  return light;
}

void Renderer::renderShadowMap(const Scene& scene, const Light& light) {
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  glViewport(0, 0, kShadowMapSize, kShadowMapSize);
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // Depth pushed away from the light in proportion to the slope: with the receivers' normal
  // offset, this keeps lit surfaces from shadowing themselves.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  drawCapsules(programs_[kCapsuleDepth], scene.opaque, light.view_proj, false);
  drawCapsules(programs_[kCapsuleDepth],
               std::span(scene.translucent)
                   .first(std::min(scene.translucent_casters, scene.translucent.size())),
               light.view_proj, false);
  drawSkinned(programs_[kSkinnedDepth], scene, light.view_proj, false);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Renderer::setLighting(GLuint program, const OrbitCamera& camera, const Light& light) {
  glUseProgram(program);
  setVec3(program, "u_eye", camera.eye());
  setVec3(program, "u_light_dir", glm::normalize(kLightDir));
  setVec3(program, "u_background", kBackground);
  // Fog and the floor's fade keep their usual distances at a character's framing, and recede
  // with the camera so that a large scene does not disappear into the background.
  setFloat(program, "u_fog_start", std::max(15.0f, 3.0f * camera.distance));
  setFloat(program, "u_fog_range", std::max(60.0f, 12.0f * camera.distance));
  setInt(program, "u_shadow_map", kShadowUnit);
  setMat4(program, "u_light_view_proj", light.view_proj);
  setFloat(program, "u_shadow_texel", light.texel);
  setFloat(program, "u_shadow_size", static_cast<float>(kShadowMapSize));
}

void Renderer::drawCapsules(GLuint program, std::span<const CapsuleInstance> all,
                            const glm::mat4& view_proj, bool translucent, int coarsest) {
  if (all.empty()) return;
  const std::span<const CapsuleInstance> capsules = capsulesWithinBudget(all, capsule_scratch_);
  const bool shadow = program == programs_[kCapsuleDepth] && !translucent;
  const int detail = capsuleDetail(capsules.size(), shadow ? std::max(coarsest, 1) : coarsest);
  const GLsizei index_count = capsule_index_count_[detail];
  const void* first = reinterpret_cast<const void*>(capsule_first_[detail] * sizeof(unsigned));
  glBindVertexArray(capsule_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capsules.size_bytes()), capsules.data(),
               GL_STREAM_DRAW);
  const auto count = static_cast<GLsizei>(capsules.size());
  if (translucent) {
    // Depth first (with the depth-only shader: llvmpipe would run the whole lit shader for a
    // pass that writes no colour), then colour where the depth matches: one clean translucent
    // surface. capsule.vert's gl_Position is invariant, so both passes agree on depth.
    const GLuint depth = programs_[kCapsuleDepth];
    glUseProgram(depth);
    setMat4(depth, "u_view_proj", view_proj);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDrawElementsInstanced(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, first, count);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(program);
    setMat4(program, "u_view_proj", view_proj);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDrawElementsInstanced(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, first, count);
    glDisable(GL_BLEND);
    glDepthFunc(GL_LESS);
  } else {
    glUseProgram(program);
    setMat4(program, "u_view_proj", view_proj);
    glDrawElementsInstanced(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, first, count);
  }
  glBindVertexArray(0);
}

// The scene's skinned meshes with `program` (shaded, or the depth pass when !shade). Each mesh's
// skinning matrices go into the float texture, one row of four texels per joint.
void Renderer::drawSkinned(GLuint program, const Scene& scene, const glm::mat4& view_proj,
                           bool shade) {
  if (scene.skinned.empty() || scene.asset != meshes_asset_) return;
  glUseProgram(program);
  setMat4(program, "u_view_proj", view_proj);
  setInt(program, "u_skinning", kSkinningUnit);
  if (shade) setInt(program, "u_base_texture", kBaseTextureUnit);
  for (const SkinnedDraw& draw : scene.skinned) {
    if (draw.mesh < 0 || draw.mesh >= static_cast<int>(meshes_.size())) continue;
    const GpuMesh& mesh = meshes_[static_cast<size_t>(draw.mesh)];
    const auto rows = static_cast<GLsizei>(draw.skinning.size());
    glActiveTexture(GL_TEXTURE0 + kSkinningUnit);
    glBindTexture(GL_TEXTURE_2D, skinning_texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (rows > skinning_rows_) {
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 4, rows, 0, GL_RGBA, GL_FLOAT,
                   draw.skinning.data());
      skinning_rows_ = rows;
    } else {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 4, rows, GL_RGBA, GL_FLOAT, draw.skinning.data());
    }
    if (shade) {
      setVec4(program, "u_base_color", mesh.base_color);
      setFloat(program, "u_textured", mesh.texture != 0 ? 1.0f : 0.0f);
      glActiveTexture(GL_TEXTURE0 + kBaseTextureUnit);
      glBindTexture(GL_TEXTURE_2D, mesh.texture);
    }
    glBindVertexArray(mesh.vao);
    glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
}

void Renderer::draw(const ViewportRect& rect, const OrbitCamera& camera, const Scene& scene,
                    bool grid) {
  if (ready_) syncMeshes(scene);
  const bool shadows = ready_ && scene.shadows && !scene.empty;
  const Light light = fitLight(scene);
  if (shadows) renderShadowMap(scene, light);
  if (profile_ != nullptr) {
    glFinish();
    profile_->mark(FrameStage::kShadow);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  drawView(rect, camera, scene, grid, shadows, light);
  if (profile_ != nullptr) {
    glFinish();
    profile_->mark(FrameStage::kViewport);
  }
}

void Renderer::drawView(const ViewportRect& rect, const OrbitCamera& camera, const Scene& scene,
                        bool grid, bool shadows, const Light& light) {
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
  const GLuint capsule = programs_[shadows ? kCapsuleShadowed : kCapsule];
  const GLuint skinned = programs_[shadows ? kSkinnedShadowed : kSkinned];
  // The unshadowed capsule program too: the population's ghosts and the x-ray skeleton use it.
  for (GLuint program : {capsule, programs_[kCapsule], skinned, programs_[kShadowFloor]}) {
    setLighting(program, camera, light);
  }
  glActiveTexture(GL_TEXTURE0 + kShadowUnit);
  glBindTexture(GL_TEXTURE_2D, shadow_texture_);
  glActiveTexture(GL_TEXTURE0);

  drawCapsules(capsule, scene.opaque, view_proj, false);
  drawSkinned(skinned, scene, view_proj, true);
  if (grid) {
    const GLuint program = programs_[kGrid];
    glUseProgram(program);
    setMat4(program, "u_view_proj", view_proj);
    setVec3(program, "u_eye", camera.eye());
    setVec3(program, "u_background", kBackground);
    setVec3(program, "u_centre", glm::vec3(camera.target.x, 0.0f, camera.target.z));
    setFloat(program, "u_extent", std::max(30.0f, camera.distance * 12.0f));
    setFloat(program, "u_fade_scale", std::max(1.0f, camera.distance / 4.0f));
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glBindVertexArray(grid_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    if (shadows) {
      // The floor's shadow over the grid, only on the patch the shadow map covers: the rest of
      // the floor (most of the viewport) never runs the shadow taps.
      const GLuint floor = programs_[kShadowFloor];
      glUseProgram(floor);
      setMat4(floor, "u_view_proj", view_proj);
      glUniform3fv(glGetUniformLocation(floor, "u_corners"), light.ground_count,
                   glm::value_ptr(light.ground[0]));
      setFloat(floor, "u_strength", kFloorShadowStrength);
      if (light.ground_count >= 3) glDrawArrays(GL_TRIANGLE_FAN, 0, light.ground_count);
    }
    glBindVertexArray(0);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  // The model as finely as the original; the population's ghosts, small and many, coarser and
  // unshadowed: they cast no shadow either, and the shadow tap per fragment was a fifth of the
  // 3D view with 16 of them (docs/editor.md).
  const std::span<const CapsuleInstance> translucent(scene.translucent);
  const size_t model = std::min(scene.translucent_casters, translucent.size());
  drawCapsules(capsule, translucent.first(model), view_proj, true);
  drawCapsules(programs_[kCapsule], translucent.subspan(model), view_proj, true, kPopulationDetail);
  if (!scene.xray.empty()) {
    // The skeleton over the mesh: in front of everything (the scissor keeps the clear in the
    // viewport), translucent so the mesh shows through, and unshadowed (it is inside the mesh,
    // which would leave it all in shadow).
    glClear(GL_DEPTH_BUFFER_BIT);
    drawCapsules(programs_[kCapsule], scene.xray, view_proj, true);
  }
  glActiveTexture(GL_TEXTURE0 + kShadowUnit);
  glBindTexture(GL_TEXTURE_2D, 0);
  glActiveTexture(GL_TEXTURE0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace sinew::editor
