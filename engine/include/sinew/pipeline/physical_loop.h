// A physically valid loop from a simulated run (DESIGN's "--loop--> PhysicalLoop"): after the run
// settles (its first stride left out), the analysis the clips get finds the window of whole
// strides that repeats best and fits its harmonic model; the model sampled over N strides loops
// with no seam by construction. The feet are then planted: each foot's contact phases come from
// the simulation (its touchdowns, and its share of time on the ground), and during a contact the
// foot's lowest point does not slide (two-bone leg IK, motion/leg_ik.h; the correction blends out
// over the swing's first frames). Root motion travels, or stays in place.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/asset.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/physics/simulation.h"
#include "sinew/pipeline/run_style.h"
#include "sinew/pipeline/settings.h"
#include "sinew/search/problem.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::pipeline {

struct LoopSettings {
  int strides = 2;          // whole strides in the loop, 1..16
  bool in_place = false;    // the root motion's travel (every translation trend) removed; sway kept
  double fps = 0.0;         // frames per second of the loop; 0: the run's recording rate
  int harmonics = 10;       // K per joint of the fit (the style analysis' K), 1..64
  double blend_s = 0.2;     // a plant's correction fades over this after lift-off, seconds, > 0
  Status validate() const;  // the message names the field ("loop: strides ...")
};

struct LoopContact {
  std::string foot;         // the foot joint's name
  double start_s = 0.0;     // touchdown, seconds from the loop's first frame
  double duration_s = 0.0;
  double slide_before_cm = 0.0;  // horizontal path of the foot's lowest point while in contact
  double slide_after_cm = 0.0;   // the same after the plant
};

struct PhysicalLoop {
  motion::Clip clip;          // strides x period: the frame after the last is the first (plus
                              // the loop's travel), so it is not repeated
  spectral::TargetMotion model;  // the fitted model, before the plant
  double period_s = 0.0;      // one stride of the loop
  int strides = 0;
  double run_start_s = 0.0;   // the fitted window's start in the run, seconds
  int window_strides = 0;     // whole strides the analysis chose for the window (<= strides)
  double seam_deg = 0.0;      // last frame to first: the largest joint rotation change
  double seam_cm = 0.0;       // last frame to first (each joint plus what it travels in a
                              // lap): the largest joint movement
  double step_deg_max = 0.0;  // the same between consecutive frames inside the loop: what one
  double step_cm_max = 0.0;   // frame of motion moves
  double deviation_deg_rms = 0.0;  // loop against the raw run over the window, every joint
  double correction_deg_max = 0.0;  // the plant's largest change of a leg joint's rotation
  double ik_residual_cm_max = 0.0;  // the farthest a planted ankle stayed from its target
  glm::dvec3 travel_m{0.0};   // the pelvis's travel over the loop, world (zero in place)
  bool in_place = false;
  std::vector<LoopContact> contacts;
  // The loop played `laps` times in a row (>= 1), each lap travelled on by the model's trends
  // (not in place).
  motion::Clip played(int laps) const;
  double slideBeforeMeanCm() const;
  double slideAfterMeanCm() const;
  nlohmann::json json() const;  // everything above except the clip and the model
};

// The loop of `run` (a simulation of `skeleton`; its recorded motion, feet and footfalls), after
// `settle_s` seconds: the first stride, the controller's (the run's own stride is looked for
// within 25% of it); of a run that fell, only what came half a stride before the fall. Fails, saying why, when what is left of the run holds no
// stride or fewer whole strides than settings.strides asks.
Result<PhysicalLoop> physicalLoop(const motion::Skeleton& skeleton,
                                  const physics::SimulationReport& run, double settle_s,
                                  const LoopSettings& settings = {});

// A search's best point replayed over the problem's window with its motion recorded (what
// best.bvh holds), and the stride its controller ran at.
struct BestReplay {
  physics::SimulationReport run;
  double stride_s = 0.0;
};
BestReplay replayBest(const search::Problem& problem, std::span<const double> point);

// The replay's loop written into `dir` (created): best_loop.bvh and best_loop.glb (on `rig`'s
// skeleton, with its mesh when it came from glTF) and loop.json (PhysicalLoop::json, "in_place",
// and under "style" the loop's style against `edits.styles` when there are any, as
// measureRunStyle measures it). What `sinew evolve` and the editor's Export write. A failure
// names the file; a run that gives no loop is physicalLoop's message, and nothing is written.
struct LoopFiles {
  PhysicalLoop loop;
  RunStyleReport style;  // empty without styles
};
Result<LoopFiles> writeLoopFiles(const search::Problem& problem, const BestReplay& best,
                                    const MotionEdits& edits, const motion::MotionAsset& rig,
                                    const LoopSettings& settings, const std::filesystem::path& dir);

}  // namespace sinew::pipeline
