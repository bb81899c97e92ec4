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

namespace {

// Whether frames [first, first + count) of `joint` overlap a glitch.
bool overlapsGlitch(std::span<const Glitch> glitches, int joint, int first, int count) {
  return std::any_of(glitches.begin(), glitches.end(), [&](const Glitch& g) {
    return g.joint == joint && first < g.first_frame + g.frame_count &&
           g.first_frame < first + count;
  });
}

// A cyclic motion repeats a stride away: the lag (either way, 0.25-2.5 s) at which the good
// frames around the glitch (0.2 s each side, at least 3) best match themselves, and the RMS
// angle of that match, radians; lag 0 when none fits in the clip. Only lags whose frames hold no
// glitch of the joint count.
std::pair<int, double> strideLag(const Clip& clip, std::span<const Glitch> glitches,
                                 const Glitch& g, int context) {
  const int a = g.first_frame, b = g.first_frame + g.frame_count;
  const int lo = std::max(1, static_cast<int>(std::lround(0.25 / clip.frame_time)));
  const int hi = static_cast<int>(std::lround(2.5 / clip.frame_time));
  int best = 0;
  double best_cost = 1e300;
  for (int lag = -hi; lag <= hi; ++lag) {
    if (std::abs(lag) < lo) continue;
    const int first = a - context + lag, last = b + context + lag;  // donor frames [first, last)
    if (first < 0 || last > clip.frame_count) continue;
    if (overlapsGlitch(glitches, g.joint, first, last - first)) continue;
    double sum = 0.0;
    int n = 0;
    for (int f = a - context; f < b + context; ++f) {
      if (f >= a && f < b) continue;
      const double d = angleBetween(clip.rotation(f, g.joint), clip.rotation(f + lag, g.joint));
      sum += d * d;
      ++n;
    }
    const double cost = std::sqrt(sum / n);
    if (cost < best_cost) best_cost = cost, best = lag;
  }
  return {best, best_cost};
}

// Frames [a, a + count) of `joint` as the frames `lag` away, carried by the offset that takes
// the donor's boundary frames onto these (interpolated between the two sides).
std::vector<glm::dquat> strideFill(const Clip& clip, int joint, int a, int count, int lag) {
  const int b = a + count;
  const glm::dquat e0 =
      clip.rotation(a - 1, joint) * glm::inverse(clip.rotation(a - 1 + lag, joint));
  const glm::dquat e1 = clip.rotation(b, joint) * glm::inverse(clip.rotation(b + lag, joint));
  std::vector<glm::dquat> fill(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k) {
    const double t = static_cast<double>(k + 1) / static_cast<double>(count + 1);
    fill[static_cast<size_t>(k)] =
        glm::normalize(shortSlerp(e0, e1, t) * clip.rotation(a + k + lag, joint));
  }
  return fill;
}

// Frames [a, a + count) by the cubic through two good frames each side (in rotation vectors
// relative to the frame before), or the slerp between the one each side near the clip's ends.
std::vector<glm::dquat> cubicFill(const Clip& clip, int joint, int a, int count) {
  const int before = a - 1, after = a + count;
  const glm::dquat q0 = clip.rotation(before, joint);
  const glm::dquat q1 = clip.rotation(after, joint);
  std::vector<glm::dquat> fill(static_cast<size_t>(count));
  const bool cubic = before >= 1 && after + 1 < clip.frame_count;
  const double times[4] = {-1.0, 0.0, static_cast<double>(count + 1),
                           static_cast<double>(count + 2)};
  glm::dvec3 points[4];
  if (cubic) {
    const glm::dquat inverse = glm::inverse(q0);
    const int frames[4] = {before - 1, before, after, after + 1};
    for (int i = 0; i < 4; ++i)
      points[i] = shortRotationVector(inverse * clip.rotation(frames[i], joint));
  }
  for (int k = 0; k < count; ++k) {
    if (!cubic) {
      fill[static_cast<size_t>(k)] =
          shortSlerp(q0, q1, static_cast<double>(k + 1) / static_cast<double>(count + 1));
      continue;
    }
    const double t = static_cast<double>(k + 1);
    glm::dvec3 v(0.0);
    for (int i = 0; i < 4; ++i) {  // Lagrange: the cubic through the four frames
      double weight = 1.0;
      for (int m = 0; m < 4; ++m)
        if (m != i) weight *= (t - times[m]) / (times[i] - times[m]);
      v += weight * points[i];
    }
    fill[static_cast<size_t>(k)] = glm::normalize(q0 * fromRotationVector(v));
  }
  return fill;
}

// Squared angles between a fill and the frames it stands for, summed, radians^2.
double fillError(const Clip& clip, int joint, int a, const std::vector<glm::dquat>& fill) {
  double sum = 0.0;
  for (size_t k = 0; k < fill.size(); ++k) {
    const double d = angleBetween(fill[k], clip.rotation(a + static_cast<int>(k), joint));
    sum += d * d;
  }
  return sum;
}

// Whether the stride fill beats the cubic on the good frames around the glitch: each of the two
// methods fills pretend runs of the glitch's length in its good context (and the stride's donor
// frames), and the one that recovers them better is used. A toe-off's snap, which no
// interpolation across the missing frames sees, is in the previous stride; a clip shorter than
// two strides, or motion that does not repeat, keeps the cubic.
bool strideFillIsBetter(const Clip& clip, std::span<const Glitch> glitches, const Glitch& g,
                        int lag, int context) {
  const int count = g.frame_count;
  double stride = 0.0, cubic = 0.0;
  int tried = 0;
  for (int a = g.first_frame - context; a <= g.first_frame + count + context - count; ++a) {
    if (a < 2 || a + count + 2 > clip.frame_count) continue;
    if (a + count + 2 > g.first_frame && a - 2 < g.first_frame + count) continue;  // the glitch
    if (a - 1 + lag < 0 || a + count + 1 + lag > clip.frame_count) continue;
    if (overlapsGlitch(glitches, g.joint, a - 2, count + 4) ||
        overlapsGlitch(glitches, g.joint, a - 1 + lag, count + 2))
      continue;
    stride += fillError(clip, g.joint, a, strideFill(clip, g.joint, a, count, lag));
    cubic += fillError(clip, g.joint, a, cubicFill(clip, g.joint, a, count));
    ++tried;
  }
  return tried >= 2 && stride < cubic;
}

}  // namespace

void repairGlitches(Clip& clip, std::span<const Glitch> glitches) {
  for (const Glitch& g : glitches) {
    const int context = std::max(3, static_cast<int>(std::lround(0.2 / clip.frame_time)));
    const int a = g.first_frame, b = g.first_frame + g.frame_count;
    int lag = 0;
    if (a - context >= 0 && b + context <= clip.frame_count)
      lag = strideLag(clip, glitches, g, context).first;
    const std::vector<glm::dquat> fill =
        lag != 0 && strideFillIsBetter(clip, glitches, g, lag, context)
            ? strideFill(clip, g.joint, a, g.frame_count, lag)
            : cubicFill(clip, g.joint, a, g.frame_count);
    for (int k = 0; k < g.frame_count; ++k)
      clip.rotations[static_cast<size_t>(a + k) * clip.joint_count + g.joint] =
          fill[static_cast<size_t>(k)];
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
