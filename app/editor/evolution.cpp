#include "editor/evolution.h"

#include <cstdio>

#include "editor/editor_state.h"
#include "sinew/physics/body_plan.h"
#include "sinew/search/controller_io.h"

namespace sinew::editor {
namespace {

std::string termsLine(const search::FitnessTerms& t) {
  char line[200];
  std::snprintf(line, sizeof line,
                "cost %.2f (fall %.1f, tracking %.2f, speed %.2f), up %.1f s, %.1f m", t.total,
                t.fall, t.tracking, t.speed, t.survived_s, t.distance_m);
  return t.fell && !t.fall_reason.empty() ? std::string(line) + " (fell: " + t.fall_reason + ")"
                                          : std::string(line);
}

}  // namespace

bool startEvolution(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) {
    state.log.error("evolve: open a clip that analyses first (the search starts from its model)");
    return false;
  }
  stopEvolution(state);
  const motion::Skeleton& skeleton = state.asset->skeleton;
  const EvolutionSettings& chosen = evolution.settings;
  Result<physics::BodyPlanSettings> body = app::parseBodyOverrides(chosen.body);
  if (!body.ok()) {
    state.log.error("evolve: body: " + body.message());
    return false;
  }
  Result<physics::BodyPlan> plan = physics::buildBodyPlan(skeleton, clip, body.value());
  if (!plan.ok()) {
    state.log.error("evolve: " + state.file_name + ": " + plan.message());
    return false;
  }
  Result<physics::SimulationSettings> simulation =
      app::simulationSettings(chosen.window_s, chosen.terrain, chosen.pushes, "terrain", "push");
  if (!simulation.ok()) {
    state.log.error("evolve: " + simulation.message());
    return false;
  }
  search::GenomeSettings genome;
  genome.no_prior = evolution.settings.no_prior;
  Result<search::Problem> problem =
      search::Problem::create(plan.value(), skeleton, state.analysis->target, genome,
                              simulation.value(), evolution.settings.weights);
  if (!problem.ok()) {
    state.log.error("evolve: " + problem.message());
    return false;
  }
  search::EvolveSettings settings;
  settings.generations = 0;
  settings.minutes = evolution.settings.minutes;
  settings.population = evolution.settings.population;
  settings.optimizer = chosen.optimizer;
  settings.seed = chosen.seed;
  settings.record_population = true;  // the viewport replays the population
  settings.nice = 10;  // the UI thread draws first; the search takes what the frames leave
  Result<std::unique_ptr<search::Session>> session =
      search::Session::create(std::move(problem).value(), settings);
  if (!session.ok()) {
    state.log.error("evolve: " + session.message());
    return false;
  }
  evolution.session = std::move(session).value();
  evolution.reported_generation = 0;
  evolution.selected = -1;
  evolution.snapshot = evolution.session->snapshot();
  evolution.session->start();
  char line[200];
  std::snprintf(
      line, sizeof line,
      "evolve: %d coordinates, %s, population %d, %.1f min, %.0f s window on %s, %s on %d threads",
      evolution.session->problem().layout.size(),
      chosen.optimizer == "ga" ? "genetic algorithm" : "CMA-ES", evolution.session->population(),
      settings.minutes, chosen.window_s, chosen.terrain.c_str(),
      genome.no_prior ? "no prior" : "seeded from the model", search::hardwareThreads());
  state.log.info(line);
  return true;
}

namespace {

std::string currentState(const EditorState& state) {
  return state.evolution.session ? state.evolution.session->snapshot()->state : "";
}

}  // namespace

void pauseEvolution(EditorState& state) {
  if (currentState(state) != "running") return;
  state.evolution.session->pause();
  state.log.info("evolve: paused");
}

void resumeEvolution(EditorState& state) {
  if (currentState(state) != "paused") return;
  state.evolution.session->resume();
  state.log.info("evolve: resumed");
}

void stopEvolution(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) return;
  const std::string was = currentState(state);
  evolution.session->stop();
  evolution.snapshot = evolution.session->snapshot();
  if (was == "running" || was == "paused") {
    state.log.info("evolve: stopped after generation " +
                   std::to_string(evolution.snapshot->generation));
  }
}

void setEvolutionWeights(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) return;
  evolution.session->setWeights(evolution.settings.weights);
  const int next = evolution.snapshot ? evolution.snapshot->generation + 1 : 1;
  state.log.info("evolve: new fitness weights from generation " + std::to_string(next));
}

void pollEvolution(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) return;
  evolution.snapshot = evolution.session->snapshot();
  const search::Snapshot& snap = *evolution.snapshot;
  for (; evolution.reported_generation < static_cast<int>(snap.history.size());
       ++evolution.reported_generation) {
    const search::GenerationRecord& r =
        snap.history[static_cast<size_t>(evolution.reported_generation)];
    char line[96];
    std::snprintf(line, sizeof line, "generation %d (%lld evaluations, %.0f s): best ",
                  r.generation, r.evaluations, r.wall_s);
    state.log.info(line + termsLine(snap.best_terms));
    evolution.selected = -1;  // its index would point at another individual now
  }
}

bool exportEvolutionBest(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session || !evolution.snapshot || evolution.snapshot->best_point.empty()) {
    state.log.error("export: no generation has finished yet");
    return false;
  }
  search::ControllerFile meta;
  meta.optimizer = evolution.session->settings().optimizer;
  meta.seed = evolution.session->settings().seed;
  meta.no_prior = evolution.settings.no_prior;
  meta.rig = state.file_path.string();
  meta.clip = state.file_path.string();
  const Status saved =
      search::exportBest(evolution.session->problem(), evolution.snapshot->best_point,
                         evolution.snapshot->best_terms, *state.asset, evolution.export_dir, meta);
  if (!saved.ok()) {
    state.log.error("export: " + saved.message());
    return false;
  }
  state.log.info("export: wrote best.json, best.bvh and best.glb to " + evolution.export_dir);
  return true;
}

}  // namespace sinew::editor
