#include "cli/controller_file.h"

namespace sinew::app {

void BodyFlags::addTo(CLI::App& command) {
  command.add_option("--mass", masses,
                     "Override a body's mass: NAME=KG (its joint's name); repeatable");
  command.add_option("--fixed", fixed, "Weld this joint (no motion); repeatable");
  command.add_option("--hinge-limits", hinge_limits,
                     "Override a hinge's range: NAME=LO,HI in degrees; repeatable");
}

Result<BodyOverrides> BodyFlags::overrides() const {
  return parseBodyOverrides(masses, fixed, hinge_limits);
}

Result<LoadedRig> loadRig(const pipeline::ProjectSettings& settings, const ImportFlags& import) {
  Result<motion::ImportOptions> options = import.options();
  if (!options.ok()) return options.status();
  Result<motion::MotionAsset> rig = motion::importMotion(settings.rig, options.value());
  if (!rig.ok()) return rig.status();
  LoadedRig out;
  out.asset = std::move(rig).value();
  if (!settings.clip.empty()) {
    Result<motion::MotionAsset> clip_asset = motion::importMotion(settings.clip, options.value());
    if (!clip_asset.ok()) return clip_asset.status();
    out.other = std::move(clip_asset).value();
    if (out.other.skeleton.names != out.asset.skeleton.names)
      return Status::error(settings.clip + ": its skeleton is not the rig's (" + settings.rig +
                           "): the joints differ in names or order");
    if (out.other.skeleton.parents != out.asset.skeleton.parents)
      return Status::error(settings.clip + ": its skeleton is not the rig's (" + settings.rig +
                           "): the same joint names in another hierarchy");
    out.from_other = true;
  }
  const motion::MotionAsset& source = out.from_other ? out.other : out.asset;
  const std::string& source_name = out.from_other ? settings.clip : settings.rig;
  if (source.clips.empty())
    return Status::error(source_name + ": no motion to track (give --clip)");
  Result<int> clip_index = selectClip(source, settings.animation);
  if (!clip_index.ok()) return clip_index.status();
  out.clip_index = clip_index.value();
  return out;
}

}  // namespace sinew::app
