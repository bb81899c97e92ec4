#include "sinew/search/controller_io.h"

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/spectral/target_io.h"

namespace sinew::search {

Status saveController(const std::filesystem::path& path, const ControllerFile& c,
                      const motion::Skeleton& skeleton) {
  const nlohmann::json json = {
      {"format", "sinew.controller"},
      {"version", 1},
      {"rig", c.rig},
      {"clip", c.clip},
      {"target", nlohmann::json::parse(spectral::targetToJson(c.target, skeleton))},
      {"balance",
       {{"cd_sagittal", c.balance.cd_sagittal},
        {"cv_sagittal", c.balance.cv_sagittal},
        {"cd_coronal", c.balance.cd_coronal},
        {"cv_coronal", c.balance.cv_coronal},
        {"torso", c.balance.torso}}},
      {"settings",
       {{"window_s", c.window_s},
        {"terrain", c.terrain},
        {"seed", c.seed},
        {"optimizer", c.optimizer},
        {"no_prior", c.no_prior}}},
      {"fitness", fitnessJson(c.fitness)}};
  return writeFileAtomically(path, json.dump(2) + "\n");
}

Result<ControllerFile> loadController(const std::filesystem::path& path,
                                      const motion::Skeleton& skeleton) {
  Result<std::string> text = readFile(path);
  if (!text.ok()) return text.status();
  const std::string name = path.string();
  try {
    const nlohmann::json json = nlohmann::json::parse(text.value());
    if (json.value("format", "") != "sinew.controller")
      return Status::error(name + ": format: expected \"sinew.controller\" (a best.json from "
                                  "sinew evolve)");
    if (json.at("version").get<int>() != 1)
      return Status::error(name + ": version: " + json.at("version").dump() + " is not 1");
    ControllerFile c;
    Result<spectral::TargetMotion> target =
        spectral::targetFromJson(json.at("target").dump(), skeleton, name + ": target");
    if (!target.ok()) return target.status();
    c.target = std::move(target).value();
    const nlohmann::json& b = json.at("balance");
    c.balance.cd_sagittal = b.at("cd_sagittal").get<double>();
    c.balance.cv_sagittal = b.at("cv_sagittal").get<double>();
    c.balance.cd_coronal = b.at("cd_coronal").get<double>();
    c.balance.cv_coronal = b.at("cv_coronal").get<double>();
    c.balance.torso = b.at("torso").get<double>();
    const nlohmann::json& s = json.at("settings");
    c.window_s = s.at("window_s").get<double>();
    c.terrain = s.at("terrain").get<std::string>();
    c.seed = s.at("seed").get<std::uint64_t>();
    c.optimizer = s.at("optimizer").get<std::string>();
    c.no_prior = s.at("no_prior").get<bool>();
    if (json.contains("fitness")) {
      Result<FitnessTerms> fitness = fitnessFromJson(json.at("fitness"));
      if (!fitness.ok()) return Status::error(name + ": fitness: " + fitness.message());
      c.fitness = fitness.value();
    }
    c.rig = json.value("rig", "");
    c.clip = json.value("clip", "");
    return c;
  } catch (const nlohmann::json::exception& e) {
    return Status::error(name + ": " + e.what());
  }
}

Status exportBest(const Problem& problem, std::span<const double> point, const FitnessTerms& fitness,
                  const motion::MotionAsset& rig, const std::filesystem::path& dir,
                  ControllerFile meta) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status::error(dir.string() + ": cannot create the folder: " + ec.message());
  meta.target = problem.layout.decodeTarget(point);
  meta.balance = problem.layout.decodeGains(point);
  meta.window_s = problem.simulation.seconds;
  meta.fitness = fitness;
  if (Status s = saveController(dir / "best.json", meta, rig.skeleton); !s.ok()) return s;
  const Evaluation replay = evaluate(problem, point, nullptr, true);
  for (const char* name : {"best.bvh", "best.glb"})
    if (Status s = motion::exportMotion(dir / name, rig, replay.report.motion); !s.ok()) return s;
  return Status();
}

}  // namespace sinew::search
