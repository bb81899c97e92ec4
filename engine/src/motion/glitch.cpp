#include "sinew/motion/glitch.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/quaternion.hpp>

#include "sinew/core/rotation.h"

namespace sinew::motion {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// The joint's rotations, frame by frame.
std::vector<glm::dquat> jointTrack(const Clip& clip, int joint) {
  std::vector<glm::dquat> track(static_cast<size_t>(clip.frame_count));
  for (int f = 0; f < clip.frame_count; ++f)
    track[static_cast<size_t>(f)] = clip.rotation(f, joint);
  return track;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t k = std::min(values.size() - 1,
                            static_cast<size_t>(q * static_cast<double>(values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// Largest angle between frames first..first+count-1 and the slerp across them, radians.
double excursion(std::span<const glm::dquat> track, int first, int count) {
  const glm::dquat& before = track[static_cast<size_t>(first - 1)];
  const glm::dquat& after = track[static_cast<size_t>(first + count)];
  double largest = 0.0;
  for (int k = 0; k < count; ++k) {
    const double t = static_cast<double>(k + 1) / static_cast<double>(count + 1);
    largest = std::max(
        largest, angleBetween(track[static_cast<size_t>(first + k)], shortSlerp(before, after, t)));
  }
  return largest;
}

// Glitches of one joint: for each frame the track jumps into by more than the threshold, the
// shortest run that jumps back out, whose neighbours agree and whose excursion is large.
void findInJoint(std::span<const glm::dquat> track, int joint, int max_frames,
                 const GlitchSettings& settings, std::vector<Glitch>& out) {
  const int frames = static_cast<int>(track.size());
  std::vector<double> steps(static_cast<size_t>(frames - 1));
  for (int f = 0; f + 1 < frames; ++f)
    steps[static_cast<size_t>(f)] = angleBetween(track[f], track[f + 1]);
  const double typical = quantile(steps, settings.step_quantile);
  const double threshold =
      std::max(settings.min_size_deg / kDegrees, settings.relative_size * typical);
  for (int first = 1; first + 1 < frames; ++first) {
    if (steps[static_cast<size_t>(first - 1)] <= threshold) continue;  // no jump into this frame
    for (int count = 1; count <= max_frames && first + count < frames; ++count) {
      const int last = first + count - 1;
      if (steps[static_cast<size_t>(last)] <= threshold) continue;  // no jump back out here
      const double across = angleBetween(track[first - 1], track[first + count]);
      const double size = excursion(track, first, count);
      if (size > threshold && across <= settings.max_across_ratio * size) {
        out.push_back(Glitch{joint, first, count, size * kDegrees});
        first = last + 1;  // resume after the run's good neighbour
        break;
      }
    }
  }
}

}  // namespace

Status GlitchSettings::validate() const {
  if (!(relative_size > 0.0 && std::isfinite(relative_size))) {
    return Status::error("glitch relative_size must be finite and > 0");
  }
  if (!(step_quantile >= 0.0 && step_quantile <= 1.0)) {
    return Status::error("glitch step_quantile must be in [0, 1]");
  }
  if (!(min_size_deg > 0.0 && std::isfinite(min_size_deg))) {
    return Status::error("glitch min_size_deg must be finite and > 0");
  }
  if (!(max_duration_s > 0.0 && std::isfinite(max_duration_s))) {
    return Status::error("glitch max_duration_s must be finite and > 0");
  }
  if (!(max_across_ratio >= 0.0 && std::isfinite(max_across_ratio))) {
    return Status::error("glitch max_across_ratio must be finite and >= 0");
  }
  return {};
}

std::vector<Glitch> findGlitches(const Clip& clip, const GlitchSettings& settings) {
  std::vector<Glitch> glitches;
  if (clip.frame_count < 3) return glitches;
  const int max_frames =
      std::max(1, static_cast<int>(std::floor(settings.max_duration_s / clip.frame_time + 1e-9)));
  for (int joint = 0; joint < clip.joint_count; ++joint) {
    const std::vector<glm::dquat> track = jointTrack(clip, joint);
    findInJoint(track, joint, max_frames, settings, glitches);
  }
  return glitches;
}

void repairGlitches(Clip& clip, std::span<const Glitch> glitches) {
  for (const Glitch& g : glitches) {
    const int before = g.first_frame - 1;
    const int after = g.first_frame + g.frame_count;
    const glm::dquat q0 = clip.rotation(before, g.joint);
    const glm::dquat q1 = clip.rotation(after, g.joint);
    // Two good frames each side: a cubic through them in the rotation vectors relative to the
    // frame before, which follows a toe-off's snap (a chord misses it by up to 23 degrees over
    // three Bandai frames). One each side: the slerp between them.
    const bool cubic = before >= 1 && after + 1 < clip.frame_count;
    const double times[4] = {-1.0, 0.0, static_cast<double>(g.frame_count + 1),
                             static_cast<double>(g.frame_count + 2)};
    glm::dvec3 points[4];
    if (cubic) {
      const glm::dquat inverse = glm::inverse(q0);
      const int frames[4] = {before - 1, before, after, after + 1};
      for (int i = 0; i < 4; ++i)
        points[i] = shortRotationVector(inverse * clip.rotation(frames[i], g.joint));
    }
    for (int k = 0; k < g.frame_count; ++k) {
      glm::dquat& q =
          clip.rotations[static_cast<size_t>(g.first_frame + k) * clip.joint_count + g.joint];
      if (!cubic) {
        q = shortSlerp(q0, q1, static_cast<double>(k + 1) / static_cast<double>(g.frame_count + 1));
        continue;
      }
      const double t = static_cast<double>(k + 1);
      glm::dvec3 v(0.0);
      for (int i = 0; i < 4; ++i) {  // Lagrange: the cubic through the four frames
        double weight = 1.0;
        for (int m = 0; m < 4; ++m) {
          if (m != i) weight *= (t - times[m]) / (times[i] - times[m]);
        }
        v += weight * points[i];
      }
      q = glm::normalize(q0 * fromRotationVector(v));
    }
  }
}

std::string describeGlitch(const Skeleton& skeleton, const Glitch& glitch) {
  const std::string& name = skeleton.names[static_cast<size_t>(glitch.joint)];
  char text[96];
  const int last = glitch.first_frame + glitch.frame_count - 1;
  if (glitch.frame_count == 1) {
    std::snprintf(text, sizeof text, " frame %d: %.1f deg", glitch.first_frame, glitch.size_deg);
  } else {
    std::snprintf(text, sizeof text, " frames %d-%d (%d): %.1f deg", glitch.first_frame, last,
                  glitch.frame_count, glitch.size_deg);
  }
  return name + text;
}

}  // namespace sinew::motion
