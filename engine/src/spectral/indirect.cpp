#include "sinew/spectral/indirect.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>
#include <sstream>

namespace sinew::spectral {
namespace {

using motion::computePoses;
using motion::horizontal;
using motion::leftOf;
using motion::Poses;

constexpr glm::dvec3 kUp(0.0, 1.0, 0.0);
// Below this horizontal speed of the centre of mass the clip runs in place, and the figure's
// facing replaces the travel direction, m/s.
constexpr double kInPlaceSpeed = 0.1;

}  // namespace

Status ContactSettings::validate() const {
  if (!(height_tolerance_m > 0.0) || !std::isfinite(height_tolerance_m)) {
    return Status::error("contacts.height_tolerance_m must be > 0 metres");
  }
  if (!(speed_tolerance_m_s > 0.0) || !std::isfinite(speed_tolerance_m_s)) {
    return Status::error("contacts.speed_tolerance_m_s must be > 0 m/s");
  }
  if (!(ground_quantile >= 0.0 && ground_quantile <= 1.0)) {
    return Status::error("contacts.ground_quantile must be in [0, 1]");
  }
  if (!(max_gap_s >= 0.0) || !std::isfinite(max_gap_s)) {
    return Status::error("contacts.max_gap_s must be >= 0 seconds");
  }
  if (!(min_contact_s >= 0.0) || !std::isfinite(min_contact_s)) {
    return Status::error("contacts.min_contact_s must be >= 0 seconds");
  }
  return {};
}

Status IndirectSettings::validate() const {
  if (Status status = contacts.validate(); !status.ok()) return status;
  return masses.validate();
}

// ---------------------------------------------------------------- contacts and spectra

namespace {

// The signal over the spectrum's window, resampled like the joint channels (minus its linear
// trend when `detrend`), and its harmonics.
IndirectSeries fitOverWindow(std::string name, std::string unit, const std::vector<double>& values,
                             const MotionSpectrum& spectrum, bool detrend) {
  const double dt = spectrum.signals.frame_time;
  const int samples = spectrum.window.strides * spectrum.samples_per_stride;
  const double length = spectrum.window.strides * spectrum.period_s;
  const double start = spectrum.window.start_s / dt;
  const double slope =
      detrend ? (catmullRomAt(values, start + length / dt) - catmullRomAt(values, start)) / length : 0.0;
  std::vector<double> sampled(samples);
  for (int i = 0; i < samples; ++i) {
    const double t = i * length / samples;
    sampled[i] = catmullRomAt(values, start + t / dt) - slope * t;
  }
  IndirectSeries out{std::move(name), std::move(unit), {}, 0.0};
  out.series = fitHarmonics(sampled, spectrum.window.strides, &out.aperiodic_energy);
  return out;
}

// Fills breaks up to `max_gap` frames inside contacts, then drops contacts shorter than
// `min_length` frames.
void cleanContacts(std::vector<std::uint8_t>& down, int max_gap, int min_length) {
  const int n = static_cast<int>(down.size());
  const auto runs = [&](std::uint8_t value, auto&& visit) {
    for (int i = 0; i < n;) {
      int end = i;
      while (end < n && down[end] == down[i]) ++end;
      if (down[i] == value) visit(i, end);
      i = end;
    }
  };
  runs(0, [&](int begin, int end) {
    if (begin > 0 && end < n && end - begin <= max_gap) {
      std::fill(down.begin() + begin, down.begin() + end, std::uint8_t{1});
    }
  });
  runs(1, [&](int begin, int end) {
    if (end - begin < min_length)
      std::fill(down.begin() + begin, down.begin() + end, std::uint8_t{0});
  });
}

// The analysed window in fractional frames of the clip.
struct WindowSpan {
  double first = 0.0;
  double last = 0.0;
};

WindowSpan windowSpan(const MotionSpectrum& spectrum, int frames, double dt) {
  const double window_s = spectrum.window.strides * spectrum.period_s;
  const double first = spectrum.window.start_s / dt;
  return {first, std::min(first + window_s / dt, frames - 1.0)};
}

Status checkIndirectInputs(const motion::Skeleton& skeleton, const motion::Clip& clip,
                           const MotionSpectrum& spectrum, const IndirectSettings& settings) {
  if (Status status = settings.validate(); !status.ok()) return status;
  if (Status status = clip.validate(skeleton); !status.ok()) return status;
  if (clip.frame_count < 2)
    return Status::error("clip '" + clip.name + "' has one frame: no contacts");
  if (spectrum.signals.frame_count != clip.frame_count || spectrum.samples_per_stride < 4) {
    return Status::error("the spectrum is not this clip's analysis (" +
                         std::to_string(spectrum.signals.frame_count) + " frames against " +
                         std::to_string(clip.frame_count) + ")");
  }
  return {};
}

// Foot i's contact point (its lowest point) per frame (into `lowest`), its height above the
// foot's own ground level, its horizontal speed, and its contacts. The speed follows the same
// point across the neighbouring frames, so a change of lowest point (heel to toe) is not a jump.
void measureFoot(IndirectSignals& out, const Poses& poses, const ContactSettings& cs, size_t i,
                 std::vector<FootPoint>& lowest) {
  const Foot& foot = out.feet[i];
  const int frames = static_cast<int>(lowest.size());
  const double dt = out.frame_time;
  std::vector<double>& height = out.foot_heights_m[i];
  for (int f = 0; f < frames; ++f) {
    FootPoint best = foot.points.front();
    for (const FootPoint& p : foot.points) {
      if (poses.at(f, p).y < poses.at(f, best).y) best = p;
    }
    lowest[f] = best;
    height[f] = poses.at(f, best).y;
    const int a = std::max(f - 1, 0);
    const int b = std::min(f + 1, frames - 1);
    out.foot_speeds_m_s[i][f] =
        b > a ? glm::length(horizontal(poses.at(b, best) - poses.at(a, best))) / ((b - a) * dt)
              : 0.0;
  }
  // The ground level is where the foot rests, not the lowest it ever goes: retargeted rigs
  // (the iClone run) dip a toe tip below the stance level at toe-off, at speed.
  std::vector<double> resting;
  for (int f = 0; f < frames; ++f) {
    if (out.foot_speeds_m_s[i][f] <= cs.speed_tolerance_m_s) resting.push_back(height[f]);
  }
  if (resting.empty()) resting = height;
  const auto q = static_cast<long>(cs.ground_quantile * static_cast<double>(resting.size() - 1));
  std::nth_element(resting.begin(), resting.begin() + q, resting.end());
  out.ground_levels_m[i] = resting[static_cast<size_t>(q)];
  for (int f = 0; f < frames; ++f) {
    height[f] -= out.ground_levels_m[i];
    out.contacts[i][f] =
        height[f] <= cs.height_tolerance_m && out.foot_speeds_m_s[i][f] <= cs.speed_tolerance_m_s;
  }
  cleanContacts(out.contacts[i], static_cast<int>(std::floor(cs.max_gap_s / dt + 1e-9)),
                static_cast<int>(std::ceil(cs.min_contact_s / dt - 1e-9)));
}

// Footfalls: contact starts after the first frame, in time order.
void findFootfalls(IndirectSignals& out, const Poses& poses,
                   const std::vector<std::vector<FootPoint>>& lowest) {
  const double dt = out.frame_time;
  for (size_t i = 0; i < out.contacts.size(); ++i) {
    const std::vector<std::uint8_t>& down = out.contacts[i];
    const int frames = static_cast<int>(down.size());
    for (int f = 1; f < frames; ++f) {
      if (!down[f] || down[f - 1]) continue;
      int end = f;
      while (end < frames && down[end]) ++end;
      out.footfalls.push_back(
          {static_cast<int>(i), f, f * dt, (end - f) * dt, poses.at(f, lowest[i][f])});
    }
  }
  std::sort(out.footfalls.begin(), out.footfalls.end(), [](const Footfall& a, const Footfall& b) {
    return a.frame != b.frame ? a.frame < b.frame : a.foot < b.foot;
  });
}

// The travel direction of the centre of mass (out.com) over the window, its speed, and the
// figure's left; in place, the figure's facing across its right feet to its left feet.
void findTravel(IndirectSignals& out, const Poses& poses, const WindowSpan& window) {
  const int frames = static_cast<int>(out.com.size());
  const double dt = out.frame_time;
  const auto comAt = [&](double frame) {
    const int i = std::min(static_cast<int>(frame), frames - 2);
    const double u = frame - i;
    return (1.0 - u) * out.com[i] + u * out.com[i + 1];
  };
  const glm::dvec3 travel = horizontal(comAt(window.last) - comAt(window.first));
  const double travel_s = (window.last - window.first) * dt;
  out.gait.speed_m_s = travel_s > 0.0 ? glm::length(travel) / travel_s : 0.0;
  if (out.gait.speed_m_s > kInPlaceSpeed) {
    out.forward = glm::normalize(travel);
  } else {
    glm::dvec3 across(0.0);
    for (const Foot& foot : out.feet) {
      const double sign = foot.side == Side::kLeft ? 1.0 : foot.side == Side::kRight ? -1.0 : 0.0;
      for (int f = 0; f < frames; ++f) {
        across +=
            sign * horizontal(poses.joint[static_cast<size_t>(f) * poses.joints + foot.joint]);
      }
    }
    if (glm::length(across) > 1e-9) out.forward = glm::normalize(glm::cross(across, kUp));
    out.notes.push_back("the clip runs in place: forward is the figure's facing");
  }
  out.left = leftOf(out.forward);
}

// Strides (same foot) and steps (to the pair's other foot), and their means.
void measureStrides(IndirectSignals& out) {
  GaitFigures& gait = out.gait;
  double interval_sum = 0.0;
  double stride_length_sum = 0.0;
  for (size_t a = 0; a < out.footfalls.size(); ++a) {
    const Footfall& from = out.footfalls[a];
    const int pair = out.feet[from.foot].pair;
    bool found_pair = pair < 0;
    for (size_t b = a + 1; b < out.footfalls.size(); ++b) {
      const Footfall& to = out.footfalls[b];
      if (to.foot == from.foot) {
        interval_sum += to.time_s - from.time_s;
        stride_length_sum += glm::length(horizontal(to.position - from.position));
        ++gait.stride_intervals;
        break;
      }
      if (to.foot == pair && !found_pair) {
        const glm::dvec3 d = to.position - from.position;
        out.steps.push_back({static_cast<int>(a), static_cast<int>(b), glm::dot(d, out.forward),
                             std::abs(glm::dot(d, out.left)), to.time_s - from.time_s});
        found_pair = true;
      }
    }
  }
  if (gait.stride_intervals > 0) {
    gait.stride_period_s = interval_sum / gait.stride_intervals;
    gait.stride_length_m = stride_length_sum / gait.stride_intervals;
    gait.contact_speed_m_s = gait.stride_length_m / gait.stride_period_s;
  }
  for (const Step& step : out.steps) {
    gait.step_length_m += step.length_m / static_cast<double>(out.steps.size());
    gait.step_width_m += step.width_m / static_cast<double>(out.steps.size());
    gait.step_duration_s += step.duration_s / static_cast<double>(out.steps.size());
  }
}

// The stride from contacts against the analysed one, and the duty factor over the window's
// frames; notes where they disagree.
void compareGait(IndirectSignals& out, const MotionSpectrum& spectrum, const WindowSpan& window) {
  GaitFigures& gait = out.gait;
  gait.analysis_period_s = spectrum.stride.found ? spectrum.stride.period_s : 0.0;
  if (gait.stride_period_s > 0.0 && gait.analysis_period_s > 0.0) {
    gait.period_difference = gait.stride_period_s / gait.analysis_period_s - 1.0;
  }
  const size_t footCount = out.feet.size();
  const int f0 = static_cast<int>(std::ceil(window.first - 1e-9));
  const int f1 = static_cast<int>(std::floor(window.last + 1e-9));
  for (size_t i = 0; i < footCount && f1 > f0; ++i) {
    const long down = std::count(out.contacts[i].begin() + f0, out.contacts[i].begin() + f1, 1);
    gait.duty_factor += static_cast<double>(down) / (f1 - f0) / static_cast<double>(footCount);
  }
  if (gait.stride_intervals == 0)
    out.notes.push_back("no foot lands twice: no stride from contacts");
  if (gait.stride_period_s > 0.0 && gait.analysis_period_s > 0.0 &&
      std::abs(gait.period_difference) > 0.05) {
    std::ostringstream note;
    note << "the stride from foot contacts (" << gait.stride_period_s
         << " s) differs from the analysed stride (" << gait.analysis_period_s << " s) by "
         << 100.0 * gait.period_difference << "%";
    out.notes.push_back(note.str());
  }
}

// Spectra over the analysed window: the centre of mass's bob, sway and surge (the latter two
// without the travel), each foot's contact indicator and height.
void fitIndirectSpectra(IndirectSignals& out, const motion::Skeleton& skeleton,
                        const MotionSpectrum& spectrum) {
  const size_t frames = out.com.size();
  std::vector<double> height(frames), lateral(frames), surge(frames);
  for (size_t f = 0; f < frames; ++f) {
    height[f] = out.com[f].y;
    lateral[f] = glm::dot(out.com[f], out.left);
    surge[f] = glm::dot(out.com[f], out.forward);
  }
  out.spectra.push_back(fitOverWindow("com height", "m", height, spectrum, false));
  out.spectra.push_back(fitOverWindow("com lateral", "m", lateral, spectrum, true));
  out.spectra.push_back(fitOverWindow("com forward", "m", surge, spectrum, true));
  for (size_t i = 0; i < out.feet.size(); ++i) {
    const std::string& name = skeleton.names[out.feet[i].joint];
    const std::vector<double> indicator(out.contacts[i].begin(), out.contacts[i].end());
    out.spectra.push_back(fitOverWindow(name + " contact", "", indicator, spectrum, false));
    out.spectra.push_back(
        fitOverWindow(name + " height", "m", out.foot_heights_m[i], spectrum, false));
  }
}

}  // namespace

Result<IndirectSignals> analyzeIndirect(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                        const MotionSpectrum& spectrum,
                                        const IndirectSettings& settings) {
  if (Status status = checkIndirectInputs(skeleton, clip, spectrum, settings); !status.ok())
    return status;
  Result<std::vector<Foot>> feet = findFeet(skeleton, clip);
  if (!feet.ok()) return feet.status();
  IndirectSignals out;
  out.frame_time = clip.frame_time;
  out.feet = std::move(feet).value();
  const int frames = clip.frame_count;
  const Poses poses = computePoses(skeleton, clip, frames);

  const size_t footCount = out.feet.size();
  out.ground_levels_m.resize(footCount);
  out.foot_heights_m.assign(footCount, std::vector<double>(frames));
  out.foot_speeds_m_s.assign(footCount, std::vector<double>(frames));
  out.contacts.assign(footCount, std::vector<std::uint8_t>(frames, 0));
  std::vector<std::vector<FootPoint>> lowest(footCount, std::vector<FootPoint>(frames));
  for (size_t i = 0; i < footCount; ++i) measureFoot(out, poses, settings.contacts, i, lowest[i]);
  findFootfalls(out, poses, lowest);

  out.masses = massDistribution(skeleton, out.feet, settings.masses);
  out.com = centreOfMass(skeleton, clip, out.masses);
  const WindowSpan window = windowSpan(spectrum, frames, clip.frame_time);
  findTravel(out, poses, window);
  measureStrides(out);
  compareGait(out, spectrum, window);
  fitIndirectSpectra(out, skeleton, spectrum);
  return out;
}

}  // namespace sinew::spectral
