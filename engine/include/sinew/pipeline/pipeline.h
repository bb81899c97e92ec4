// From a project's settings to a search, once, for the command line, the editor and the tests:
//
//   MotionAsset + Clip --resolveJointK, analyze, targetFromSpectrum--> model (or a target file)
//     --applyMotionEdits (band gains, styles, secondary)-----------> the target the search tracks
//     --buildBodyPlan (body overrides)-----------------------------> BodyPlan
//     --simulationSettings (window, terrain, pushes, servo lead)---> SimulationSettings
//     --search::Problem::create (genome, weights)------------------> Problem
//   SearchSettings --evolveSettings-------------------------------> search::EvolveSettings
//
// `sinew evolve`, `sinew simulate` and the editor's Evolve call these; nothing else assembles
// the pipeline. Every message names the file or field.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/asset.h"
#include "sinew/pipeline/settings.h"
#include "sinew/search/controller_io.h"
#include "sinew/search/problem.h"
#include "sinew/search/session.h"
#include "sinew/spectral/cycle.h"
#include "sinew/spectral/style.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::pipeline {

// K per joint (skeleton order): `harmonics` everywhere, then `joint_k` by joint name. A name the
// skeleton does not have is an error naming it and `rig` ("joint_harmonics: RIG has no joint
// called 'Tail'").
Result<std::vector<int>> resolveJointK(const motion::Skeleton& skeleton, int harmonics,
                                       const std::map<std::string, int>& joint_k,
                                       const std::string& rig);

// Harmonics per joint with which style clips are analysed (as `sinew style` does).
inline constexpr int kStyleHarmonics = 10;
// A clip analysed for style work (kStyleHarmonics per joint); `name` starts messages.
// `stride_hint_s` > 0: the stride is looked for within 25% of it (a simulated run, whose
// controller's stride is known; its strides vary, and twice the stride can repeat better).
Result<spectral::TargetMotion> styleTarget(const motion::Skeleton& skeleton,
                                           const motion::Clip& clip, const std::string& name,
                                           double stride_hint_s = 0.0);
// Stride bounds within 25% of a known stride, seconds (> 0).
spectral::CycleSettings strideNear(double stride_s);
// The same for a clip file, whose skeleton must be `skeleton`'s (same joint names), or the
// message says so, naming the file.
Result<spectral::TargetMotion> styleClipTarget(const std::string& path,
                                               const motion::Skeleton& skeleton);
// The style of a pair: both clips analysed, then spectral::measureStyle.
Result<spectral::StyleVector> measureStylePair(const StylePair& pair,
                                               const motion::Skeleton& skeleton);
// `model` with the edits applied in order (band gains, styles at their weights, secondary motion).
// `styles` holds the measured style of each of edits.styles (nullptr: left out). The message
// names what could not be applied.
Result<spectral::TargetMotion> applyMotionEdits(
    const spectral::TargetMotion& model, const motion::Skeleton& skeleton, const MotionEdits& edits,
    const std::vector<const spectral::StyleVector*>& styles);

// The motion a search tracks, with a line saying what it is.
struct TrackedMotion {
  spectral::TargetMotion target;
  std::string what;  // for messages: "'walk' (K = 5)", or the coefficient file
};
// The target of `settings` on `clip` of `rig` (skeleton `rig.skeleton`): the coefficient file
// `settings.target` as it is, or the clip analysed with K per joint and then the edits. `styles`:
// the measured style of each of settings.edits.styles (nullptr: measured here); a style that
// cannot be measured is an error naming it.
Result<TrackedMotion> trackedMotion(
    const motion::Skeleton& skeleton, const motion::Clip& clip, const ProjectSettings& settings,
    const std::vector<const spectral::StyleVector*>* styles = nullptr);
// What a search of `settings` tracks, in the words of lines an artist reads ("furthest from the
// clip: ..."): "the coefficients" of `settings.target`, "the edited clip" when the project edits
// the model (band gains, styles, secondary motion), else "the clip".
const char* trackedName(const ProjectSettings& settings);
// The body plan of `clip` with the overrides (the message names the rig).
Result<physics::BodyPlan> bodyPlan(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                   const BodyOverrides& body, const std::string& rig);
// A simulation of the window on the terrain, with the pushes; the servos lead their targets by
// their lag (physics::servoLag).
physics::SimulationSettings simulationSettings(const PhysicsSettings& physics);
// The session's settings from a project's (budget: its minutes; no generation limit).
search::EvolveSettings evolveSettings(const SearchSettings& search);

// The search a project describes: every step above, in order.
struct SearchSetup {
  search::Problem problem;  // problem.seed is the tracked (edited) target
  std::string what;         // what is tracked, for messages
};
Result<SearchSetup> prepareSearch(
    const motion::Skeleton& skeleton, const motion::Clip& clip, const ProjectSettings& settings,
    const std::vector<const spectral::StyleVector*>* styles = nullptr);

// A search's history as CSV: a row per generation, best/mean/worst of the total and each term.
std::string historyCsv(const search::Snapshot& snapshot);
// checkpoint.json and history.csv in `dir` (created), each written atomically: what
// writeSearchResults writes first, and what `sinew evolve` rewrites after every generation so
// that a killed run loses at most the generation in flight.
Status writeCheckpoint(const search::Session& session, const nlohmann::json& problem,
                       const std::filesystem::path& dir);
// What a search leaves in `dir` (created), as `sinew evolve --out` and the editor's headless
// export write it: checkpoint.json (the session's checkpoint with `problem`, the project's
// settings as project JSON, under "problem": what a resume rebuilds the problem from),
// history.csv and, once a generation has finished, best.json, best.bvh and best.glb
// (search::exportBest). Returns whether best.* were written.
Result<bool> writeSearchResults(const search::Session& session, const motion::MotionAsset& rig,
                                const nlohmann::json& problem, const search::ControllerFile& meta,
                                const std::filesystem::path& dir);

}  // namespace sinew::pipeline
