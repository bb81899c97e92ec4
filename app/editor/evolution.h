// The editor's evolution: a search session (sinew::search::Session, on its own thread) over the
// loaded rig, seeded from the model the user is editing (the K per joint of the Spectrum panel),
// polled each frame for its latest snapshot. Plain model code, no ImGui: the Evolve panel and
// the viewport read it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
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
};

struct EvolutionState {
  EvolutionSettings settings;
  std::unique_ptr<search::Session> session;
  pipeline::ProjectSettings started;  // what the session was built from (its results record it)
  std::shared_ptr<const search::Snapshot> snapshot;  // the latest published
  int reported_generation = 0;                       // the last generation written to the log
  bool show_population = true;                       // draw the population's runs beside the clip
  int selected = -1;       // the individual clicked in the viewport (index in the snapshot's
                           // population), -1 for none; cleared when a new generation arrives
  std::string export_dir;  // where "Export best" writes; default beside the opened file
};

// Starts a search on the loaded clip with the project as the editor has it now (captureProject),
// through the engine's pipeline::prepareSearch, as `sinew evolve PROJECT` does; says in the log
// why not when it cannot (nothing loaded, no analysis, a plan that does not build). Replaces a
// running search. `generations` > 0: that budget instead of the settings' minutes.
bool startEvolution(EditorState& state, int generations = 0);
void pauseEvolution(EditorState& state);
void resumeEvolution(EditorState& state);
void stopEvolution(EditorState& state);  // within one simulation step; keeps the snapshot
// Hands the settings' weights to the running search (from its next generation; logged).
void setEvolutionWeights(EditorState& state);
// Takes the session's latest snapshot and logs each finished generation. Call once per frame.
void pollEvolution(EditorState& state);
// Writes best.json, best.bvh and best.glb of the best so far into evolution.export_dir.
bool exportEvolutionBest(EditorState& state);
// Writes the best so far as a loop (best_loop.bvh, best_loop.glb, loop.json: what `sinew evolve
// --loop-strides N [--in-place]` writes) into evolution.export_dir; logs the loop's figures, or
// why there is none (a run that fell in its first strides).
bool exportEvolutionLoop(EditorState& state, int strides, bool in_place);
// Writes what `sinew evolve PROJECT --out DIR` writes (checkpoint.json, history.csv, best.*).
bool exportEvolutionResults(EditorState& state, const std::filesystem::path& dir);
// The running search's state (kReady when there is none).
search::SessionState evolutionState(const EditorState& state);

}  // namespace sinew::editor
