// Limits every motion reader checks and every writer relies on (docs/formats.md lists them).
// Lengths beyond these are not a character (a kilometre-long bone) and would overflow float32 in
// glTF and the renderer; frame times beyond them make clips of one frame or of billions. The
// checks name the file, line or field.
#pragma once

#include <glm/vec3.hpp>

namespace sinew::motion {

inline constexpr double kMaxLength_m = 1e6;      // |offset| and |translation| components, metres
inline constexpr double kMaxScale = 1e6;         // |scale| components
inline constexpr double kMinFrameTime_s = 1e-4;  // 10,000 frames per second
inline constexpr double kMaxFrameTime_s = 60.0;  // one frame a minute

// Finite and within kMaxLength_m (kMaxScale) in every component.
bool withinLength(const glm::dvec3& v);
bool withinScale(const glm::dvec3& v);

}  // namespace sinew::motion
