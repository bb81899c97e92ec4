#include "sinew/pipeline/pipeline.h"

#include <sstream>

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"

#include "sinew/spectral/analysis.h"
#include "sinew/spectral/bands.h"
#include "sinew/spectral/secondary.h"
#include "sinew/spectral/target_io.h"

namespace sinew::pipeline {

Result<std::vector<int>> resolveJointK(const motion::Skeleton& skeleton, int harmonics,
                                       const std::map<std::string, int>& joint_k,
                                       const std::string& rig) {
  std::vector<int> k(static_cast<size_t>(skeleton.jointCount()), harmonics);
  for (const auto& [name, value] : joint_k) {
    const int joint = skeleton.findJoint(name);
    if (joint < 0)
      return Status::error("joint_harmonics: " + rig + " has no joint called '" + name + "'");
    k[static_cast<size_t>(joint)] = value;
  }
  return k;
}

spectral::CycleSettings strideNear(double stride_s) {
  spectral::CycleSettings cycle;
  cycle.min_period_s = 0.75 * stride_s;
  cycle.max_period_s = 1.25 * stride_s;
  return cycle;
}

Result<spectral::TargetMotion> styleTarget(const motion::Skeleton& skeleton,
                                           const motion::Clip& clip, const std::string& name,
                                           double stride_hint_s) {
  spectral::AnalysisSettings settings;
  settings.harmonics = kStyleHarmonics;
  if (stride_hint_s > 0.0) settings.cycle = strideNear(stride_hint_s);
  Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, clip, settings);
  if (!spectrum.ok()) return Status::error(name + ": " + spectrum.message());
  return spectral::targetFromSpectrum(spectrum.value(), {}, clip.name);
}

Result<spectral::TargetMotion> styleClipTarget(const std::string& path,
                                               const motion::Skeleton& skeleton) {
  Result<motion::MotionAsset> asset = motion::importMotion(path);
  if (!asset.ok()) return asset.status();
  if (asset.value().clips.empty()) return Status::error(path + ": no animation");
  if (asset.value().skeleton.names != skeleton.names)
    return Status::error(path + ": its skeleton is not the open clip's (the joints differ)");
  return styleTarget(asset.value().skeleton, asset.value().clips.front(), path);
}

Result<spectral::StyleVector> measureStylePair(const StylePair& pair,
                                               const motion::Skeleton& skeleton) {
  Result<spectral::TargetMotion> neutral = styleClipTarget(pair.neutral, skeleton);
  if (!neutral.ok()) return neutral.status();
  Result<spectral::TargetMotion> styled = styleClipTarget(pair.styled, skeleton);
  if (!styled.ok()) return styled.status();
  return spectral::measureStyle(neutral.value(), styled.value(), pair.label);
}

Result<spectral::TargetMotion> applyMotionEdits(
    const spectral::TargetMotion& model, const motion::Skeleton& skeleton, const MotionEdits& edits,
    const std::vector<const spectral::StyleVector*>& styles) {
  spectral::TargetMotion target = model;
  if (edits.band_gains != MotionEdits().band_gains) {
    spectral::BandGains gains;
    for (size_t b = 0; b < gains.gains.size() && b < edits.band_gains.size(); ++b) {
      for (size_t g = 0; g < gains.gains[b].size(); ++g) gains.gains[b][g] = edits.band_gains[b][g];
    }
    if (Status valid = gains.validate(); !valid.ok())
      return Status::error("band_gains: " + valid.message());
    target = spectral::applyBandGains(target, skeleton, gains);
  }
  std::vector<std::pair<const spectral::StyleVector*, double>> weighted;
  for (size_t i = 0; i < edits.styles.size() && i < styles.size(); ++i) {
    if (styles[i] != nullptr && edits.styles[i].weight != 0.0)
      weighted.emplace_back(styles[i], edits.styles[i].weight);
  }
  if (!weighted.empty()) {
    Result<spectral::TargetMotion> styled = spectral::applyStyles(target, weighted);
    if (!styled.ok()) return Status::error("styles: " + styled.message());
    target = std::move(styled).value();
  }
  if (!edits.secondary.empty()) {
    spectral::SecondarySettings settings;
    for (const SecondaryMotion& m : edits.secondary) {
      spectral::SecondarySource source;
      source.kind = m.noise ? spectral::SecondarySource::Kind::kNoise
                            : spectral::SecondarySource::Kind::kPeriodic;
      source.joint = m.joint;
      source.axis = m.axis;
      source.frequency_hz = m.frequency_hz;
      source.amplitude_deg = m.amplitude_deg;
      source.seed = m.seed;
      settings.sources.push_back(source);
    }
    Result<spectral::TargetMotion> moved = spectral::addSecondaryMotion(target, skeleton, settings);
    if (!moved.ok()) return Status::error("secondary: " + moved.message());
    target = std::move(moved).value();
  }
  return target;
}

Result<TrackedMotion> trackedMotion(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                    const ProjectSettings& settings,
                                    const std::vector<const spectral::StyleVector*>* styles) {
  TrackedMotion out;
  if (!settings.target.empty()) {
    // Coefficients written by `sinew style -o X.json` (or any edit): tracked as they are.
    Result<spectral::TargetMotion> loaded = spectral::loadTarget(settings.target, skeleton);
    if (!loaded.ok()) return loaded.status();
    out.target = std::move(loaded).value();
    out.what = settings.target;
    return out;
  }
  const std::string source = settings.clip.empty() ? settings.rig : settings.clip;
  Result<std::vector<int>> k =
      resolveJointK(skeleton, settings.harmonics, settings.joint_k, settings.rig);
  if (!k.ok()) return k.status();
  spectral::AnalysisSettings analysis;
  analysis.harmonics = settings.harmonics;
  Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, clip, analysis);
  if (!spectrum.ok()) return Status::error(source + ": " + spectrum.message());
  out.target = spectral::targetFromSpectrum(spectrum.value(), k.value(), clip.name);
  const size_t own = settings.joint_k.size();
  out.what = "'" + clip.name + "' (K = " + std::to_string(settings.harmonics) +
             (own == 0 ? ""
                       : ", " + std::to_string(own) + (own == 1 ? " joint" : " joints") +
                             " with its own K") +
             ")";
  if (settings.edits.empty()) return out;
  // The project's edits of the model, as the editor shows them.
  std::vector<spectral::StyleVector> measured;
  std::vector<const spectral::StyleVector*> given;
  if (styles == nullptr) {
    measured.reserve(settings.edits.styles.size());
    for (const StylePair& pair : settings.edits.styles) {
      Result<spectral::StyleVector> style = measureStylePair(pair, skeleton);
      if (!style.ok()) return Status::error("style '" + pair.label + "': " + style.message());
      measured.push_back(std::move(style).value());
    }
    for (const spectral::StyleVector& style : measured) given.push_back(&style);
    styles = &given;
  }
  for (size_t i = 0; i < settings.edits.styles.size(); ++i) {
    if (i >= styles->size() || (*styles)[i] == nullptr)
      return Status::error("style '" + settings.edits.styles[i].label + "': not measured");
  }
  Result<spectral::TargetMotion> edited =
      applyMotionEdits(out.target, skeleton, settings.edits, *styles);
  if (!edited.ok()) return edited.status();
  out.target = std::move(edited).value();
  out.what += " with the project's edits";
  return out;
}

const char* trackedName(const ProjectSettings& settings) {
  if (!settings.target.empty()) return "the coefficients";
  return settings.edits.empty() ? "the clip" : "the edited clip";
}

Result<physics::BodyPlan> bodyPlan(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                   const BodyOverrides& body, const std::string& rig) {
  Result<physics::BodyPlanSettings> settings = body.planSettings();
  if (!settings.ok()) return Status::error("body: " + settings.message());
  Result<physics::BodyPlan> plan = physics::buildBodyPlan(skeleton, &clip, settings.value());
  if (!plan.ok()) return Status::error(rig + ": " + plan.message());
  return plan;
}

physics::SimulationSettings simulationSettings(const PhysicsSettings& physics) {
  physics::SimulationSettings simulation;
  simulation.seconds = physics.window_s;
  simulation.world.terrain = physics.terrain;
  simulation.pushes = physics.pushes;
  simulation.tracking.servo_lead_s =
      physics::servoLag(simulation.world.step_hz, simulation.tracking.servo_rate);
  simulation.tracking.lead_yielding_legs = true;
  return simulation;
}

search::EvolveSettings evolveSettings(const SearchSettings& search) {
  search::EvolveSettings settings;
  settings.optimizer = search.optimizer;
  settings.population = search.population;
  settings.generations = 0;
  settings.minutes = search.minutes;
  settings.seed = search.seed;
  settings.restart_after = search.restart_after;
  settings.start_generations = search.start_generations;
  return settings;
}

Result<SearchSetup> prepareSearch(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                  const ProjectSettings& settings,
                                  const std::vector<const spectral::StyleVector*>* styles) {
  if (Status valid = settings.validate(); !valid.ok()) return valid;
  Result<TrackedMotion> tracked = trackedMotion(skeleton, clip, settings, styles);
  if (!tracked.ok()) return tracked.status();
  Result<physics::BodyPlan> plan = bodyPlan(skeleton, clip, settings.physics.body, settings.rig);
  if (!plan.ok()) return plan.status();
  search::GenomeSettings genome;
  genome.no_prior = settings.search.no_prior;
  Result<search::Problem> problem =
      search::Problem::create(plan.value(), skeleton, tracked.value().target, genome,
                              simulationSettings(settings.physics), settings.search.weights);
  if (!problem.ok()) return problem.status();
  if (Status s = search::setTrials(problem.value(), settings.search.trials,
                                   settings.search.trial_push_m_s);
      !s.ok())
    return s;
  if (Status s = search::addRobustPushes(problem.value(), settings.search.robust_push_m_s); !s.ok())
    return s;
  return SearchSetup{std::move(problem).value(), std::move(tracked.value().what)};
}

std::string historyCsv(const search::Snapshot& snapshot) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "generation,evaluations,wall_s,total_best,total_mean,total_worst";
  for (int k = 0; k < search::kFitnessTermCount; ++k) {
    const std::string n = search::fitnessTermName(k);
    csv << ',' << n << "_best," << n << "_mean," << n << "_worst";
  }
  csv << ",best_survived_s,best_distance_m,scored,diverged\n";
  for (const search::GenerationRecord& r : snapshot.history) {
    csv << r.generation << ',' << r.evaluations << ',' << r.wall_s;
    if (r.scored == 0) {  // nothing scored: empty cells, not inf or nan
      csv << std::string(3 * (search::kFitnessTermCount + 1) + 2, ',');
    } else {
      csv << ',' << r.total.best << ',' << r.total.mean << ',' << r.total.worst;
      for (const search::TermStats& t : r.terms)
        csv << ',' << t.best << ',' << t.mean << ',' << t.worst;
      csv << ',' << r.best_survived_s << ',' << r.best_distance_m;
    }
    csv << ',' << r.scored << ',' << r.diverged << '\n';
  }
  return csv.str();
}

Status writeCheckpoint(const search::Session& session, const nlohmann::json& problem,
                       const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status::error(dir.string() + ": cannot create the output folder: " + ec.message());
  const auto snapshot = session.snapshot();
  nlohmann::json saved_state = session.checkpoint();
  saved_state["problem"] = problem;
  const std::string text =
      saved_state.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  if (Status s = writeFileAtomically(dir / "checkpoint.json", text); !s.ok()) return s;
  return writeFileAtomically(dir / "history.csv", historyCsv(*snapshot));
}

Result<bool> writeSearchResults(const search::Session& session, const motion::MotionAsset& rig,
                                const nlohmann::json& problem, const search::ControllerFile& meta,
                                const std::filesystem::path& dir) {
  if (Status s = writeCheckpoint(session, problem, dir); !s.ok()) return s;
  const auto snapshot = session.snapshot();
  if (snapshot->best_point.empty()) return false;
  if (Status s = search::exportBest(session.problem(), snapshot->best_point, snapshot->best_terms,
                                    rig, dir, meta);
      !s.ok())
    return s;
  return true;
}

}  // namespace sinew::pipeline
