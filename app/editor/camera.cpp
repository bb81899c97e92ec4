#include "editor/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace sinew::editor {

glm::vec3 OrbitCamera::eye() const {
  const glm::vec3 dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                      std::cos(pitch) * std::cos(yaw));
  return target + dir * distance;
}

glm::mat4 OrbitCamera::view() const {
  return glm::lookAt(eye(), target, glm::vec3(0, 1, 0));
}

glm::mat4 OrbitCamera::projection(float aspect) const {
  const float near_m = std::max(0.01f, distance * 0.01f);
  return glm::perspective(fov_y, std::max(aspect, 0.01f), near_m, near_m * 20000.0f);
}

void OrbitCamera::orbit(float dx_px, float dy_px) {
  yaw -= dx_px * 0.008f;
  pitch = std::clamp(pitch + dy_px * 0.008f, -1.5f, 1.5f);
}

void OrbitCamera::pan(float dx_px, float dy_px, float viewport_h_px) {
  const glm::mat4 v = view();
  const glm::vec3 right(v[0][0], v[1][0], v[2][0]);
  const glm::vec3 up(v[0][1], v[1][1], v[2][1]);
  const float metres_per_px =
      2.0f * distance * std::tan(fov_y * 0.5f) / std::max(viewport_h_px, 1.0f);
  target += (-dx_px * right + dy_px * up) * metres_per_px;
}

void OrbitCamera::zoom(float wheel_steps) {
  distance = std::clamp(distance * std::pow(0.88f, wheel_steps), 0.05f, 500.0f);
}

void OrbitCamera::frame(const glm::vec3& lo, const glm::vec3& hi) {
  target = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 0.05f);
  distance = radius / std::sin(fov_y * 0.5f) * 1.05f;
}

glm::vec3 OrbitCamera::rayDirection(float x_ndc, float y_ndc, float aspect) const {
  const glm::mat4 inverse = glm::inverse(projection(aspect) * view());
  glm::vec4 near_point = inverse * glm::vec4(x_ndc, y_ndc, -1.0f, 1.0f);
  glm::vec4 far_point = inverse * glm::vec4(x_ndc, y_ndc, 1.0f, 1.0f);
  near_point /= near_point.w;
  far_point /= far_point.w;
  return glm::normalize(glm::vec3(far_point - near_point));
}

}  // namespace sinew::editor
