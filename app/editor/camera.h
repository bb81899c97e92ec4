// An orbit camera around a target point (Y up): yaw and pitch about the target, a distance, and
// pan that moves the target in the view plane. Pure math; the editor feeds it mouse deltas.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace sinew::editor {

struct OrbitCamera {
  glm::vec3 target{0.0f, 1.0f, 0.0f};  // metres, world
  float distance = 4.0f;               // metres from the target, > 0
  float yaw = 0.7f;                    // radians about +Y; 0 looks along -Z
  float pitch = 0.22f;                 // radians above the horizon, within +-1.5
  float fov_y = 0.75f;                 // radians

  glm::vec3 eye() const;
  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;

  void orbit(float dx_px, float dy_px);                      // mouse pixels
  void pan(float dx_px, float dy_px, float viewport_h_px);   // keeps the point under the mouse
  void zoom(float wheel_steps);                              // + zooms in
  void frame(const glm::vec3& lo, const glm::vec3& hi);      // fits the box in view
  // The world-space direction (unit) through a point of the view, in normalised device
  // coordinates (-1..1, Y up); the ray starts at eye().
  glm::vec3 rayDirection(float x_ndc, float y_ndc, float aspect) const;
};

}  // namespace sinew::editor
