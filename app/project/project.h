// A project (format "sinew.project", JSON): the files a piece of work starts from and every
// setting made on them, so that a pipeline names one file and the editor reopens where the artist
// left off. `sinew evolve PROJECT`, `sinew edit PROJECT` and the editor's File menu share it.
//
// Version 2 (written) adds the per-joint harmonics, the search's settings and the editor's view;
// version 1 files (rig, clip, animation, target, harmonics, terrain, window_s, pushes, body) still
// load. Paths inside are relative to the project file. See docs/file_formats.md.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/pipeline/settings.h"
#include "sinew/search/controller_io.h"

namespace sinew::app {

inline constexpr int kProjectVersion = 2;

// The settings themselves are the engine's (sinew/pipeline/settings.h); this file only reads and
// writes them.
using pipeline::BodyOverrides;
using pipeline::HingeLimitOverride;
using pipeline::kBandCount;
using pipeline::kGroupCount;
using pipeline::MassOverride;
using pipeline::MotionEdits;
using pipeline::PhysicsSettings;
using pipeline::SearchSettings;
using pipeline::SecondaryMotion;
using pipeline::StylePair;

// What the editor shows and how it plays.
struct ViewSettings {
  double speed = 1.0;  // playback rate, 0.1..4
  bool loop = true;
  bool show_original = true;
  bool show_model = true;
  bool model_beside = true;
  bool follow = true;
  bool show_grid = true;
  bool show_end_sites = true;
  bool show_population = true;
  bool show_ghost = true;  // the search's target over the chosen simulated run
  bool operator==(const ViewSettings&) const = default;
};

// A project: the pipeline's settings (files, harmonics, edits, physics, search) and the view.
struct Project : pipeline::ProjectSettings {
  ViewSettings view;
  bool operator==(const Project&) const = default;
};

// Reads and checks a project; every message names the file and the field. Keys this version
// does not know are left out, each with a line in `warnings` (when given) naming key and file.
Result<Project> loadProject(const std::filesystem::path& path,
                            std::vector<std::string>* warnings = nullptr);
// Parses a project's JSON text; `base` resolves relative paths, `name` starts messages.
Result<Project> parseProject(const std::string& text, const std::filesystem::path& base,
                             const std::string& name, std::vector<std::string>* warnings = nullptr);
// Checks every field (the pipeline's settings and the view); the message names the field.
Status validateProject(const Project& project);
// The JSON text of a project (version kProjectVersion), paths relative to `base` where they can be.
std::string projectJson(const Project& project, const std::filesystem::path& base);
// Writes the project atomically (a temporary file, then rename): a failed save keeps the old file.
Status saveProject(const Project& project, const std::filesystem::path& path);

// What a search's results record of its project: best.json's settings (terrain, seed, optimiser,
// files) and checkpoint.json's "problem", the project's JSON with absolute paths (a resume reads
// it back with parseProject). `sinew evolve` and the editor write the same.
search::ControllerFile resultsMeta(const pipeline::ProjectSettings& settings,
                                   const search::EvolveSettings& used);
std::string settingsJson(const pipeline::ProjectSettings& settings);

// The text grammars of the command line and project files, read into the engine's types once.
// `field` starts the message ("--terrain", "terrain"); each *Text function writes what its parse
// function reads back to the same value.
// "flat", "slope:5", "steps:0.05,0.6", "rough:0.02,7".
Result<physics::TerrainSettings> parseTerrain(const std::string& text,
                                              const std::string& field = "--terrain");
std::string terrainText(const physics::TerrainSettings& terrain);
// "TIME,X,Y,Z[,LINK]": seconds, N s (world, Y up), a joint name (the base when left out).
Result<physics::Push> parsePush(const std::string& text, const std::string& field = "--push");
std::string pushText(const physics::Push& push);
// Body overrides: "NAME=KG" (--mass), "NAME" (--fixed), "NAME=LO,HI" in degrees (--hinge-limits).
Result<BodyOverrides> parseBodyOverrides(const std::vector<std::string>& masses,
                                         const std::vector<std::string>& fixed,
                                         const std::vector<std::string>& hinge_limits);
std::string massText(const MassOverride& mass);
std::string hingeLimitText(const HingeLimitOverride& limit);
// A number as the shortest text that reads back to it ("0.05", "9", "1e-05").
std::string numberText(double value);

}  // namespace sinew::app
