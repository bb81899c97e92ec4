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
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/search/problem.h"
#include "sinew/spectral/style.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::app {

inline constexpr int kProjectVersion = 2;

// The body plan's overrides as text, as on the command line: "NAME=KG", "NAME", "NAME=LO,HI".
struct BodyOverrides {
  std::vector<std::string> masses;        // NAME=KG
  std::vector<std::string> fixed;         // NAME (welded)
  std::vector<std::string> hinge_limits;  // NAME=LO,HI in degrees
  bool operator==(const BodyOverrides&) const = default;
};

// The evolutionary search's settings (sinew evolve's flags, the editor's Evolve panel).
struct SearchSettings {
  double minutes = 2.0;             // wall-clock budget, > 0
  int population = 0;               // 0: CMA-ES's default
  bool no_prior = false;            // the baseline: random start, generic ranges
  std::string optimizer = "cmaes";  // "cmaes" or "ga"
  std::uint64_t seed = 1;
  search::FitnessWeights weights;
  bool operator==(const SearchSettings&) const = default;
};

// A style measured from a neutral and a styled clip of the rig's skeleton, applied at a weight
// (0 changes nothing, 1 gives the styled clip's character, 2 exaggerates, -1 removes).
struct StylePair {
  std::string label;    // "tired"; default: the styled file's stem
  std::string neutral;  // clip files (absolute once loaded)
  std::string styled;
  double weight = 0.0;  // -1..2
  bool operator==(const StylePair&) const = default;
};

// A secondary motion source (breathing, sway): a sinusoid or band-limited noise on one axis of a
// joint's rotation, deterministic by seed.
struct SecondaryMotion {
  std::string joint;
  int axis = 0;        // 0 X, 1 Y, 2 Z
  bool noise = false;  // band-limited noise instead of a sinusoid
  double frequency_hz = 0.25;
  double amplitude_deg = 1.0;
  std::uint64_t seed = 1;
  bool operator==(const SecondaryMotion&) const = default;
};

// Edits of the harmonic model, applied in this order: band gains, styles, secondary motion.
inline constexpr int kBandCount = 3;   // gait (1-2), style (3-5), detail (6+)
inline constexpr int kGroupCount = 4;  // legs, arms, spine, head
struct MotionEdits {
  std::array<std::array<double, kGroupCount>, kBandCount> band_gains{
      {{1.0, 1.0, 1.0, 1.0}, {1.0, 1.0, 1.0, 1.0}, {1.0, 1.0, 1.0, 1.0}}};
  std::vector<StylePair> styles;
  std::vector<SecondaryMotion> secondary;
  bool operator==(const MotionEdits&) const = default;
  bool empty() const { return *this == MotionEdits(); }
};

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
  bool operator==(const ViewSettings&) const = default;
};

struct Project {
  // Files, absolute (or as given) once loaded.
  std::string rig;        // required: the skeleton (and its clips)
  std::string clip;       // another file with the clip to use; empty: the rig's own
  std::string animation;  // the clip's name in a glTF; empty: the first
  std::string target;     // coefficients (.json) to track instead of the clip's model
  // The harmonic model: K for every joint, then per-joint overrides by joint name.
  int harmonics = 5;
  std::map<std::string, int> joint_k;
  MotionEdits edits;  // band gains, styles, secondary motion
  // Physics.
  std::string terrain = "flat";     // flat | slope:DEG | steps:H,D | rough:A,SEED
  double window_s = 10.0;           // seconds simulated per evaluation
  std::vector<std::string> pushes;  // TIME,X,Y,Z[,LINK]
  BodyOverrides body;
  SearchSettings search;
  ViewSettings view;
  bool operator==(const Project&) const = default;
};

// Reads and checks a project; every message names the file and the field.
Result<Project> loadProject(const std::filesystem::path& path);
// Parses a project's JSON text; `base` resolves relative paths, `name` starts messages.
Result<Project> parseProject(const std::string& text, const std::filesystem::path& base,
                             const std::string& name);
// Checks the fields that have a grammar of their own (terrain, pushes, body, weights).
Status validateProject(const Project& project);
// The JSON text of a project (version kProjectVersion), paths relative to `base` where they can be.
std::string projectJson(const Project& project, const std::filesystem::path& base);
// Writes the project atomically (a temporary file, then rename): a failed save keeps the old file.
Status saveProject(const Project& project, const std::filesystem::path& path);

// The text grammars shared by the command line, project files and the editor. `field` starts the
// message ("--terrain", "terrain").
// "flat", "slope:5", "steps:0.05,0.6", "rough:0.02,7".
Result<physics::TerrainSettings> parseTerrain(const std::string& text,
                                              const std::string& field = "--terrain");
// "TIME,X,Y,Z[,LINK]": seconds, N s (world, Y up), a joint name (the base when left out).
Result<physics::Push> parsePush(const std::string& text, const std::string& field = "--push");
// A simulation of `seconds` on `terrain` with `pushes` (every run takes the same pushes).
Result<physics::SimulationSettings> simulationSettings(
    double seconds, const std::string& terrain, const std::vector<std::string>& pushes,
    const std::string& terrain_field = "--terrain", const std::string& push_field = "--push");
// Style work: a clip analysed with enough harmonics for a style's detail (10 per joint); its
// skeleton must be `skeleton`'s (same joint names), or the message says so, naming the file.
Result<spectral::TargetMotion> styleClipTarget(const std::string& path,
                                               const motion::Skeleton& skeleton);
// The same for a clip already loaded (`name` starts messages).
Result<spectral::TargetMotion> styleTarget(const motion::Skeleton& skeleton,
                                           const motion::Clip& clip, const std::string& name);
// The style of a pair: both clips analysed, then spectral::measureStyle.
Result<spectral::StyleVector> measureStylePair(const StylePair& pair,
                                               const motion::Skeleton& skeleton);
// `model` with the edits applied in order (band gains, styles at their weights, secondary motion).
// `styles` holds the measured style of each of edits.styles (nullptr: left out, as when its
// measurement failed). The message names what could not be applied.
Result<spectral::TargetMotion> applyMotionEdits(
    const spectral::TargetMotion& model, const motion::Skeleton& skeleton, const MotionEdits& edits,
    const std::vector<const spectral::StyleVector*>& styles);

// The body plan's overrides; messages name the flag (--mass, --fixed, --hinge-limits).
Result<physics::BodyPlanSettings> parseBodyOverrides(const BodyOverrides& body);

}  // namespace sinew::app
