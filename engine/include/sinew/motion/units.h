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

// kCmu: the CMU motion-capture database's length unit as its BVH conversions keep it,
// (1 / 0.45) inch = 0.056444 m (its ASF files scale inches by 0.45).
enum class LengthUnit { kMetres, kCentimetres, kMillimetres, kInches, kFeet, kCmu };
inline constexpr LengthUnit kAllLengthUnits[] = {LengthUnit::kMetres,      LengthUnit::kCentimetres,
                                                 LengthUnit::kMillimetres, LengthUnit::kInches,
                                                 LengthUnit::kFeet,        LengthUnit::kCmu};
enum class UpAxis { kY, kZ };

double metresPerUnit(LengthUnit unit);
std::string_view unitName(LengthUnit unit);  // "m", "cm", "mm", "in", "ft", "cmu"
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

// What detectFrame (anatomy.h) saw, for the report shown to the user.
struct FrameDetection {
  SourceFrame frame;
  double height_in_file_units = 0.0;  // extent of the figure along the detected up axis, file units
  double height_m = 0.0;              // the same in metres with the chosen unit
  std::string reason;                 // one sentence: what decided it
};

}  // namespace sinew::motion
