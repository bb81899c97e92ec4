#include "sinew/spectral/analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <utility>

#include "sinew/spectral/indirect.h"

namespace sinew::spectral {
namespace {

// Each foot's contact point height (its lowest joint or End Site) per frame, world metres: the
// stride's cross-check (estimateStride). Empty when no feet are found.
std::vector<std::vector<double>> footHeights(const motion::Skeleton& skeleton, const motion::Clip& clip) {
  Result<std::vector<Foot>> feet = findFeet(skeleton, clip);
  if (!feet.ok() || feet.value().empty()) return {};
  std::vector<std::vector<double>> heights(feet.value().size(),
                                           std::vector<double>(static_cast<size_t>(clip.frame_count)));
  std::vector<glm::dmat4> world(static_cast<size_t>(skeleton.jointCount()));
  for (int f = 0; f < clip.frame_count; ++f) {
    motion::worldTransforms(skeleton, clip, f, world);
    for (size_t n = 0; n < feet.value().size(); ++n) {
      double lowest = 1e300;
      for (const FootPoint& point : feet.value()[n].points) {
        const glm::dmat4& m = world[static_cast<size_t>(point.joint)];
        const double y = point.end_site ? (m * glm::dvec4(*skeleton.end_sites[point.joint], 1.0)).y : m[3].y;
        lowest = std::min(lowest, y);
      }
      heights[n][static_cast<size_t>(f)] = lowest;
    }
  }
  return heights;
}

// Seconds since the last lap (or construction).
class StageClock {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

int nextPowerOfTwo(int n) {
  int p = 1;
  while (p < n) p *= 2;
  return p;
}

// Frames whose time lies in [start, start + length): the frames the model describes.
std::pair<int, int> frameRange(const MotionSignals& signals, const AnalysisWindow& window,
                               double period_s) {
  const double dt = signals.frame_time;
  const double start = window.start_s;
  const double end = start + window.strides * period_s;
  const int first = static_cast<int>(std::ceil(start / dt - 1e-9));
  int last = static_cast<int>(std::ceil(end / dt - 1e-9)) - 1;
  last = std::min(last, signals.frame_count - 1);
  return {first, std::max(first, last)};
}

// Frames first..last inclusive.
motion::Clip clipRange(const motion::Clip& clip, int first, int last) {
  return motion::clipFrames(clip, first, last - first + 1);
}

// The model's pose at frames first..last of the clip (t from start_s): mean pose, the channels'
// series (one FourierEvaluator time per frame), travel continuing at each channel's `trends`.
motion::Clip evaluateModel(const motion::Skeleton& skeleton, const MotionSignals& signals,
                           int first, int last, double start_s, FourierEvaluator series,
                           const std::vector<double>& trends) {
  const int joints = skeleton.jointCount();
  motion::Clip out;
  out.name = "model";
  out.frame_time = signals.frame_time;
  out.frame_count = last - first + 1;
  out.joint_count = joints;
  out.rotations.resize(static_cast<size_t>(out.frame_count) * joints);
  out.translations.resize(out.rotations.size());
  if (!signals.mean_scales.empty()) {
    for (int f = 0; f < out.frame_count; ++f) {
      out.scales.insert(out.scales.end(), signals.mean_scales.begin(), signals.mean_scales.end());
    }
  }
  for (int f = 0; f < out.frame_count; ++f) {
    const double t = (first + f) * signals.frame_time - start_s;
    for (int j = 0; j < joints; ++j) {
      const size_t n = static_cast<size_t>(f) * joints + j;
      out.rotations[n] = signals.mean_rotations[j];
      out.translations[n] = signals.mean_translations[j];
    }
    series.setTime(t);
    glm::dvec3 vector(0.0);
    for (size_t c = 0; c < series.channelCount(); ++c) {
      const SignalChannel& channel = signals.channels[c];
      const double value = series.value(c);
      const size_t n = static_cast<size_t>(f) * joints + channel.joint;
      if (channel.kind == SignalKind::kRotation) {
        vector[channel.axis] = value;
        if (channel.axis == 2) {
          out.rotations[n] = glm::normalize(signals.mean_rotations[channel.joint] *
                                            fromRotationVector(vector));
        }
      } else {
        // Travel continues at the window's velocity.
        out.translations[n][channel.axis] += value + trends[c] * t;
      }
    }
  }
  return out;
}

// The point (a joint, or its End Site) and frame where the model is furthest from the original,
// with its error in centimetres.
struct WorstPoint {
  int joint = -1;
  bool end_site = false;
  int frame = 0;
  double cm = 0.0;
};

WorstPoint worstPoint(const motion::Skeleton& skeleton, const motion::Clip& original,
                      const motion::Clip& model) {
  const int joints = skeleton.jointCount();
  std::vector<glm::dmat4> a(joints);
  std::vector<glm::dmat4> b(joints);
  WorstPoint worst;
  for (int f = 0; f < std::min(original.frame_count, model.frame_count); ++f) {
    motion::worldTransforms(skeleton, original, f, a);
    motion::worldTransforms(skeleton, model, f, b);
    for (int j = 0; j < joints; ++j) {
      const double cm = 100.0 * glm::length(glm::dvec3(a[j][3]) - glm::dvec3(b[j][3]));
      if (cm > worst.cm) worst = {j, false, f, cm};
      if (skeleton.end_sites[j]) {
        const glm::dvec4 site(*skeleton.end_sites[j], 1.0);
        const double end_cm = 100.0 * glm::length(glm::dvec3(a[j] * site) - glm::dvec3(b[j] * site));
        if (end_cm > worst.cm) worst = {j, true, f, end_cm};
      }
    }
  }
  return worst;
}

// The fewest harmonics per joint keeping the worst position error under the tolerance. Greedy:
// from the mean pose, find the worst point and give one more harmonic to the joint above it whose
// next harmonic moves that point furthest per coefficient it costs (rotation amplitude x
// distance, or translation amplitude, over the joint's channel count); then take back every
// harmonic the tolerance does not need.
std::vector<int> autoHarmonics(const motion::Skeleton& skeleton, const motion::Clip& original,
                               const MotionSpectrum& spectrum, double tolerance_cm) {
  const int joints = skeleton.jointCount();
  std::vector<int> k(joints, 0);
  // Per joint, per channel, the harmonics strongest first.
  std::vector<std::vector<std::vector<Harmonic>>> ranked(joints);
  std::vector<bool> translates(joints, false);
  for (size_t c = 0; c < spectrum.series.size(); ++c) {
    const SignalChannel& channel = spectrum.signals.channels[c];
    ranked[channel.joint].push_back(spectrum.series[c].strongest(1 << 30));
    translates[channel.joint] = translates[channel.joint] || channel.kind == SignalKind::kTranslation;
  }
  const auto nextAmplitude = [&](int j) {
    double sum = 0.0;
    for (const auto& channel : ranked[j]) {
      if (k[j] < static_cast<int>(channel.size())) sum += channel[k[j]].amplitude;
    }
    return sum;
  };
  const motion::Clip frames = windowFrames(original, spectrum);
  std::vector<glm::dmat4> world(joints);
  while (true) {
    const WorstPoint worst = worstPoint(skeleton, frames, reconstruct(skeleton, spectrum, k));
    if (worst.cm <= tolerance_cm) break;
    motion::worldTransforms(skeleton, frames, worst.frame, world);
    const glm::dvec3 point =
        worst.end_site ? glm::dvec3(world[worst.joint] * glm::dvec4(*skeleton.end_sites[worst.joint], 1.0))
                       : glm::dvec3(world[worst.joint][3]);
    int pick = -1;
    double gain = 0.0;
    // A joint's rotation moves its End Site and everything below, not itself; its translation
    // moves itself too.
    for (int j = worst.end_site ? worst.joint : worst.joint; j != motion::kNoParent;
         j = skeleton.parents[j]) {
      const bool rotation_moves_point = worst.end_site || j != worst.joint;
      const double lever = glm::length(point - glm::dvec3(world[j][3]));
      double moved = 0.0;
      if (rotation_moves_point || translates[j]) {
        // Per coefficient spent: a step on a joint with rotation and travel channels costs twice
        // what a step on a limb joint does.
        moved = nextAmplitude(j) * (translates[j] ? 1.0 : lever) /
                static_cast<double>(std::max<size_t>(1, ranked[j].size()));
      }
      if (moved > gain) {
        gain = moved;
        pick = j;
      }
    }
    if (pick < 0) break;  // nothing left to add above the worst point: the window's floor
    ++k[pick];
  }
  // Take back what is not needed, the most generous joints first.
  std::vector<int> order(joints);
  for (int j = 0; j < joints; ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&k](int a, int b) { return k[a] > k[b]; });
  for (int j : order) {
    while (k[j] > 0) {
      --k[j];
      if (worstPoint(skeleton, frames, reconstruct(skeleton, spectrum, k)).cm > tolerance_cm) {
        ++k[j];
        break;
      }
    }
  }
  return k;
}

// What fitting the candidate windows reuses: the DFT plan (rebuilt only when a window's sample
// count differs) and the sample buffer.
struct FitScratch {
  std::optional<HarmonicPlan> plan;
  std::vector<double> sampled;
};

// A window's DFT before it becomes harmonic series: candidate windows are ranked on it, so the
// windows that lose never pay for amplitudes and phases (a hypot and an atan2 per bin).
struct WindowBins {
  AnalysisWindow window;
  double period_s = 0.0;
  double omega0 = 0.0;
  int samples_per_stride = 0;
  int samples = 0;                            // strides x samples_per_stride
  glm::dvec3 travel_velocity{0.0};
  std::vector<std::complex<double>> bins;     // (channels x samples / 2) real DFTs
  std::vector<double> trends;                 // (channels)

  std::span<const std::complex<double>> channel(size_t c) const {
    return {bins.data() + c * static_cast<size_t>(samples / 2), static_cast<size_t>(samples / 2)};
  }
};

// Samples every channel at L = strides x M even times over the window and transforms it.
// Translations lose their linear trend over the window (travel), which makes the rest periodic.
void transformWindow(const MotionSignals& signals, const AnalysisWindow& window,
                     FitScratch& scratch, WindowBins& out) {
  const double dt = signals.frame_time;
  out.window = window;
  out.period_s = window.period_s;
  out.omega0 = 2.0 * std::numbers::pi / out.period_s;
  out.samples_per_stride =
      std::max(16, nextPowerOfTwo(static_cast<int>(std::ceil(out.period_s / dt - 1e-9))));
  out.samples = window.strides * out.samples_per_stride;
  const int samples = out.samples;
  const double length = window.strides * out.period_s;
  const double start_frame = window.start_s / dt;
  if (!scratch.plan || scratch.plan->samples() != static_cast<size_t>(samples)) {
    scratch.plan.emplace(static_cast<size_t>(samples));
  }
  std::vector<double>& sampled = scratch.sampled;
  sampled.resize(samples);
  out.bins.resize(signals.channels.size() * static_cast<size_t>(samples / 2));
  out.trends.assign(signals.channels.size(), 0.0);
  out.travel_velocity = glm::dvec3(0.0);
  for (size_t c = 0; c < signals.channels.size(); ++c) {
    const SignalChannel& channel = signals.channels[c];
    double slope = 0.0;
    if (channel.kind == SignalKind::kTranslation) {
      slope = (catmullRomAt(channel.values, start_frame + length / dt) -
               catmullRomAt(channel.values, start_frame)) / length;
      if (channel.joint == signals.travel_joint) out.travel_velocity[channel.axis] = slope;
    }
    for (int i = 0; i < samples; ++i) {
      const double t = i * length / samples;
      sampled[i] = catmullRomAt(channel.values, start_frame + t / dt) - slope * t;
    }
    scratch.plan->transform(sampled, {out.bins.data() + c * static_cast<size_t>(samples / 2),
                                      static_cast<size_t>(samples / 2)});
    out.trends[c] = slope;
  }
}

// The window's harmonic series into the spectrum.
void applyWindow(MotionSpectrum& spectrum, const WindowBins& fit) {
  spectrum.window = fit.window;
  spectrum.period_s = fit.period_s;
  spectrum.omega0 = fit.omega0;
  spectrum.samples_per_stride = fit.samples_per_stride;
  spectrum.travel_velocity = fit.travel_velocity;
  spectrum.trends = fit.trends;
  spectrum.series.resize(fit.trends.size());
  spectrum.aperiodic_energy.resize(fit.trends.size());
  for (size_t c = 0; c < fit.trends.size(); ++c) {
    spectrum.series[c] = seriesFromBins(fit.channel(c), static_cast<size_t>(fit.samples),
                                        fit.window.strides, &spectrum.aperiodic_energy[c]);
  }
}

// The model with the k strongest harmonics of every channel straight from a window's bins
// (amplitudes compared squared; B cos D = -Im and B sin D = Re of the scaled bin, since
// D = arg X + pi / 2): what a fixed K ranks windows on.
motion::Clip modelFromBins(const motion::Skeleton& skeleton, const MotionSignals& signals,
                           const WindowBins& fit, int k) {
  const int periods = fit.window.strides;
  const size_t half = static_cast<size_t>(fit.samples / 2);
  const double scale = 2.0 / static_cast<double>(fit.samples);
  std::vector<FourierEvaluator::Channel> channels(fit.trends.size());
  std::vector<std::pair<double, int>> ranked;  // (squared magnitude, n)
  for (size_t c = 0; c < channels.size(); ++c) {
    const std::span<const std::complex<double>> bins = fit.channel(c);
    ranked.clear();
    for (size_t b = static_cast<size_t>(periods); b < half; b += static_cast<size_t>(periods)) {
      ranked.emplace_back(std::norm(bins[b]), static_cast<int>(b) / periods);
    }
    const size_t keep = std::min(ranked.size(), static_cast<size_t>(std::max(k, 0)));
    std::partial_sort(ranked.begin(), ranked.begin() + keep, ranked.end(),
                      [](const auto& a, const auto& b) {
                        return a.first > b.first || (a.first == b.first && a.second < b.second);
                      });
    channels[c].mean = bins[0].real() / static_cast<double>(fit.samples);
    for (size_t h = 0; h < keep; ++h) {
      const int n = ranked[h].second;
      const std::complex<double> coefficient = bins[static_cast<size_t>(n * periods)] * scale;
      channels[c].terms.push_back({n, -coefficient.imag(), coefficient.real()});
    }
  }
  const auto [first, last] = frameRange(signals, fit.window, fit.period_s);
  return evaluateModel(skeleton, signals, first, last, fit.window.start_s,
                       FourierEvaluator(fit.omega0, std::move(channels)), fit.trends);
}

// World positions of every joint, then every End Site (joint order), for one frame: the
// translations of worldTransforms() with 3x3 linear parts (a quarter of the arithmetic of 4x4
// products), which is all the position error needs.
class PositionKinematics {
 public:
  explicit PositionKinematics(const motion::Skeleton& skeleton) : skeleton_(skeleton) {
    const int joints = skeleton.jointCount();
    linear_.resize(joints);
    for (int j = 0; j < joints; ++j) {
      if (skeleton.end_sites[j]) sites_.push_back(j);
    }
    points_.resize(joints + sites_.size());
  }

  const std::vector<glm::dvec3>& points(const motion::Clip& clip, int frame) {
    for (int j = 0; j < skeleton_.jointCount(); ++j) {
      glm::dmat3 local = glm::mat3_cast(clip.rotation(frame, j));
      if (!clip.scales.empty()) {
        const glm::dvec3 scale = clip.scale(frame, j);
        for (int axis = 0; axis < 3; ++axis) local[axis] *= scale[axis];
      }
      const int parent = skeleton_.parents[j];
      if (parent == motion::kNoParent) {
        linear_[j] = local;
        points_[j] = clip.translation(frame, j);
      } else {
        linear_[j] = linear_[parent] * local;
        points_[j] = points_[parent] + linear_[parent] * clip.translation(frame, j);
      }
    }
    const size_t joints = static_cast<size_t>(skeleton_.jointCount());
    for (size_t n = 0; n < sites_.size(); ++n) {
      const int j = sites_[n];
      points_[joints + n] = points_[j] + linear_[j] * *skeleton_.end_sites[j];
    }
    return points_;
  }

 private:
  const motion::Skeleton& skeleton_;
  std::vector<int> sites_;             // joints with an End Site
  std::vector<glm::dmat3> linear_;     // (joints) world rotation and scale
  std::vector<glm::dvec3> points_;     // (joints + End Sites) world positions, metres
};

// Mean and max over frames and points (joints and End Sites) of the model's world position
// error, centimetres: how candidate windows are ranked.
struct PositionError {
  double mean_cm = 0.0;
  double max_cm = 0.0;
};

PositionError positionError(const motion::Skeleton& skeleton, const motion::Clip& original,
                            const motion::Clip& model) {
  PositionKinematics a(skeleton);
  PositionKinematics b(skeleton);
  PositionError error;
  double sum = 0.0;
  long count = 0;
  const int frames = std::min(original.frame_count, model.frame_count);
  for (int f = 0; f < frames; ++f) {
    const std::vector<glm::dvec3>& pa = a.points(original, f);
    const std::vector<glm::dvec3>& pb = b.points(model, f);
    for (size_t p = 0; p < pa.size(); ++p) {
      const double cm = 100.0 * glm::length(pa[p] - pb[p]);
      sum += cm;
      error.max_cm = std::max(error.max_cm, cm);
    }
    count += static_cast<long>(pa.size());
  }
  error.mean_cm = count > 0 ? sum / static_cast<double>(count) : 0.0;
  return error;
}

}  // namespace

Status AnalysisSettings::validate() const {
  if (harmonics < 0) return Status::error("harmonics must be >= 0, got " + std::to_string(harmonics));
  if (!(tolerance_cm > 0.0)) return Status::error("tolerance_cm must be > 0");
  if (max_strides < 1) return Status::error("max_strides must be >= 1");
  if (!(cycle.min_period_s > 0.0) || !(cycle.max_period_s > cycle.min_period_s)) {
    return Status::error("stride search range must satisfy 0 < min_period_s < max_period_s");
  }
  for (const auto& [name, k] : joint_harmonics) {
    if (k < 0) return Status::error("harmonics for joint '" + name + "' must be >= 0");
  }
  return {};
}

int MotionSpectrum::coefficientCount() const {
  int count = 0;
  for (size_t c = 0; c < signals.channels.size(); ++c) {
    const int k = joint_k[signals.channels[c].joint];
    count += 1 + 2 * std::min(k, static_cast<int>(series[c].harmonics.size()));
  }
  return count;
}

Result<MotionSpectrum> analyze(const motion::Skeleton& skeleton, const motion::Clip& clip,
                               const AnalysisSettings& settings, AnalysisTimings* timings) {
  AnalysisTimings local_timings;
  AnalysisTimings& time = timings != nullptr ? *timings : local_timings;
  time = {};
  StageClock clock;
  if (Status status = settings.validate(); !status.ok()) return status;
  if (Status status = clip.validate(skeleton); !status.ok()) return status;
  if (clip.frame_count < 2) {
    return Status::error("clip '" + clip.name + "' has one frame: nothing moves to analyse");
  }
  time.checks_s = clock.lap();
  MotionSpectrum spectrum;
  spectrum.signals = extractSignals(skeleton, clip);
  const MotionSignals& signals = spectrum.signals;
  const double dt = clip.frame_time;
  const double duration = (clip.frame_count - 1) * dt;
  time.signals_s = clock.lap();

  spectrum.stride = estimateStride(signals, settings.cycle, footHeights(skeleton, clip));
  time.stride_s = clock.lap();
  std::vector<AnalysisWindow> candidates;
  if (spectrum.stride.found) {
    candidates = candidateWindows(signals, spectrum.stride.period_s, settings.max_strides, 0.03);
    time.windows_s = clock.lap();
  } else {
    // No rhythm: the whole clip as one cycle (its seam is what it is), so there is still a
    // spectrum to look at, and the user is told.
    candidates = {{0.0, 1, duration, 0.0}};
    std::ostringstream note;
    note << spectrum.stride.message << "; the whole clip (" << duration
         << " s) is analysed as one cycle";
    spectrum.notes.push_back(note.str());
  }
  // Real strides vary: of the windows with the smallest seams, keep the one whose model
  // describes its own frames best, where a viewer sees it: with a fixed K, the smallest mean
  // position error; for auto, the fewest coefficients within the tolerance (then the smallest
  // worst error). Errors within a part in 1e9 are a tie, which the smaller seam (the earlier
  // candidate) wins: perfectly periodic clips tie to rounding, and rounding must not choose.
  // The best window's DFT is kept aside, not computed again.
  constexpr double kTie = 1.0 - 1e-9;
  FitScratch scratch;
  WindowBins trial;
  WindowBins best;
  double best_error = -1.0;
  int best_count = 0;
  std::vector<int> best_k;
  for (const AnalysisWindow& window : candidates) {
    transformWindow(signals, window, scratch, trial);
    ++time.candidates;
    time.fits_s += clock.lap();
    if (candidates.size() == 1 && !settings.auto_harmonics) {
      std::swap(trial, best);
      break;  // nothing to choose between
    }
    PositionError error;
    int count = 0;
    if (settings.auto_harmonics) {
      applyWindow(spectrum, trial);
      spectrum.joint_k = autoHarmonics(skeleton, clip, spectrum, settings.tolerance_cm);
      error = positionError(skeleton, windowFrames(clip, spectrum), reconstruct(skeleton, spectrum));
      count = spectrum.coefficientCount();
    } else {
      const auto [first, last] = frameRange(signals, trial.window, trial.period_s);
      error = positionError(skeleton, clipRange(clip, first, last),
                            modelFromBins(skeleton, signals, trial, settings.harmonics));
    }
    const bool better =
        best_error < 0.0 ||
        (settings.auto_harmonics
             ? std::make_pair(error.max_cm > settings.tolerance_cm, count) <
                   std::make_pair(best_error > settings.tolerance_cm, best_count) ||
                   (count == best_count && error.max_cm < kTie * best_error)
             : error.mean_cm < kTie * best_error);
    if (better) {
      best_error = settings.auto_harmonics ? error.max_cm : error.mean_cm;
      best_count = count;
      best_k = spectrum.joint_k;
      std::swap(trial, best);
    }
    time.ranking_s += clock.lap();
  }
  applyWindow(spectrum, best);

  // Harmonics kept per joint: the window's auto choice, or K with per-joint overrides.
  if (settings.auto_harmonics) {
    spectrum.joint_k = best_k;
  } else {
    spectrum.joint_k.assign(skeleton.jointCount(), settings.harmonics);
    for (const auto& [name, k] : settings.joint_harmonics) {
      const int joint = skeleton.findJoint(name);
      if (joint < 0) return Status::error("harmonics set for unknown joint '" + name + "'");
      spectrum.joint_k[joint] = k;
    }
  }
  spectrum.joint_errors = measureError(skeleton, windowFrames(clip, spectrum),
                                       reconstruct(skeleton, spectrum), signals, &spectrum.total);
  time.result_s = clock.lap();
  return spectrum;
}

std::pair<int, int> windowFrameRange(const MotionSpectrum& spectrum) {
  return frameRange(spectrum.signals, spectrum.window, spectrum.period_s);
}

motion::Clip windowFrames(const motion::Clip& clip, const MotionSpectrum& spectrum) {
  const auto [first, last] = windowFrameRange(spectrum);
  return clipRange(clip, first, last);
}

motion::Clip reconstruct(const motion::Skeleton& skeleton, const MotionSpectrum& spectrum,
                         const std::vector<int>& joint_k) {
  const std::vector<int>& k = joint_k.empty() ? spectrum.joint_k : joint_k;
  const MotionSignals& signals = spectrum.signals;
  std::vector<FourierEvaluator::Channel> channels(signals.channels.size());
  for (size_t c = 0; c < channels.size(); ++c) {
    channels[c].mean = spectrum.series[c].mean;
    for (const Harmonic& h : spectrum.series[c].strongest(k[signals.channels[c].joint])) {
      channels[c].terms.push_back(cartesian(h));
    }
  }
  const auto [first, last] = windowFrameRange(spectrum);
  return evaluateModel(skeleton, signals, first, last, spectrum.window.start_s,
                       FourierEvaluator(spectrum.omega0, std::move(channels)), spectrum.trends);
}

std::vector<JointError> measureError(const motion::Skeleton& skeleton,
                                     const motion::Clip& original, const motion::Clip& model,
                                     const MotionSignals& signals, JointError* total) {
  const int joints = skeleton.jointCount();
  std::vector<JointError> errors(joints);
  std::vector<double> rot_squared(joints, 0.0);
  std::vector<double> pos_sum(joints, 0.0);
  std::vector<bool> moving(joints, false);
  for (const SignalChannel& channel : signals.channels) {
    if (channel.kind == SignalKind::kRotation) moving[channel.joint] = true;
  }
  std::vector<glm::dmat4> a(joints);
  std::vector<glm::dmat4> b(joints);
  double all_rot_squared = 0.0;
  double all_pos = 0.0;
  long rot_count = 0;
  long pos_count = 0;
  JointError sum;
  const int frames = std::min(original.frame_count, model.frame_count);
  for (int f = 0; f < frames; ++f) {
    motion::worldTransforms(skeleton, original, f, a);
    motion::worldTransforms(skeleton, model, f, b);
    for (int j = 0; j < joints; ++j) {
      const double degrees = glm::degrees(angleBetween(original.rotation(f, j), model.rotation(f, j)));
      rot_squared[j] += degrees * degrees;
      errors[j].rot_err_deg_max = std::max(errors[j].rot_err_deg_max, degrees);
      if (moving[j]) {
        all_rot_squared += degrees * degrees;
        ++rot_count;
        sum.rot_err_deg_max = std::max(sum.rot_err_deg_max, degrees);
      }
      double cm = 100.0 * glm::length(glm::dvec3(a[j][3]) - glm::dvec3(b[j][3]));
      all_pos += cm;
      ++pos_count;
      sum.pos_err_cm_max = std::max(sum.pos_err_cm_max, cm);
      if (skeleton.end_sites[j]) {  // End Sites count as their joint's end effector
        const glm::dvec4 site(*skeleton.end_sites[j], 1.0);
        const double end_cm = 100.0 * glm::length(glm::dvec3(a[j] * site) - glm::dvec3(b[j] * site));
        all_pos += end_cm;
        ++pos_count;
        sum.pos_err_cm_max = std::max(sum.pos_err_cm_max, end_cm);
        cm = std::max(cm, end_cm);
      }
      pos_sum[j] += cm;
      errors[j].pos_err_cm_max = std::max(errors[j].pos_err_cm_max, cm);
    }
  }
  for (int j = 0; j < joints && frames > 0; ++j) {
    errors[j].rot_err_deg_rms = std::sqrt(rot_squared[j] / frames);
    errors[j].pos_err_cm_mean = pos_sum[j] / frames;
  }
  if (total != nullptr) {
    sum.rot_err_deg_rms = rot_count > 0 ? std::sqrt(all_rot_squared / rot_count) : 0.0;
    sum.pos_err_cm_mean = pos_count > 0 ? all_pos / pos_count : 0.0;
    *total = sum;
  }
  return errors;
}

}  // namespace sinew::spectral
