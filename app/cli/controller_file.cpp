#include "cli/controller_file.h"

#include <sstream>

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
  physics::BodyPlanSettings s;
  auto split = [](const std::string& text, const char* flag) -> Result<std::pair<std::string, std::string>> {
    const size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
      return Status::error(std::string(flag) + " '" + text + "': expected NAME=VALUE");
    return std::make_pair(text.substr(0, eq), text.substr(eq + 1));
  };
  auto number = [](const std::string& text, const std::string& whole, const char* flag) -> Result<double> {
    try {
      size_t used = 0;
      const double v = std::stod(text, &used);
      if (used != text.size()) throw std::invalid_argument(text);
      return v;
    } catch (const std::exception&) {
      return Status::error(std::string(flag) + " '" + whole + "': '" + text + "' is not a number");
    }
  };
  for (const std::string& m : masses) {
    auto parts = split(m, "--mass");
    if (!parts.ok()) return parts.status();
    Result<double> kg = number(parts.value().second, m, "--mass");
    if (!kg.ok()) return kg.status();
    s.mass_overrides.emplace_back(parts.value().first, kg.value());
  }
  for (const std::string& f : fixed) s.type_overrides.emplace_back(f, physics::JointType::kFixed);
  for (const std::string& h : hinge_limits) {
    auto parts = split(h, "--hinge-limits");
    if (!parts.ok()) return parts.status();
    const std::string& range = parts.value().second;
    const size_t comma = range.find(',');
    if (comma == std::string::npos) return Status::error("--hinge-limits '" + h + "': expected NAME=LO,HI");
    Result<double> lo = number(range.substr(0, comma), h, "--hinge-limits");
    Result<double> hi = number(range.substr(comma + 1), h, "--hinge-limits");
    if (!lo.ok()) return lo.status();
    if (!hi.ok()) return hi.status();
    constexpr double kRad = 3.14159265358979323846 / 180.0;
    s.hinge_limit_overrides.emplace_back(parts.value().first,
                                         std::make_pair(lo.value() * kRad, hi.value() * kRad));
  }
  if (Status v = s.validate(); !v.ok()) return Status::error("body overrides: " + v.message());
  return s;
}

Result<ProjectFile> loadProject(const std::filesystem::path& path) {
  Result<std::string> text = readFile(path);
  if (!text.ok()) return text.status();
  const std::string name = path.string();
  try {
    const nlohmann::json json = nlohmann::json::parse(text.value());
    if (json.value("format", "") != "sinew.project")
      return Status::error(name + ": format: expected \"sinew.project\"");
    if (json.value("version", 0) != 1)
      return Status::error(name + ": version: expected 1");
    const std::filesystem::path base = path.parent_path();
    auto file = [&](const char* key) -> std::string {
      const std::string value = json.value(key, "");
      if (value.empty()) return value;
      const std::filesystem::path p(value);
      return (p.is_absolute() ? p : base / p).lexically_normal().string();
    };
    ProjectFile project;
    if (!json.contains("rig")) return Status::error(name + ": rig: missing (the rig file)");
    project.rig = file("rig");
    project.clip = file("clip");
    project.target = file("target");
    project.animation = json.value("animation", "");
    project.harmonics = json.value("harmonics", 5);
    if (project.harmonics < 1 || project.harmonics > 64)
      return Status::error(name + ": harmonics: must be 1..64");
    project.terrain = json.value("terrain", "flat");
    project.window_s = json.value("window_s", 10.0);
    if (!(project.window_s >= 0.5 && project.window_s <= 600.0))
      return Status::error(name + ": window_s: must be 0.5..600 seconds");
    project.pushes = json.value("pushes", std::vector<std::string>{});
    if (json.contains("body")) {
      const nlohmann::json& body = json.at("body");
      project.body.masses = body.value("masses", std::vector<std::string>{});
      project.body.fixed = body.value("fixed", std::vector<std::string>{});
      project.body.hinge_limits = body.value("hinge_limits", std::vector<std::string>{});
    }
    return project;
  } catch (const nlohmann::json::exception& e) {
    return Status::error(name + ": " + e.what());
  }
}

Result<LoadedRig> loadRigAndTarget(const std::string& rig_path, const std::string& clip_path,
                                   const std::string& target_path, const std::string& animation,
                                   int harmonics, const ImportFlags& import, const BodyFlags& body) {
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
