#include "cli/controller_file.h"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/target_io.h"

namespace sinew::app {

void BodyFlags::addTo(CLI::App& command) {
  command.add_option("--mass", masses, "Override a body's mass: NAME=KG (its joint's name); repeatable");
  command.add_option("--fixed", fixed, "Weld this joint (no motion); repeatable");
  command.add_option("--hinge-limits", hinge_limits,
                     "Override a hinge's range: NAME=LO,HI in degrees; repeatable");
}

Result<physics::BodyPlanSettings> BodyFlags::settings() const {
  return parseBodyOverrides(BodyOverrides{masses, fixed, hinge_limits});
}

Result<LoadedRig> loadRigAndTarget(const std::string& rig_path, const std::string& clip_path,
                                   const std::string& target_path, const std::string& animation,
                                   int harmonics, const ImportFlags& import, const BodyFlags& body,
                                   const std::map<std::string, int>& joint_k) {
  Result<physics::BodyPlanSettings> body_settings = body.settings();
  if (!body_settings.ok()) return body_settings.status();
  Result<motion::ImportOptions> options = import.options();
  if (!options.ok()) return options.status();
  Result<motion::MotionAsset> rig = motion::importMotion(rig_path, options.value());
  if (!rig.ok()) return rig.status();
  LoadedRig out;
  out.asset = std::move(rig).value();
  motion::MotionAsset other;
  const motion::MotionAsset* source = &out.asset;
  if (!clip_path.empty()) {
    Result<motion::MotionAsset> clip_asset = motion::importMotion(clip_path, options.value());
    if (!clip_asset.ok()) return clip_asset.status();
    other = std::move(clip_asset).value();
    if (other.skeleton.names != out.asset.skeleton.names)
      return Status::error(clip_path + ": its skeleton is not the rig's (" + rig_path +
                           "): the joints differ in names or order");
    if (other.skeleton.parents != out.asset.skeleton.parents)
      return Status::error(clip_path + ": its skeleton is not the rig's (" + rig_path +
                           "): the same joint names in another hierarchy");
    source = &other;
  }
  const std::string source_name = clip_path.empty() ? rig_path : clip_path;
  if (source->clips.empty()) return Status::error(source_name + ": no motion to track (give --clip)");
  Result<int> clip_index = selectClip(*source, animation);
  if (!clip_index.ok()) return clip_index.status();
  const motion::Clip& clip = source->clips[static_cast<size_t>(clip_index.value())];
  const motion::Skeleton& skeleton = out.asset.skeleton;
  Result<physics::BodyPlan> plan = physics::buildBodyPlan(skeleton, &clip, body_settings.value());
  if (!plan.ok()) return Status::error(rig_path + ": " + plan.message());
  out.plan = std::move(plan).value();
  if (!target_path.empty()) {
    // Coefficients written by `sinew style -o X.json` (or any edit): tracked as they are.
    std::vector<std::string> warnings;
    Result<spectral::TargetMotion> loaded = spectral::loadTarget(target_path, skeleton, &warnings);
    if (!loaded.ok()) return loaded.status();
    for (const std::string& warning : warnings)
      std::fprintf(stderr, "sinew: warning: %s\n", warning.c_str());
    out.target = std::move(loaded).value();
    out.what = target_path;
  } else {
    spectral::AnalysisSettings analysis;
    analysis.harmonics = harmonics;
    Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, clip, analysis);
    if (!spectrum.ok()) return Status::error(source_name + ": " + spectrum.message());
    std::vector<int> k_per_joint;
    if (!joint_k.empty()) {
      k_per_joint.assign(static_cast<size_t>(skeleton.jointCount()), harmonics);
      for (const auto& [name, k] : joint_k) {
        const int joint = skeleton.findJoint(name);
        if (joint < 0)
          return Status::error("joint_harmonics: " + rig_path + " has no joint called '" + name + "'");
        k_per_joint[static_cast<size_t>(joint)] = k;
      }
    }
    out.target = spectral::targetFromSpectrum(spectrum.value(), k_per_joint, clip.name);
    out.what = "'" + clip.name + "' (K = " + std::to_string(harmonics) +
               (joint_k.empty() ? ""
                                : ", " + std::to_string(joint_k.size()) +
                                      (joint_k.size() == 1 ? " joint" : " joints") + " with its own K") +
               ")";
  }
  return out;
}

}  // namespace sinew::app
