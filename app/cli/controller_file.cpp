#include "cli/controller_file.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/target_io.h"

namespace sinew::app {

Result<LoadedRig> loadRigAndTarget(const std::string& rig_path, const std::string& clip_path,
                                   const std::string& target_path, const std::string& animation,
                                   int harmonics, const ImportFlags& import) {
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
    source = &other;
  }
  const std::string source_name = clip_path.empty() ? rig_path : clip_path;
  if (source->clips.empty()) return Status::error(source_name + ": no motion to track (give --clip)");
  Result<int> clip_index = selectClip(*source, animation);
  if (!clip_index.ok()) return clip_index.status();
  const motion::Clip& clip = source->clips[static_cast<size_t>(clip_index.value())];
  const motion::Skeleton& skeleton = out.asset.skeleton;
  Result<physics::BodyPlan> plan = physics::buildBodyPlan(skeleton, &clip);
  if (!plan.ok()) return Status::error(rig_path + ": " + plan.message());
  out.plan = std::move(plan).value();
  if (!target_path.empty()) {
    // Coefficients written by `sinew style -o X.json` (or any edit): tracked as they are.
    Result<spectral::TargetMotion> loaded = spectral::loadTarget(target_path, skeleton);
    if (!loaded.ok()) return loaded.status();
    out.target = std::move(loaded).value();
    out.what = target_path;
  } else {
    spectral::AnalysisSettings analysis;
    analysis.harmonics = harmonics;
    Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, clip, analysis);
    if (!spectrum.ok()) return Status::error(source_name + ": " + spectrum.message());
    out.target = spectral::targetFromSpectrum(spectrum.value(), {}, clip.name);
    out.what = "'" + clip.name + "' (K = " + std::to_string(harmonics) + ")";
  }
  return out;
}

// "slope:5", "steps:0.05,0.6", "rough:0.02,7", "flat".
Result<physics::TerrainSettings> parseTerrain(const std::string& text) {
  physics::TerrainSettings t;
  const size_t colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  std::vector<double> values;
  if (colon != std::string::npos) {
    std::stringstream in(text.substr(colon + 1));
    std::string item;
    while (std::getline(in, item, ',')) {
      try {
        size_t used = 0;
        values.push_back(std::stod(item, &used));
        if (used != item.size()) throw std::invalid_argument(item);
      } catch (const std::exception&) {
        return Status::error("--terrain: '" + item + "' is not a number (in '" + text + "')");
      }
    }
  }
  auto want = [&](size_t most) -> Status {
    if (values.size() > most)
      return Status::error("--terrain " + kind + ": at most " + std::to_string(most) +
                           " values, got " + std::to_string(values.size()));
    return Status();
  };
  using Kind = physics::TerrainSettings::Kind;
  if (kind == "flat") {
    if (Status s = want(0); !s.ok()) return s;
  } else if (kind == "slope") {
    if (Status s = want(1); !s.ok()) return s;
    t.kind = Kind::kSlope;
    if (!values.empty()) t.slope_deg = values[0];
  } else if (kind == "steps") {
    if (Status s = want(2); !s.ok()) return s;
    t.kind = Kind::kSteps;
    if (values.size() > 0) t.step_height_m = values[0];
    if (values.size() > 1) t.step_depth_m = values[1];
  } else if (kind == "rough") {
    if (Status s = want(2); !s.ok()) return s;
    t.kind = Kind::kRough;
    if (values.size() > 0) t.amplitude_m = values[0];
    if (values.size() > 1) {
      if (values[1] < 0.0 || values[1] != static_cast<double>(static_cast<std::uint64_t>(values[1])))
        return Status::error("--terrain rough: the seed must be a whole number >= 0");
      t.seed = static_cast<std::uint64_t>(values[1]);
    }
  } else {
    return Status::error("--terrain: unknown kind '" + kind +
                         "' (flat, slope:DEG, steps:HEIGHT,DEPTH, rough:AMPLITUDE,SEED)");
  }
  if (Status s = t.validate(); !s.ok()) return Status::error("--terrain: " + s.message());
  return t;
}

// "TIME,X,Y,Z[,LINK]": seconds, N s (world, Y up), and a joint name (the base when left out).
Result<physics::Push> parsePush(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) parts.push_back(item);
  if (parts.size() != 4 && parts.size() != 5)
    return Status::error("--push '" + text + "': expected TIME,X,Y,Z[,LINK] (seconds, N s)");
  double v[4];
  for (size_t i = 0; i < 4; ++i) {
    try {
      size_t used = 0;
      v[i] = std::stod(parts[i], &used);
      if (used != parts[i].size()) throw std::invalid_argument(parts[i]);
    } catch (const std::exception&) {
      return Status::error("--push '" + text + "': '" + parts[i] + "' is not a number");
    }
  }
  physics::Push push;
  push.time_s = v[0];
  push.impulse_ns = glm::dvec3(v[1], v[2], v[3]);
  if (parts.size() == 5) push.link = parts[4];
  return push;
}


}  // namespace sinew::app
