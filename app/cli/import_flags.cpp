#include <iostream>

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

CLI::Validator wholeNumber() {
  return CLI::Validator(
      [](std::string& text) {
        const bool digits = !text.empty() && text.size() <= 19 &&
                            text.find_first_not_of("0123456789") == std::string::npos;
        return digits ? std::string() : "expected a whole number >= 0, got '" + text + "'";
      },
      "N >= 0");
}

int fail(const std::string& message) {
  std::cerr << "sinew: " << message << '\n';
  return 1;
}

}  // namespace sinew::app
