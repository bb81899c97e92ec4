// BVH writer: the clip's quaternions back into each joint's own Euler order, in the target
// frame's units and axes, continuous from frame to frame.
#include <charconv>
#include <cmath>

#include "sinew/motion/bvh.h"

namespace sinew::motion {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// Fixed-point with 6 decimals: exact to 5e-7 (degrees or file units), read by every BVH tool.
void appendNumber(std::string& out, double value) {
  if (std::abs(value) < 5e-7) value = 0.0;  // no "-0.000000"
  char buffer[400];  // room for any finite double in fixed notation (up to 309 integer digits)
  const auto [end, error] =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, 6);
  out.append(buffer, error == std::errc() ? end : buffer);
}

void appendVector(std::string& out, const glm::dvec3& v) {
  for (int n = 0; n < 3; ++n) {
    out += ' ';
    appendNumber(out, v[n]);
  }
}

// The layout each joint is written with: its own, or a default for rigs that did not come from BVH.
std::vector<ChannelLayout> layoutsFor(const Skeleton& skeleton, const Clip& clip) {
  if (skeleton.channelCount() > 0) return skeleton.channels;
  std::vector<ChannelLayout> layouts(skeleton.jointCount());
  const ChannelLayout rotations{{ChannelType::kZrotation, ChannelType::kXrotation,
                                 ChannelType::kYrotation}};
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    bool moves = skeleton.parents[j] == kNoParent;
    for (int f = 0; f < clip.frame_count && !moves; ++f) {
      moves = glm::length(clip.translation(f, j) - skeleton.offsets[j]) > 1e-6;
    }
    if (moves) {
      layouts[j].types = {ChannelType::kXposition, ChannelType::kYposition,
                          ChannelType::kZposition};
    }
    layouts[j].types.insert(layouts[j].types.end(), rotations.types.begin(), rotations.types.end());
  }
  return layouts;
}

// BVH has no scale: a uniform scale on a joint is folded into its descendants' translations.
// Returns, per joint, the factor its translation is multiplied by (product of ancestor scales).
std::vector<double> inheritedScale(const Skeleton& skeleton, const Clip& clip, int frame) {
  std::vector<double> own(skeleton.jointCount(), 1.0);
  std::vector<double> inherited(skeleton.jointCount(), 1.0);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const glm::dvec3 s = clip.scale(frame, j);
    own[j] = (s.x + s.y + s.z) / 3.0;
    const int parent = skeleton.parents[j];
    inherited[j] = parent == kNoParent ? 1.0 : inherited[parent] * own[parent];
  }
  return inherited;
}

}  // namespace

SourceFrame defaultBvhFrame(const Skeleton& skeleton) {
  return skeleton.channelCount() > 0 ? skeleton.source
                                     : SourceFrame{LengthUnit::kCentimetres, UpAxis::kY};
}

std::string writeBvh(const Skeleton& skeleton, const Clip& clip, const SourceFrame& frame) {
  const std::vector<ChannelLayout> layouts = layoutsFor(skeleton, clip);
  const std::vector<double> rest_scale = inheritedScale(skeleton, clip, 0);
  std::string out = "HIERARCHY\n";
  std::vector<int> open;  // joints whose block is not closed yet
  const auto indent = [&out](size_t depth) { out.append(depth, '\t'); };
  const auto close = [&]() {
    const int j = open.back();
    if (skeleton.end_sites[j]) {
      indent(open.size());
      out += "End Site\n";
      indent(open.size());
      out += "{\n";
      indent(open.size() + 1);
      out += "OFFSET";
      appendVector(out, frame.pointFromEngine(*skeleton.end_sites[j] * rest_scale[j]));
      out += '\n';
      indent(open.size());
      out += "}\n";
    }
    open.pop_back();
    indent(open.size());
    out += "}\n";
  };
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    while (!open.empty() && open.back() != skeleton.parents[j]) close();
    indent(open.size());
    out += skeleton.parents[j] == kNoParent ? "ROOT " : "JOINT ";
    out += skeleton.names[j];
    out += '\n';
    indent(open.size());
    out += "{\n";
    indent(open.size() + 1);
    out += "OFFSET";
    appendVector(out, frame.pointFromEngine(skeleton.offsets[j] * rest_scale[j]));
    out += '\n';
    indent(open.size() + 1);
    out += "CHANNELS " + std::to_string(layouts[j].types.size());
    for (ChannelType type : layouts[j].types) {
      out += ' ';
      out += channelName(type);
    }
    out += '\n';
    open.push_back(j);
  }
  while (!open.empty()) close();

  out += "MOTION\nFrames: " + std::to_string(clip.frame_count) + "\nFrame Time: ";
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof(buffer), clip.frame_time);
  out.append(buffer, error == std::errc() ? end : buffer);
  out += '\n';

  std::vector<glm::dvec3> previous(skeleton.jointCount(), glm::dvec3(0.0));
  const bool has_start = clip.euler_start.size() == static_cast<size_t>(skeleton.jointCount()) &&
                         skeleton.channelCount() > 0;
  if (has_start) previous = clip.euler_start;
  for (int f = 0; f < clip.frame_count; ++f) {
    const std::vector<double> scale = clip.scales.empty() ? rest_scale : inheritedScale(skeleton, clip, f);
    bool first_value = true;
    for (int j = 0; j < skeleton.jointCount(); ++j) {
      const ChannelLayout& layout = layouts[j];
      if (layout.types.empty()) continue;
      const glm::dvec3 position = frame.pointFromEngine(clip.translation(f, j) * scale[j]);
      glm::dvec3 angles(0.0);
      if (layout.rotationCount() == 3) {
        angles = quatToEuler(layout.eulerOrder(), frame.rotationFromEngine(clip.rotation(f, j)),
                             previous[j], clip.euler_range);
        previous[j] = angles;
      }
      int rotation = 0;
      for (ChannelType type : layout.types) {
        if (!first_value) out += ' ';
        first_value = false;
        appendNumber(out, isRotation(type) ? angles[rotation++] * kDegrees
                                           : position[channelAxis(type)]);
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace sinew::motion
