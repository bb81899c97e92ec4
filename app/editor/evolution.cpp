#include "editor/evolution.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "editor/editor_state.h"
#include "editor/project_model.h"
#include "sinew/pipeline/physical_loop.h"
#include "sinew/pipeline/pipeline.h"
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

// The search `project` describes on the loaded clip, with the Style panel's measured styles.
Result<pipeline::SearchSetup> prepareEditorSearch(EditorState& state, const app::Project& project) {
  std::vector<const spectral::StyleVector*> styles;
  for (const app::StylePair& pair : project.edits.styles) {
    const Result<spectral::StyleVector>& style = styleOf(state, pair);
    if (!style.ok()) return Status::error("style '" + pair.label + "': " + style.message());
    styles.push_back(&style.value());
  }
  return pipeline::prepareSearch(state.asset->skeleton, *state.clip(), project, &styles);
}

}  // namespace

int editorSearchThreads() {
  return std::max(search::hardwareThreads() - 1, 1);
}

void resolvePopulation(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (state.clip() == nullptr || !state.analysis) {
    evolution.resolved_key.clear();
    evolution.resolved_population = evolution.resolved_coordinates = 0;
    return;
  }
  const app::Project project = captureProject(state);
  std::string key = app::settingsJson(project);
  if (key == evolution.resolved_key) return;
  evolution.resolved_key = std::move(key);
  evolution.resolved_population = evolution.resolved_coordinates = 0;
  Result<pipeline::SearchSetup> setup = prepareEditorSearch(state, project);
  if (!setup.ok()) return;
  evolution.resolved_coordinates = setup.value().problem.layout.size();
  Result<std::unique_ptr<search::Session>> session = search::Session::create(
      std::move(setup.value().problem), pipeline::evolveSettings(project.search));
  if (session.ok()) evolution.resolved_population = session.value()->population();
}

bool startEvolution(EditorState& state, int generations) {
  EvolutionState& evolution = state.evolution;
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) {
    state.log.error("evolve: open a clip that analyses first (the search starts from its model)");
    return false;
  }
  stopEvolution(state);
  // The project as it is now, through the engine's one path to a search (as `sinew evolve`).
  const app::Project project = captureProject(state);
  Result<pipeline::SearchSetup> setup = prepareEditorSearch(state, project);
  if (!setup.ok()) {
    state.log.error("evolve: " + setup.message());
    return false;
  }
  search::EvolveSettings settings = pipeline::evolveSettings(project.search);
  if (generations > 0) {
    settings.generations = generations;
    settings.minutes = 0.0;
  } else {
    settings.generations = std::max(evolution.settings.generations, 0);
  }
  settings.record_population = true;  // the viewport replays the population
  settings.nice = 10;  // the UI thread draws first; the search takes what the frames leave
  settings.threads = std::max(evolution.threads, 0);
  Result<std::unique_ptr<search::Session>> session =
      search::Session::create(std::move(setup.value().problem), settings);
  if (!session.ok()) {
    state.log.error("evolve: " + session.message());
    return false;
  }
  evolution.session = std::move(session).value();
  evolution.started = project;
  evolution.reported_generation = 0;
  evolution.selected = -1;
  evolution.longest_poll_wait_s = evolution.poll_wait_s = 0.0;
  evolution.slow_polls = 0;
  evolution.snapshot = evolution.session->snapshot();
  evolution.session->start();
  const std::string budget = budgetText(settings);
  char line[320];
  std::snprintf(line, sizeof line,
                "evolve %s: %d coordinates, %s, population %d, %s, %.0f s window on %s, %s on %d "
                "of %d threads",
                setup.value().what.c_str(), evolution.session->problem().layout.size(),
                settings.optimizer == search::OptimizerKind::kGa ? "genetic algorithm" : "CMA-ES",
                evolution.session->population(), budget.c_str(), project.physics.window_s,
                app::terrainText(project.physics.terrain).c_str(),
                project.search.no_prior ? "no prior" : "seeded from the model",
                settings.threads > 0 ? settings.threads : search::hardwareThreads(),
                search::hardwareThreads());
  state.log.info(line);
  return true;
}

std::string budgetText(const search::EvolveSettings& settings) {
  char budget[64];
  if (settings.minutes <= 0.0)
    std::snprintf(budget, sizeof budget, "%d generations", settings.generations);
  else if (settings.generations > 0)
    std::snprintf(budget, sizeof budget, "%.1f min or %d generations", settings.minutes,
                  settings.generations);
  else
    std::snprintf(budget, sizeof budget, "%.1f min", settings.minutes);
  return budget;
}

int chosenIndividual(const EvolutionState& evolution) {
  if (!evolution.snapshot) return -1;
  const search::Snapshot& snap = *evolution.snapshot;
  const size_t runs = std::min(snap.population_motions.size(), snap.population_terms.size());
  if (runs == 0) return -1;
  if (evolution.selected >= 0 && static_cast<size_t>(evolution.selected) < runs)
    return evolution.selected;
  size_t best = 0;  // the first of the lowest, as the viewport's stable sort ranks them
  for (size_t i = 1; i < runs; ++i) {
    if (snap.population_terms[i].total < snap.population_terms[best].total) best = i;
  }
  return static_cast<int>(best);
}

void selectIndividual(EvolutionState& evolution, int individual) {
  const size_t runs = evolution.snapshot ? evolution.snapshot->population_terms.size() : 0;
  evolution.selected = individual >= 0 && static_cast<size_t>(individual) < runs ? individual : -1;
}

std::vector<int> rankedIndividuals(const search::Snapshot& snap) {
  std::vector<int> order(snap.population_terms.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return snap.population_terms[static_cast<size_t>(a)].total <
           snap.population_terms[static_cast<size_t>(b)].total;
  });
  return order;
}

int individualRank(const search::Snapshot& snap, int individual) {
  const std::vector<int> order = rankedIndividuals(snap);
  const auto at = std::find(order.begin(), order.end(), individual);
  return at == order.end() ? 0 : static_cast<int>(at - order.begin()) + 1;
}

std::string chosenRunLabel(const EvolutionState& evolution) {
  const int chosen = chosenIndividual(evolution);
  if (chosen < 0) return "";
  char label[64];
  std::snprintf(label, sizeof label, "#%d of %zu (%s)", individualRank(*evolution.snapshot, chosen),
                evolution.snapshot->population_terms.size(),
                chosen == evolution.selected ? "clicked" : "best");
  return label;
}

std::optional<ExportedRun> exportedRun(const EvolutionState& evolution) {
  if (!evolution.snapshot || evolution.snapshot->best_point.empty()) return std::nullopt;
  const search::Snapshot& snap = *evolution.snapshot;
  const int i = evolution.selected;
  if (i < 0 || static_cast<size_t>(i) >= snap.population.size() ||
      static_cast<size_t>(i) >= snap.population_terms.size())
    return ExportedRun{snap.best_point, snap.best_terms, evolution.export_dir, "the best so far"};
  char folder[64], what[96];
  std::snprintf(folder, sizeof folder, "generation_%d_individual_%d", snap.generation, i);
  std::snprintf(what, sizeof what, "individual %d of generation %d (#%d of %zu)", i,
                snap.generation, individualRank(snap, i), snap.population_terms.size());
  return ExportedRun{snap.population[static_cast<size_t>(i)],
                     snap.population_terms[static_cast<size_t>(i)],
                     std::filesystem::path(evolution.export_dir) / folder, what};
}

search::SessionState evolutionState(const EditorState& state) {
  return state.evolution.session ? state.evolution.session->snapshot()->state
                                 : search::SessionState::kReady;
}

void pauseEvolution(EditorState& state) {
  if (evolutionState(state) != search::SessionState::kRunning) return;
  state.evolution.session->pause();
  state.log.info("evolve: paused");
}

void resumeEvolution(EditorState& state) {
  if (evolutionState(state) != search::SessionState::kPaused) return;
  state.evolution.session->resume();
  state.log.info("evolve: resumed");
}

void stopEvolution(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) return;
  const search::SessionState was = evolutionState(state);
  evolution.session->stop();
  evolution.snapshot = evolution.session->snapshot();
  if (search::underWay(was)) {
    state.log.info("evolve: stopped after generation " +
                   std::to_string(evolution.snapshot->generation));
  }
}

void setEvolutionWeights(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) return;
  evolution.session->setWeights(evolution.settings.search.weights);
  const int next = evolution.snapshot ? evolution.snapshot->generation + 1 : 1;
  state.log.info("evolve: new fitness weights from generation " + std::to_string(next));
}

void pollEvolution(EditorState& state) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) return;
  const auto asked = std::chrono::steady_clock::now();
  std::shared_ptr<const search::Snapshot> latest = evolution.session->snapshot();
  evolution.poll_wait_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
  evolution.longest_poll_wait_s = std::max(evolution.longest_poll_wait_s, evolution.poll_wait_s);
  if (evolution.poll_wait_s > kSlowPoll_s) ++evolution.slow_polls;
  evolution.snapshot = std::move(latest);
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
  const std::optional<ExportedRun> run = exportedRun(evolution);
  if (!evolution.session || !run) {
    state.log.error("export: no generation has finished yet");
    return false;
  }
  const Status saved = search::exportBest(
      evolution.session->problem(), run->point, run->terms, *state.asset, run->dir,
      app::resultsMeta(evolution.started, evolution.session->settings()));
  if (!saved.ok()) {
    state.log.error("export: " + saved.message());
    return false;
  }
  state.log.info("export: wrote " + run->what + " as best.json, best.bvh and best.glb to " +
                 run->dir.string());
  return true;
}

bool exportEvolutionLoop(EditorState& state, int strides, bool in_place) {
  EvolutionState& evolution = state.evolution;
  const std::optional<ExportedRun> run = exportedRun(evolution);
  if (!evolution.session || !run) {
    state.log.error("export: no generation has finished yet");
    return false;
  }
  pipeline::LoopSettings settings;
  settings.strides = strides;
  settings.in_place = in_place;
  const search::Problem& problem = evolution.session->problem();
  Result<pipeline::LoopFiles> files =
      pipeline::writeLoopFiles(problem, pipeline::replayBest(problem, run->point),
                               evolution.started.edits, *state.asset, settings, run->dir);
  if (!files.ok()) {
    state.log.error("export: " + files.message());
    return false;
  }
  const pipeline::PhysicalLoop& loop = files.value().loop;
  char line[512];
  std::snprintf(line, sizeof line,
                "export: wrote %s as best_loop.bvh, best_loop.glb and loop.json to %s: %d "
                "strides of %.3f s, foot slide %.2f -> %.2f cm per contact",
                run->what.c_str(), run->dir.string().c_str(), loop.strides, loop.period_s,
                loop.slideBeforeMeanCm(), loop.slideAfterMeanCm());
  state.log.info(line);
  for (const std::string& style : files.value().style.lines())
    state.log.info("loop style " + style);
  return true;
}

bool exportEvolutionResults(EditorState& state, const std::filesystem::path& dir) {
  EvolutionState& evolution = state.evolution;
  if (!evolution.session) {
    state.log.error("export: no search has run");
    return false;
  }
  Result<bool> wrote = pipeline::writeSearchResults(
      *evolution.session, *state.asset, nlohmann::json::parse(app::settingsJson(evolution.started)),
      app::resultsMeta(evolution.started, evolution.session->settings()), dir);
  if (!wrote.ok()) {
    state.log.error("export: " + wrote.message());
    return false;
  }
  state.log.info("export: wrote checkpoint.json, history.csv" +
                 std::string(wrote.value() ? ", best.json, best.bvh and best.glb" : "") + " to " +
                 dir.string());
  return true;
}

}  // namespace sinew::editor
