// Units and up axis. Inside the engine everything is metres and Y-up; files are whatever they
// are. BVH says nothing about either, so import detects them (detectFrame) and the user can
// override; export converts back to the file's own frame.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace sinew::motion {

enum class LengthUnit { kMetres, kCentimetres, kMillimetres, kInches };
enum class UpAxis { kY, kZ };

double metresPerUnit(LengthUnit unit);
std::string_view unitName(LengthUnit unit);  // "m", "cm", "mm", "in"
std::optional<LengthUnit> unitFromName(std::string_view name);
std::string_view upAxisName(UpAxis up);  // "Y", "Z"
std::optional<UpAxis> upAxisFromName(std::string_view name);

// The frame a file's numbers live in, and the map to and from the engine's metres, Y-up.
struct SourceFrame {
  LengthUnit unit = LengthUnit::kMetres;
  UpAxis up = UpAxis::kY;

  // Rotation taking file axes to engine axes: identity for Y-up; -90 degrees about X for Z-up,
  // so (x, y, z) in the file becomes (x, z, -y).
  glm::dquat axisRotation() const;
  glm::dvec3 pointToEngine(const glm::dvec3& p) const;    // file units -> metres, Y-up
  glm::dvec3 pointFromEngine(const glm::dvec3& p) const;  // inverse of pointToEngine
  glm::dquat rotationToEngine(const glm::dquat& q) const;
  glm::dquat rotationFromEngine(const glm::dquat& q) const;
};

// What detectFrame saw, for the report shown to the user.
struct FrameDetection {
  SourceFrame frame;
  double height_in_file_units = 0.0;  // extent along the detected up axis, file units
  std::string reason;                 // one sentence: what decided it
};

}  // namespace sinew::motion

#include <span>
#include <vector>

namespace sinew::motion {

// Detects the up axis and length unit from points of a posed character in file units (the first
// frame's pose, so a root rotation that stands a Z-up rest pose upright counts). `is_leaf` marks
// chain ends (End Sites, or joints without children) and `centre` the pelvis (the first joint
// that branches). On the true up axis several chain ends (the feet) share the lowest height and
// the pelvis stands well above them. Height >= 1000 units reads as millimetres, >= 10 as
// centimetres, else metres.
FrameDetection detectFrame(std::span<const glm::dvec3> points, const std::vector<bool>& is_leaf,
                           int centre);

}  // namespace sinew::motion
