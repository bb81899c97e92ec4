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

struct EvolutionSettings {
  double minutes = 2.0;     // wall-clock budget, > 0
  double window_s = 10.0;   // seconds simulated per evaluation
  int population = 0;      // 0: CMA-ES's default (4 + 3 ln n)
  bool no_prior = false;    // the baseline: random start, generic ranges
  int shown = 8;            // individuals drawn in the viewport, best first
  search::FitnessWeights weights;  // the fitness terms' weights; live while a search runs
  std::string optimizer = "cmaes";  // "cmaes" or "ga"
  std::uint64_t seed = 1;   // same seed, same search (on the same number of threads)
  // The physical problem (a project's terrain, pushes and body overrides, as text).
  std::string terrain = "flat";
  std::vector<std::string> pushes;
  app::BodyOverrides body;
};

struct EvolutionState {
  EvolutionSettings settings;
  std::unique_ptr<search::Session> session;
  std::shared_ptr<const search::Snapshot> snapshot;  // the latest published
  int reported_generation = 0;  // the last generation written to the log
  bool show_population = true;  // draw the population's runs beside the clip
  int selected = -1;  // the individual clicked in the viewport (index in the snapshot's
                      // population), -1 for none; cleared when a new generation arrives
  std::string export_dir;        // where "Export best" writes; default beside the opened file
};

// Starts a search on the loaded clip and its current model; says in the log why not when it
// cannot (nothing loaded, no analysis, a plan that does not build). Replaces a running search.
bool startEvolution(EditorState& state);
void pauseEvolution(EditorState& state);
void resumeEvolution(EditorState& state);
void stopEvolution(EditorState& state);  // within one simulation step; keeps the snapshot
// Hands the settings' weights to the running search (from its next generation; logged).
void setEvolutionWeights(EditorState& state);
// Takes the session's latest snapshot and logs each finished generation. Call once per frame.
void pollEvolution(EditorState& state);
// Writes best.json, best.bvh and best.glb of the best so far into evolution.export_dir.
bool exportEvolutionBest(EditorState& state);

}  // namespace sinew::editor
