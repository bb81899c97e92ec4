// The settings a project makes on its files, typed: what the motion to track is (K per joint,
// edits of the harmonic model), the physical problem (window, terrain, pushes, body overrides) and
// the search (budget, optimiser, seed, fitness weights). The command line's flags, the editor's
// panels and the project file (app/project) fill and serialise these structs; the pipeline
// (pipeline.h) turns them into a search. Nothing here is text to be parsed again at use.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/search/problem.h"
#include "sinew/search/session.h"

namespace sinew::pipeline {

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
  int axis = 0;                // 0 X, 1 Y, 2 Z
  bool noise = false;          // band-limited noise instead of a sinusoid
  double frequency_hz = 0.25;  // (0, 30]
  double amplitude_deg = 1.0;  // 0..30
  std::uint64_t seed = 1;
  bool operator==(const SecondaryMotion&) const = default;
};

// Edits of the harmonic model, applied in this order: band gains, styles, secondary motion.
inline constexpr int kBandCount = 3;   // gait (1-2), style (3-5), detail (6+)
inline constexpr int kGroupCount = 4;  // legs, arms, spine, head
struct MotionEdits {
  std::array<std::array<double, kGroupCount>, kBandCount> band_gains{
      {{1.0, 1.0, 1.0, 1.0}, {1.0, 1.0, 1.0, 1.0}, {1.0, 1.0, 1.0, 1.0}}};  // 0..10
  std::vector<StylePair> styles;
  std::vector<SecondaryMotion> secondary;
  bool operator==(const MotionEdits&) const = default;
  bool empty() const { return *this == MotionEdits(); }
  Status validate() const;  // the message names the field ("styles[1].weight")
};

// The body plan's overrides, each naming a link by its pivot joint's name.
struct MassOverride {
  std::string link;
  double kg = 1.0;  // > 0
  bool operator==(const MassOverride&) const = default;
};
struct HingeLimitOverride {
  std::string link;
  double lo_deg = 0.0, hi_deg = 0.0;  // lo < hi
  bool operator==(const HingeLimitOverride&) const = default;
};
struct BodyOverrides {
  std::vector<MassOverride> masses;
  std::vector<std::string> fixed;  // welded joints
  std::vector<HingeLimitOverride> hinge_limits;
  bool operator==(const BodyOverrides&) const = default;
  bool empty() const { return masses.empty() && fixed.empty() && hinge_limits.empty(); }
  // The plan's settings with these overrides (the rules' defaults otherwise), validated.
  Result<physics::BodyPlanSettings> planSettings() const;
};

// The physical problem every evaluation simulates.
struct PhysicsSettings {
  double window_s = 10.0;  // seconds simulated per evaluation, 0.5..600
  physics::TerrainSettings terrain;
  std::vector<physics::Push> pushes;  // every run takes the same pushes
  BodyOverrides body;
  bool operator==(const PhysicsSettings& other) const;  // field by field
  Status validate() const;  // the message names the field ("terrain: ...", "pushes[0]: ...")
};

// The evolutionary search's settings (sinew evolve's flags, the editor's Evolve panel).
struct SearchSettings {
  double minutes = 2.0;   // wall-clock budget, (0, 10000]
  int population = 0;     // 0: the optimiser's default
  bool no_prior = false;  // the baseline: random start, generic ranges
  search::OptimizerKind optimizer = search::OptimizerKind::kCmaes;
  std::uint64_t seed = 1;
  search::FitnessWeights weights;
  int trials = 1;               // runs per point, 1..search::kMaxTrials: the nominal one and
                                // trials - 1 pushed ones (search::setTrials); its cost the mean
  double trial_push_m_s = 0.3;  // the trials' pushes, per kg of body: m/s, (0, 10]
  double robust_push_m_s = 0.0; // pushes inside every run, per kg of body: m/s, [0, 10]
                                // (search::addRobustPushes); 0: none
  int restart_after = 0;        // CMA-ES: restart from the prior after this many generations
                                // without a better best (search::EvolveSettings); 0: never
  int start_generations = 50;   // generations each start is tried before the best goes on (the
                                // stance yield off and at half: search::EvolveSettings); 0: one
  bool operator==(const SearchSettings&) const = default;
  Status validate() const;  // the message names the field ("search.minutes: ...")
};

// Everything a project sets for a search, beside the editor's view: the files (absolute, or as
// given), the harmonic model, its edits, the physics and the search.
struct ProjectSettings {
  std::string rig;                     // required: the skeleton (and its clips)
  std::string clip;                    // another file with the clip to use; empty: the rig's own
  std::string animation;               // the clip's name in a glTF; empty: the first
  std::string target;                  // coefficients (.json) to track instead of the clip's model
  int harmonics = 5;                   // K for every joint, 1..64
  std::map<std::string, int> joint_k;  // per-joint K by joint name, 0..64
  MotionEdits edits;  // band gains, styles, secondary motion (not applied to `target`)
  PhysicsSettings physics;
  SearchSettings search;
  bool operator==(const ProjectSettings&) const = default;
  Status validate() const;  // the message names the field
};

}  // namespace sinew::pipeline
