#include "sinew/pipeline/physical_loop.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <optional>

#include <nlohmann/json.hpp>

#include "sinew/core/rotation.h"
#include "sinew/motion/anatomy.h"
#include "sinew/motion/leg_ik.h"
#include "sinew/pipeline/pipeline.h"
#include "sinew/spectral/analysis.h"

namespace sinew::pipeline {
namespace {

constexpr double kMaxContactShare = 0.9;  // of a stride: a foot always swings a little
constexpr double kLift_m = 0.03;  // an ankle this far above its touchdown height has lifted

glm::dvec3 flat(glm::dvec3 v) {
  v.y = 0.0;
  return v;
}

// The run after `settle_s`, analysed: its best window of whole strides and its model.
struct Fit {
  spectral::TargetMotion model;
  double run_start_s = 0.0;
  int window_strides = 0;
};
Result<Fit> fitWindow(const motion::Skeleton& skeleton, const motion::Clip& motion,
                      double settle_s, double end_s, const LoopSettings& settings) {
  const int skip = static_cast<int>(std::lround(settle_s / motion.frame_time));
  const int end = std::min(motion.frame_count, static_cast<int>(std::floor(end_s / motion.frame_time)) + 1);
  if (skip + 2 >= end) return Status::error("loop: the run ended before its first stride did");
  const motion::Clip rest = motion::clipFrames(motion, skip, end - skip);
  spectral::AnalysisSettings analysis;
  analysis.harmonics = settings.harmonics;
  analysis.max_strides = settings.strides;
  analysis.cycle = strideNear(settle_s);  // the controller's stride
  Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, rest, analysis);
  if (!spectrum.ok()) return Status::error("loop: the run: " + spectrum.message());
  const spectral::MotionSpectrum& s = spectrum.value();
  if (!s.stride.found) return Status::error("loop: the run has no stride: " + s.stride.message);
  if (rest.duration() < settings.strides * s.period_s) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "loop: after its first stride the run holds %.2f s, %d strides of %.2f s need "
                  "more (a longer --window, or fewer --loop-strides)",
                  rest.duration(), settings.strides, s.period_s);
    return Status::error(text);
  }
  Fit fit{spectral::targetFromSpectrum(s, {}, motion.name + "_loop"), skip * motion.frame_time + s.window.start_s,
          s.window.strides};
  return fit;
}

// A contact phase in loop frames: [first, first + frames), `first` may pass the loop's end.
struct Plant {
  int foot_joint = 0;
  std::string foot;
  int first = 0, frames = 0;
};

// Each foot's plants from the simulation: its mean touchdown phase over the run's footfalls
// after the settling (those at its ankle's standing height: a swinging toe that scuffs the ground
// is not a step), held while the ankle stays within kLift_m of its height at touchdown (the heel
// rising ends the plant), once per stride.
std::vector<Plant> contactPhases(const motion::Skeleton& skeleton,
                                 const physics::SimulationReport& run, const Fit& fit,
                                 const motion::Clip& loop, double climb_m, int strides,
                                 double frame_step) {
  std::vector<Plant> plants;
  const double period = fit.model.period();
  const int n = loop.frame_count;
  for (size_t f = 0; f < run.feet.size(); ++f) {
    const int joint = skeleton.findJoint(run.feet[f]);
    if (joint < 0) continue;
    double lowest = std::numeric_limits<double>::infinity();
    for (const physics::Footfall& fall : run.footfalls)
      if (fall.foot == static_cast<int>(f) && fall.time_s >= fit.run_start_s - period)
        lowest = std::min(lowest, fall.position.y);
    std::complex<double> mean(0.0, 0.0);
    for (const physics::Footfall& fall : run.footfalls)
      if (fall.foot == static_cast<int>(f) && fall.time_s >= fit.run_start_s - period &&
          fall.position.y < lowest + kLift_m)
        mean += std::polar(1.0, 2.0 * std::numbers::pi * (fall.time_s - fit.run_start_s) / period);
    if (std::abs(mean) < 1e-9) continue;
    double phase = std::arg(mean) / (2.0 * std::numbers::pi);
    if (phase < 0.0) phase += 1.0;
    // The ankle's height in frame u of the loop played on (a lap further up by its climb).
    const auto height = [&](int u) {
      return motion::worldPositions(skeleton, loop, u % n)[joint].y + climb_m * (u / n);
    };
    for (int s = 0; s < strides; ++s) {
      Plant plant{joint, run.feet[f], static_cast<int>(std::lround((phase + s) * period / frame_step)), 1};
      const double touchdown = height(plant.first);
      const int most = static_cast<int>(kMaxContactShare * period / frame_step);
      while (plant.frames < most && height(plant.first + plant.frames) < touchdown + kLift_m)
        ++plant.frames;
      plants.push_back(plant);
    }
  }
  return plants;
}

// The foot's lowest point (index into its points) and its position in frame u of the loop played
// on (u past the end: the next lap, `travel` further).
struct Lowest {
  int point = -1;
  glm::dvec3 position{0.0};
};
Lowest lowestPoint(const motion::Poses& poses, const motion::Foot& foot, int u, int n,
                   const glm::dvec3& travel) {
  Lowest low;
  const int frame = u % n;
  for (size_t i = 0; i < foot.points.size(); ++i) {
    const glm::dvec3& p = poses.at(frame, foot.points[i]);
    if (low.point < 0 || p.y < low.position.y) low = {static_cast<int>(i), p};
  }
  low.position += travel * static_cast<double>(u / n);
  return low;
}

// Horizontal path of the lowest point over a contact, metres (a change of lowest point, heel to
// toe, is a roll, not a slide); with `shifts`, the offsets that keep it still, per contact frame.
double contactSlide(const motion::Poses& poses, const motion::Foot& foot, const Plant& plant, int n,
                    const glm::dvec3& travel, std::vector<glm::dvec3>* shifts) {
  double path = 0.0;
  Lowest previous = lowestPoint(poses, foot, plant.first, n, travel);
  glm::dvec3 anchor = previous.position, shift(0.0);
  for (int u = plant.first; u < plant.first + plant.frames; ++u) {
    const Lowest low = lowestPoint(poses, foot, u, n, travel);
    if (low.point == previous.point) {
      path += glm::length(flat(low.position - previous.position));
      shift = flat(anchor - low.position);
    } else {
      anchor = low.position + shift;
    }
    if (shifts) shifts->push_back(shift);
    previous = low;
  }
  return path;
}

const motion::Foot* footOf(const std::vector<motion::Foot>& feet, int joint) {
  for (const motion::Foot& f : feet)
    if (f.joint == joint) return &f;
  return nullptr;
}

// Plants every contact: per frame the ankle's horizontal offset (contact, then fading over
// `blend` frames), solved by leg IK. Fills the contacts' slides before.
void plantFeet(const motion::Skeleton& skeleton, motion::Clip& clip, const std::vector<motion::Foot>& feet,
               const std::vector<Plant>& plants, int blend, const glm::dvec3& travel,
               PhysicalLoop& loop) {
  const int n = clip.frame_count;
  const motion::Poses poses = motion::computePoses(skeleton, clip, n);
  // (feet joints) x frames: the offset to apply, when any.
  std::vector<std::vector<std::optional<glm::dvec3>>> offsets(
      static_cast<size_t>(skeleton.jointCount()), std::vector<std::optional<glm::dvec3>>(static_cast<size_t>(n)));
  for (const Plant& plant : plants) {
    const motion::Foot* foot = footOf(feet, plant.foot_joint);
    LoopContact contact{plant.foot, (plant.first % n) * clip.frame_time, plant.frames * clip.frame_time};
    if (foot == nullptr) continue;
    std::vector<glm::dvec3> shifts;
    contact.slide_before_cm = 100.0 * contactSlide(poses, *foot, plant, n, travel, &shifts);
    loop.contacts.push_back(contact);
    // Held where the foot was on average (not at touchdown): the leg reaches half as far.
    glm::dvec3 mean(0.0);
    for (const glm::dvec3& shift : shifts) mean += shift / static_cast<double>(shifts.size());
    auto& mine = offsets[static_cast<size_t>(plant.foot_joint)];
    for (int k = 0; k < plant.frames; ++k)
      mine[static_cast<size_t>((plant.first + k) % n)] = shifts[k] - mean;
    for (int k = 1; k <= blend; ++k) {  // fading in before touchdown and out after lift-off
      const double fade = 1.0 - static_cast<double>(k) / (blend + 1);
      const size_t after = static_cast<size_t>((plant.first + plant.frames - 1 + k) % n);
      const size_t before = static_cast<size_t>(((plant.first - k) % n + n) % n);
      if (!mine[after]) mine[after] = (shifts.back() - mean) * fade;
      if (!mine[before]) mine[before] = (shifts.front() - mean) * fade;
    }
  }
  for (int frame = 0; frame < n; ++frame) {
    for (int joint = 0; joint < skeleton.jointCount(); ++joint) {
      const auto& offset = offsets[static_cast<size_t>(joint)][static_cast<size_t>(frame)];
      if (!offset || glm::length(*offset) < 1e-6) continue;
      const glm::dvec3 ankle = motion::worldPositions(skeleton, clip, frame)[joint];
      const motion::LegIkResult r = motion::placeAnkle(skeleton, clip, frame, joint, ankle + *offset);
      loop.correction_deg_max = std::max(loop.correction_deg_max, r.correction_rad * 180.0 / std::numbers::pi);
      loop.ik_residual_cm_max = std::max(loop.ik_residual_cm_max, 100.0 * r.residual_m);
    }
  }
}

// The slides after the plant, contact by contact (plants and loop.contacts in the same order).
void measureSlidesAfter(const motion::Skeleton& skeleton, const motion::Clip& clip,
                        const std::vector<motion::Foot>& feet, const std::vector<Plant>& plants,
                        const glm::dvec3& travel, PhysicalLoop& loop) {
  const motion::Poses poses = motion::computePoses(skeleton, clip, clip.frame_count);
  size_t c = 0;
  for (const Plant& plant : plants) {
    const motion::Foot* foot = footOf(feet, plant.foot_joint);
    if (foot == nullptr || c >= loop.contacts.size()) continue;
    loop.contacts[c++].slide_after_cm =
        100.0 * contactSlide(poses, *foot, plant, clip.frame_count, travel, nullptr);
  }
}

// Seam (last frame to first, each joint moved by what it travels in a lap: `lap`, joints) and
// the largest step between frames, degrees and cm.
void measureSeam(const motion::Skeleton& skeleton, const motion::Clip& clip,
                 const std::vector<glm::dvec3>& lap, PhysicalLoop& loop) {
  const int n = clip.frame_count;
  std::vector<std::vector<glm::dvec3>> positions;
  for (int f = 0; f < n; ++f) positions.push_back(motion::worldPositions(skeleton, clip, f));
  const std::vector<glm::dvec3> none(lap.size(), glm::dvec3(0.0));
  const auto step = [&](int a, int b, const std::vector<glm::dvec3>& shift, double& deg, double& cm) {
    deg = cm = 0.0;
    for (int j = 0; j < clip.joint_count; ++j) {
      deg = std::max(deg, angleBetween(clip.rotation(a, j), clip.rotation(b, j)) * 180.0 / std::numbers::pi);
      cm = std::max(cm, 100.0 * glm::length(positions[b][j] + shift[j] - positions[a][j]));
    }
  };
  step(n - 1, 0, lap, loop.seam_deg, loop.seam_cm);
  for (int f = 0; f + 1 < n; ++f) {
    double deg = 0.0, cm = 0.0;
    step(f, f + 1, none, deg, cm);
    loop.step_deg_max = std::max(loop.step_deg_max, deg);
    loop.step_cm_max = std::max(loop.step_cm_max, cm);
  }
}

// RMS angle over joints and frames between the loop and the run at the same time.
double deviationFromRun(const motion::Clip& loop_clip, double model_step, double run_start_s,
                        const motion::Clip& run) {
  double squared = 0.0;
  long count = 0;
  for (int f = 0; f < loop_clip.frame_count; ++f) {
    const int r = static_cast<int>(std::lround((run_start_s + f * model_step) / run.frame_time));
    if (r < 0 || r >= run.frame_count) continue;
    for (int j = 0; j < run.joint_count; ++j) {
      const double a = angleBetween(loop_clip.rotation(f, j), run.rotation(r, j));
      squared += a * a;
      ++count;
    }
  }
  return count > 0 ? std::sqrt(squared / count) * 180.0 / std::numbers::pi : 0.0;
}

// In place: every translation channel's trend (the root motion's travel) taken out of the
// clip's frames, which the model's time `step` apart; the sway and bob stay. Travel then 0.
void removeTravel(const spectral::TargetMotion& model, double step, motion::Clip& clip,
                  glm::dvec3& travel_m) {
  for (const spectral::ChannelModel& channel : model.channels) {
    if (channel.kind == spectral::SignalKind::kRotation || channel.trend == 0.0) continue;
    for (int f = 0; f < clip.frame_count; ++f)
      clip.translations[static_cast<size_t>(f) * clip.joint_count + channel.joint][channel.axis] -=
          channel.trend * f * step;
  }
  travel_m = glm::dvec3(0.0);
}

}  // namespace

Status LoopSettings::validate() const {
  if (strides < 1 || strides > 16) return Status::error("loop: strides must be 1..16");
  if (!(std::isfinite(fps) && fps >= 0.0 && fps <= 1000.0))
    return Status::error("loop: fps must be 0 (the run's) or in (0, 1000]");
  if (harmonics < 1 || harmonics > 64) return Status::error("loop: harmonics must be 1..64");
  if (!(std::isfinite(blend_s) && blend_s > 0.0 && blend_s <= 2.0))
    return Status::error("loop: blend_s must be in (0, 2] seconds");
  return Status();
}

motion::Clip PhysicalLoop::played(int laps) const {
  motion::Clip out = clip;
  const size_t per_lap = clip.rotations.size();
  const double lap_s = strides * period_s;
  for (int lap = 1; lap < laps; ++lap) {
    out.rotations.insert(out.rotations.end(), clip.rotations.begin(), clip.rotations.end());
    out.translations.insert(out.translations.end(), clip.translations.begin(), clip.translations.end());
    if (!clip.scales.empty()) out.scales.insert(out.scales.end(), clip.scales.begin(), clip.scales.end());
    for (const spectral::ChannelModel& channel : model.channels) {  // each lap further on
      if (channel.kind == spectral::SignalKind::kRotation || in_place) continue;
      for (int f = 0; f < clip.frame_count; ++f)
        out.translations[lap * per_lap + static_cast<size_t>(f) * clip.joint_count + channel.joint]
                        [channel.axis] += channel.trend * lap_s * lap;
    }
  }
  out.frame_count = clip.frame_count * std::max(1, laps);
  return out;
}

double PhysicalLoop::slideBeforeMeanCm() const {
  double sum = 0.0;
  for (const LoopContact& c : contacts) sum += c.slide_before_cm;
  return contacts.empty() ? 0.0 : sum / static_cast<double>(contacts.size());
}

double PhysicalLoop::slideAfterMeanCm() const {
  double sum = 0.0;
  for (const LoopContact& c : contacts) sum += c.slide_after_cm;
  return contacts.empty() ? 0.0 : sum / static_cast<double>(contacts.size());
}

nlohmann::json PhysicalLoop::json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const LoopContact& c : contacts)
    list.push_back({{"foot", c.foot},
                    {"start_s", c.start_s},
                    {"duration_s", c.duration_s},
                    {"slide_before_cm", c.slide_before_cm},
                    {"slide_after_cm", c.slide_after_cm}});
  return {{"period_s", period_s},
          {"strides", strides},
          {"frames", clip.frame_count},
          {"fps", clip.fps()},
          {"run_start_s", run_start_s},
          {"window_strides", window_strides},
          {"seam_deg", seam_deg},
          {"seam_cm", seam_cm},
          {"step_deg_max", step_deg_max},
          {"step_cm_max", step_cm_max},
          {"deviation_from_run_deg_rms", deviation_deg_rms},
          {"plant_correction_deg_max", correction_deg_max},
          {"plant_residual_cm_max", ik_residual_cm_max},
          {"travel_m", {travel_m.x, travel_m.y, travel_m.z}},
          {"slide_before_cm_mean", slideBeforeMeanCm()},
          {"slide_after_cm_mean", slideAfterMeanCm()},
          {"contacts", list}};
}

Result<PhysicalLoop> physicalLoop(const motion::Skeleton& skeleton,
                                  const physics::SimulationReport& run, double settle_s,
                                  const LoopSettings& settings) {
  if (Status valid = settings.validate(); !valid.ok()) return valid;
  if (run.motion.frame_count < 2) return Status::error("loop: the run recorded no motion");
  // A run that fell: only what came half a stride before the fall (the collapse never loops).
  const double end_s = run.fell ? run.fall_time_s - 0.5 * settle_s : run.motion.duration();
  Result<Fit> fit = fitWindow(skeleton, run.motion, settle_s, end_s, settings);
  if (!fit.ok()) return fit.status();
  PhysicalLoop loop;
  loop.model = fit.value().model;
  loop.period_s = loop.model.period();
  loop.strides = settings.strides;
  loop.run_start_s = fit.value().run_start_s;
  loop.window_strides = fit.value().window_strides;
  // N strides, the closing frame (the first again, travelled) left out.
  const double fps = settings.fps > 0.0 ? settings.fps : run.motion.fps();
  const motion::Clip sampled = loop.model.sample(fps, settings.strides);
  const int n = sampled.frame_count - 1;
  loop.clip = motion::clipFrames(sampled, 0, n);
  // What the whole figure travels over the loop (the closing frame is the first, moved by it).
  const std::vector<glm::dvec3> closing = motion::worldPositions(skeleton, sampled, n);
  std::vector<glm::dvec3> lap = motion::worldPositions(skeleton, sampled, 0);
  for (size_t j = 0; j < lap.size(); ++j) lap[j] = closing[j] - lap[j];
  loop.travel_m = lap[static_cast<size_t>(motion::pelvisJoint(skeleton))];
  const double model_step = settings.strides * loop.period_s / n;
  // The plant, on the travelling loop.
  Result<std::vector<motion::Foot>> feet = motion::findFeet(skeleton, loop.clip);
  if (feet.ok()) {
    const std::vector<Plant> plants =
        contactPhases(skeleton, run, fit.value(), loop.clip, loop.travel_m.y, settings.strides, model_step);
    const int blend = std::max(1, static_cast<int>(std::lround(settings.blend_s * fps)));
    plantFeet(skeleton, loop.clip, feet.value(), plants, blend, loop.travel_m, loop);
    measureSlidesAfter(skeleton, loop.clip, feet.value(), plants, loop.travel_m, loop);
  }
  loop.deviation_deg_rms = deviationFromRun(loop.clip, model_step, loop.run_start_s, run.motion);
  if (settings.in_place) {
    removeTravel(loop.model, model_step, loop.clip, loop.travel_m);
    lap.assign(lap.size(), glm::dvec3(0.0));
  }
  loop.in_place = settings.in_place;
  measureSeam(skeleton, loop.clip, lap, loop);
  return loop;
}

}  // namespace sinew::pipeline
