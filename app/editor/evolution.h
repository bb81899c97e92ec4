// The editor's evolution: a search session (sinew::search::Session, on its own thread) over the
// loaded rig, seeded from the model the user is editing (the K per joint of the Spectrum panel),
// polled each frame for its latest snapshot. Plain model code, no ImGui: the Evolve panel and
// the viewport read it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "project/project.h"
#include "sinew/search/session.h"

namespace sinew::editor {

struct EditorState;

// The Evolve and Body panels' settings: the engine's structs, which the project saves as they are.
struct EvolutionSettings {
  pipeline::PhysicsSettings physics;  // window, terrain, pushes, body overrides
  pipeline::SearchSettings search;    // budget, population, optimiser, seed, weights (the weights
                                      // are live while a search runs)
  int shown = 8;                      // individuals drawn in the viewport, best first
  int generations = 0;  // budget in generations beside the minutes (whichever ends first); 0:
                        // the minutes only. Not a project setting (`sinew evolve --generations`)
};

struct EvolutionState {
  EvolutionSettings settings;
  std::unique_ptr<search::Session> session;
  pipeline::ProjectSettings started;  // what the session was built from (its results record it)
  std::shared_ptr<const search::Snapshot> snapshot;  // the latest published
  int reported_generation = 0;                       // the last generation written to the log
  bool show_population = true;                       // draw the population's runs beside the clip
  bool show_ghost = true;  // the search's target drawn over the chosen run (ghost.h)
  int threads = 0;         // evaluation threads of the next search, 0: every core (the window
                           // sets editorSearchThreads(); headless runs keep every core)
  int selected = -1;       // the individual clicked (in the viewport or the Evolve panel's list;
                           // index in the snapshot's population), -1 for none: the one selection
                           // every panel reads through chosenIndividual; cleared when a new
                           // generation arrives
  std::string export_dir;  // where "Export best" writes; default beside the opened file
  // How long pollEvolution waited for the session's snapshot (its lock), seconds: the last
  // call, the longest since the search started, and the polls that took over kSlowPoll_s.
  double poll_wait_s = 0.0;
  double longest_poll_wait_s = 0.0;
  int slow_polls = 0;
  // The population the next search will use and its coordinates (resolvePopulation), for the
  // project whose settings JSON is resolved_key; 0 when it cannot be built.
  std::string resolved_key;
  int resolved_population = 0;
  int resolved_coordinates = 0;
};

// A poll of the snapshot that takes longer than this waited on the search (the lock is held
// for a pointer copy, well under a microsecond, when nothing else holds it).
inline constexpr double kSlowPoll_s = 0.05;

// The evaluation threads an editor's search takes: one fewer than the cores (at least one), so
// that the UI thread and the GL driver keep a core while the window draws; `sinew evolve` keeps
// them all.
int editorSearchThreads();

// Resolves the population a search started now would use ("0: the optimiser's default" made a
// number: CMA-ES 4 + 3 ln n of the controller's n coordinates) into resolved_population, building
// the search's problem again only when the project changed since the last call.
void resolvePopulation(EditorState& state);

// Starts a search on the loaded clip with the project as the editor has it now (captureProject),
// through the engine's pipeline::prepareSearch, as `sinew evolve PROJECT` does; says in the log
// why not when it cannot (nothing loaded, no analysis, a plan that does not build). Replaces a
// running search. `generations` > 0: that budget instead of the settings' minutes; else the
// settings' minutes and their `generations` (when > 0), whichever ends first.
bool startEvolution(EditorState& state, int generations = 0);
void pauseEvolution(EditorState& state);
void resumeEvolution(EditorState& state);
void stopEvolution(EditorState& state);  // within one simulation step; keeps the snapshot
// Hands the settings' weights to the running search (from its next generation; logged).
void setEvolutionWeights(EditorState& state);
// Takes the session's latest snapshot and logs each finished generation. Call once per frame.
void pollEvolution(EditorState& state);
// The run Export writes: the clicked individual of the last generation when one is clicked (into
// the subfolder "generation_G_individual_I" of evolution.export_dir, so its files, named as
// `sinew evolve` names them, do not pass for the search's best), else the best so far (into
// export_dir itself). Empty before the first generation.
struct ExportedRun {
  std::vector<double> point;  // the genome
  search::FitnessTerms terms;
  std::filesystem::path dir;
  std::string what;  // "the best so far" or "individual 3 of generation 2 (#4 of 23)"
};
std::optional<ExportedRun> exportedRun(const EvolutionState& evolution);
// Writes best.json, best.bvh and best.glb of exportedRun into its folder.
bool exportEvolutionBest(EditorState& state);
// Writes exportedRun as a loop (best_loop.bvh, best_loop.glb, loop.json: what `sinew evolve
// --loop-strides N [--in-place]` writes) into evolution.export_dir; logs the loop's figures, or
// why there is none (a run that fell in its first strides).
bool exportEvolutionLoop(EditorState& state, int strides, bool in_place);
// Writes what `sinew evolve PROJECT --out DIR` writes (checkpoint.json, history.csv, best.*).
bool exportEvolutionResults(EditorState& state, const std::filesystem::path& dir);
// The individual the viewport's ghost and the panels show: the one clicked (`selected`, when
// it is in the snapshot), else the generation's best (lowest total cost); -1 when no generation
// has recorded its runs.
int chosenIndividual(const EvolutionState& evolution);
// Selects an individual of the snapshot's population (a click in the viewport or the list); -1,
// or an index the snapshot does not have, goes back to the best.
void selectIndividual(EvolutionState& evolution, int individual);
// The individual's rank in its generation (1: the lowest total cost; ties by index, as the
// viewport orders them), 0 when it is not in the snapshot.
int individualRank(const search::Snapshot& snap, int individual);
// The individuals of the snapshot's population, best first (the viewport's lanes, the list).
std::vector<int> rankedIndividuals(const search::Snapshot& snap);
// What the panels call the chosen run: "#3 of 23 (clicked)" or "#1 of 23 (best)"; "" for none.
std::string chosenRunLabel(const EvolutionState& evolution);
// The running search's state (kReady when there is none).
search::SessionState evolutionState(const EditorState& state);
// A search's budget as the log and the Evolve panel say it: "40 generations", "1.5 min" or
// "1.5 min or 40 generations".
std::string budgetText(const search::EvolveSettings& settings);

}  // namespace sinew::editor
