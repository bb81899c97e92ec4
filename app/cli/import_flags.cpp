#include <charconv>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>

#include "cli/commands.h"

namespace sinew::app {

void ImportFlags::addTo(CLI::App& command) {
  command.add_option("--units", units, "Length unit of a BVH file, overriding detection (cmu: the CMU database's 0.056444 m)")
      ->check(CLI::IsMember({"m", "cm", "mm", "in", "ft", "cmu"}));
  command.add_option("--up", up, "Up axis of a BVH file, overriding detection")
      ->check(CLI::IsMember({"Y", "Z", "y", "z"}));
  command
      .add_option(
          "--fps", fps,
          "Frame rate to resample to (default: the file's own; for glTF the keys' median spacing)")
      ->check(CLI::Range(1.0 / 60.0, 1000.0));  // motion/limits.h: frame times up to 60 s
  command.add_flag("--keep-glitches", keep_glitches,
                   "Keep rotation glitches (a joint flipping away for a few frames) instead of "
                   "repairing them by interpolation; they are reported either way");
}

Result<motion::ImportOptions> ImportFlags::options() const {
  motion::ImportOptions options;
  if (!units.empty()) {
    options.unit = motion::unitFromName(units);
    if (!options.unit) return Status::error("--units: unknown unit '" + units + "'");
  }
  if (!up.empty()) {
    options.up = motion::upAxisFromName(up);
    if (!options.up) return Status::error("--up: expected Y or Z, got '" + up + "'");
  }
  if (fps > 0.0) options.fps = fps;
  options.repair_glitches = !keep_glitches;
  return options;
}

Result<int> selectClip(const motion::MotionAsset& asset, const std::string& name) {
  if (asset.clips.empty()) {
    return Status::error(asset.path.string() + ": has no animation");
  }
  if (name.empty()) return 0;
  const int index = asset.findClip(name);
  if (index >= 0) return index;
  std::string names;
  for (const motion::Clip& clip : asset.clips) {
    if (!names.empty()) names += ", ";
    names += clip.name;
  }
  return Status::error(asset.path.string() + ": no animation named '" + name +
                       "'; the file has: " + names);
}

CLI::Validator wholeNumber(std::uint64_t max) {
  const bool bounded = max != std::numeric_limits<std::uint64_t>::max();
  const std::string range = bounded ? "from 0 to " + std::to_string(max) : ">= 0";
  return CLI::Validator(
      [max, range](std::string& text) {
        std::uint64_t value = 0;
        const bool digits =
            !text.empty() && text.size() <= 19 &&
            text.find_first_not_of("0123456789") == std::string::npos &&
            std::from_chars(text.data(), text.data() + text.size(), value).ec == std::errc();
        return digits && value <= max ? std::string()
                                      : "expected a whole number " + range + ", got '" + text + "'";
      },
      bounded ? "N in [0 - " + std::to_string(max) + "]" : "N >= 0");
}

std::string glitchSummary(const motion::MotionAsset& asset, int clip) {
  if (clip < 0 || clip >= static_cast<int>(asset.glitches.size()) || asset.glitches[clip].empty()) {
    return "none";
  }
  const std::vector<motion::Glitch>& found = asset.glitches[clip];
  std::set<int> joints;
  for (const motion::Glitch& glitch : found) joints.insert(glitch.joint);
  std::string names;
  for (int joint : joints) names += (names.empty() ? "" : ", ") + asset.skeleton.names[joint];
  return std::to_string(found.size()) + " in " + names +
         (asset.glitches_repaired ? ", repaired by interpolation (--keep-glitches keeps them)"
                                  : ", kept (--keep-glitches)");
}

nlohmann::json glitchJson(const motion::MotionAsset& asset, int clip) {
  nlohmann::json list = nlohmann::json::array();
  if (clip < 0 || clip >= static_cast<int>(asset.glitches.size())) return list;
  for (const motion::Glitch& glitch : asset.glitches[clip]) {
    list.push_back({{"joint", asset.skeleton.names[glitch.joint]},
                    {"first_frame", glitch.first_frame},
                    {"frames", glitch.frame_count},
                    {"size_deg", glitch.size_deg},
                    {"repaired", asset.glitches_repaired}});
  }
  return list;
}

int fail(const std::string& message) {
  std::cerr << "sinew: " << message << '\n';
  return 1;
}

}  // namespace sinew::app
