#include "sinew/spectral/cycle.h"

#include <kissfft/kissfft.hh>

#include <algorithm>
#include <complex>
#include <cmath>
#include <numbers>
#include <sstream>

namespace sinew::spectral {
namespace {

// The channels that carry the gait: rotation channels (translation channels include travel,
// which never repeats) of largest variance. 24 is plenty to see a stride and keeps long clips
// fast; every channel is used for fewer.
constexpr size_t kMaxChannels = 24;

struct Selection {
  std::vector<const std::vector<double>*> values;
  double variance = 0.0;  // summed over the selection
};

// Sum of f(v) over values in four interleaved partial sums: one running sum waits for every
// addition in turn, four keep the adder busy (every channel of a long clip is summed twice).
template <class F>
double sum(const std::vector<double>& values, F f) {
  double partial[4] = {0.0, 0.0, 0.0, 0.0};
  const size_t size = values.size();
  size_t i = 0;
  for (; i + 4 <= size; i += 4) {
    for (size_t k = 0; k < 4; ++k) partial[k] += f(values[i + k]);
  }
  for (; i < size; ++i) partial[0] += f(values[i]);
  return (partial[0] + partial[1]) + (partial[2] + partial[3]);
}

Selection selectChannels(const MotionSignals& signals) {
  std::vector<std::pair<double, const std::vector<double>*>> ranked;
  for (const SignalChannel& channel : signals.channels) {
    if (channel.kind != SignalKind::kRotation) continue;
    const double n = static_cast<double>(channel.values.size());
    const double mean = sum(channel.values, [](double v) { return v; }) / n;
    const double squares = sum(channel.values, [mean](double v) { return (v - mean) * (v - mean); });
    ranked.emplace_back(squares / n, &channel.values);
  }
  std::sort(ranked.begin(), ranked.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  if (ranked.size() > kMaxChannels) ranked.resize(kMaxChannels);
  Selection selection;
  for (const auto& [variance, values] : ranked) {
    selection.values.push_back(values);
    selection.variance += variance;
  }
  return selection;
}

double sampleAt(const std::vector<double>& values, double frame) {
  const int last = static_cast<int>(values.size()) - 1;
  if (frame <= 0.0) return values[0];
  if (frame >= last) return values[last];
  const int a = static_cast<int>(frame);
  const double u = frame - a;
  return values[a] * (1.0 - u) + values[a + 1] * u;
}

// The smallest even size >= n whose only prime factors are 2, 3 and 5: KissFFT has butterflies
// for those, and a power of two can be almost twice as long.
size_t fftSize(size_t n) {
  for (size_t size = std::max<size_t>(n + n % 2, 2);; size += 2) {
    size_t rest = size;
    for (size_t factor : {2, 3, 5}) {
      while (rest % factor == 0) rest /= factor;
    }
    if (rest == 1) return size;
  }
}

// Similarity of the pose with itself `lag` frames later, 1 - (mean squared change) / (2 x
// variance), at every integer lag 0 .. frames - 1 at once. The squared differences expand to
// two sums of squares (prefix sums) minus twice the autocorrelation, and the autocorrelations of
// all channels add up to one inverse FFT of their summed power spectra: O(channels x N log N)
// instead of O(channels x N x lags). Two real channels share one complex FFT (a in the real
// part, b in the imaginary): |A_k|^2 + |B_k|^2 = (|Z_k|^2 + |Z_{N-k}|^2) / 2, and the summed
// power spectrum is real and even, so its transform back is a real FFT of half the size.
std::vector<double> similarityTable(const Selection& selection, int frames) {
  std::vector<double> table(frames, 0.0);
  if (selection.variance <= 0.0 || frames < 2) return table;
  const size_t size = fftSize(2 * static_cast<size_t>(frames) - 1);  // no wrap-around
  const kissfft<double> forward(size, false);
  const kissfft<double> half(size / 2, false);
  std::vector<std::complex<double>> padded(size);
  std::vector<std::complex<double>> spectrum(size);
  std::vector<double> power(size, 0.0);
  std::vector<double> prefix(frames + 1, 0.0);  // running sum of squares over all channels
  const auto centred = [frames](const std::vector<double>& values, std::vector<double>& out) {
    double mean = 0.0;
    for (double v : values) mean += v / frames;
    for (int f = 0; f < frames; ++f) out[f] = values[f] - mean;  // the differences are unchanged
  };
  std::vector<double> a(frames);
  std::vector<double> b(frames);
  for (size_t c = 0; c < selection.values.size(); c += 2) {
    centred(*selection.values[c], a);
    if (c + 1 < selection.values.size()) {
      centred(*selection.values[c + 1], b);
    } else {
      std::fill(b.begin(), b.end(), 0.0);
    }
    std::fill(padded.begin(), padded.end(), 0.0);
    for (int f = 0; f < frames; ++f) {
      padded[f] = {a[f], b[f]};
      prefix[f + 1] += a[f] * a[f] + b[f] * b[f];
    }
    forward.transform(padded.data(), spectrum.data());
    power[0] += std::norm(spectrum[0]);
    for (size_t k = 1; k < size; ++k) {
      power[k] += 0.5 * (std::norm(spectrum[k]) + std::norm(spectrum[size - k]));
    }
  }
  for (int f = 0; f < frames; ++f) prefix[f + 1] += prefix[f];
  // Real and even: the forward transform equals the inverse. Bin 0's real part is lag 0 (its
  // imaginary part carries the Nyquist bin, not needed: lags stop at frames - 1 < size / 2).
  half.transform_real(power.data(), spectrum.data());
  for (int lag = 0; lag < frames - 1; ++lag) {
    const int count = frames - lag;
    const double autocorrelation = spectrum[lag].real() / static_cast<double>(size);
    const double squares = (prefix[frames] - prefix[lag]) + prefix[count];
    const double squared = std::max(0.0, squares - 2.0 * autocorrelation);
    table[lag] = 1.0 - squared / count / (2.0 * selection.variance);
  }
  return table;
}

// Sub-frame peak position from three samples around an integer maximum.
double refinePeak(double before, double at, double after) {
  const double curvature = before - 2.0 * at + after;
  if (curvature >= 0.0) return 0.0;
  return std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5);
}

// The feet's heights as a selection of their own (each centred by similarityTable).
Selection footSelection(const std::vector<std::vector<double>>& foot_heights, int frames) {
  Selection selection;
  for (const std::vector<double>& heights : foot_heights) {
    if (static_cast<int>(heights.size()) != frames) continue;
    const double n = static_cast<double>(frames);
    const double mean = sum(heights, [](double v) { return v; }) / n;
    selection.values.push_back(&heights);
    selection.variance += sum(heights, [mean](double v) { return (v - mean) * (v - mean); }) / n;
  }
  return selection;
}

}  // namespace

StrideEstimate estimateStride(const MotionSignals& signals, const CycleSettings& settings,
                              const std::vector<std::vector<double>>& foot_heights) {
  StrideEstimate estimate;
  const Selection selection = selectChannels(signals);
  const int frames = signals.frame_count;
  const double dt = signals.frame_time;
  if (selection.values.empty() || selection.variance < 1e-10) {
    estimate.message = "no stride found: no joint rotates";
    return estimate;
  }
  const int min_lag = std::max(2, static_cast<int>(std::ceil(settings.min_period_s / dt)));
  const int max_lag = std::min(frames - 2, static_cast<int>(std::floor(settings.max_period_s / dt)));
  if (max_lag < min_lag) {
    std::ostringstream why;
    if ((frames - 1) * dt < settings.min_period_s) {
      why << "no stride found: the clip (" << (frames - 1) * dt << " s) is shorter than the "
          << "shortest stride looked for (" << settings.min_period_s << " s)";
    } else {
      why << "no stride found: " << frames << " frames are too few to see the pose repeat";
    }
    estimate.message = why.str();
    return estimate;
  }
  const std::vector<double> sim = similarityTable(selection, frames);
  // Local maxima above the threshold; the first that is nearly as strong as the best wins (the
  // best may sit at two or three strides).
  std::vector<int> peaks;
  for (int lag = min_lag; lag <= max_lag; ++lag) {
    const bool rising = sim[lag] >= sim[lag - 1];
    const bool falling = lag + 1 > max_lag || sim[lag] >= sim[lag + 1];
    if (rising && falling && sim[lag] >= settings.min_similarity) {
      peaks.push_back(lag);
    }
  }
  if (peaks.empty()) {
    double highest = 0.0;
    for (int lag = min_lag; lag <= max_lag; ++lag) highest = std::max(highest, sim[lag]);
    std::ostringstream why;
    why << "no stride found: the pose never repeats between " << min_lag * dt << " and "
        << max_lag * dt << " s (best similarity " << highest << ", needs "
        << settings.min_similarity << ")";
    estimate.message = why.str();
    return estimate;
  }
  // The feet cross-check: each peak scored by the mean of the pose's similarity and the feet's
  // (their best within a frame: the feet's peak need not fall on the pose's frame).
  const Selection feet = footSelection(foot_heights, frames);
  const bool check_feet = feet.variance > 1e-12;
  const std::vector<double> foot_sim = check_feet ? similarityTable(feet, frames) : std::vector<double>();
  const auto footAt = [&](int lag) {
    if (!check_feet) return 0.0;
    double value = foot_sim[lag];
    for (int near = std::max(0, lag - 1); near <= std::min(frames - 2, lag + 1); ++near) {
      value = std::max(value, foot_sim[near]);
    }
    return value;
  };
  const auto score = [&](int lag) { return check_feet ? 0.5 * (sim[lag] + footAt(lag)) : sim[lag]; };
  double best_score = -1e30;
  for (int lag : peaks) best_score = std::max(best_score, score(lag));
  int chosen = peaks.back();
  for (int lag : peaks) {
    if (score(lag) >= best_score - 0.05) {
      chosen = lag;
      break;
    }
  }
  const double offset = chosen + 1 < frames - 1
                            ? refinePeak(sim[chosen - 1], sim[chosen], sim[chosen + 1])
                            : 0.0;
  double period = (chosen + offset) * dt;
  // Several strides in the clip measure the period more finely: refine on the furthest repeat.
  for (int k = 2;; ++k) {
    const int around = static_cast<int>(std::lround(k * period / dt));
    if (around + 2 >= frames - 1) break;
    int at = around;
    for (int lag = around - 2; lag <= around + 2; ++lag) {
      if (sim[lag] > sim[at]) at = lag;
    }
    if (sim[at] < settings.min_similarity) break;
    period = (at + refinePeak(sim[at - 1], sim[at], sim[at + 1])) * dt / k;
  }
  estimate.found = true;
  estimate.period_s = period;
  estimate.similarity = sim[chosen];
  estimate.feet_checked = check_feet;
  estimate.foot_similarity = footAt(chosen);
  return estimate;
}

std::vector<AnalysisWindow> candidateWindows(const MotionSignals& signals, double period_s,
                                             int max_strides, double period_slack, int count) {
  const double dt = signals.frame_time;
  const int frames = signals.frame_count;
  const double duration = (frames - 1) * dt;
  const Selection selection = selectChannels(signals);
  const auto& rotations = selection.values;
  // Per channel prefix sums of values and squares: any window's variance in O(1).
  std::vector<std::vector<double>> sum1(rotations.size(), std::vector<double>(frames + 1, 0.0));
  std::vector<std::vector<double>> sum2(rotations.size(), std::vector<double>(frames + 1, 0.0));
  for (size_t c = 0; c < rotations.size(); ++c) {
    for (int f = 0; f < frames; ++f) {
      const double v = (*rotations[c])[f];
      sum1[c][f + 1] = sum1[c][f] + v;
      sum2[c][f + 1] = sum2[c][f] + v * v;
    }
  }
  const auto activity = [&](int first, int length) {
    const int last = std::min(frames, first + std::max(length, 2));
    const double n = last - first;
    double total = 0.0;
    for (size_t c = 0; c < rotations.size(); ++c) {
      const double mean = (sum1[c][last] - sum1[c][first]) / n;
      total += (sum2[c][last] - sum2[c][first]) / n - mean * mean;
    }
    return total;
  };
  // Value and slope must both meet: a jump in either leaks into every harmonic. Slopes are
  // scaled to radians by the time a fifth harmonic takes to turn a radian.
  const auto seam = [&](int s, double length, double period) {
    const double end = s + length / dt;
    const double slope_scale = period / (2.0 * std::numbers::pi * 5.0) / (2.0 * dt);
    double squared = 0.0;
    for (const std::vector<double>* values : rotations) {
      const double d = sampleAt(*values, end) - (*values)[s];
      const double slope_end = sampleAt(*values, end + 1.0) - sampleAt(*values, end - 1.0);
      const double slope_start = sampleAt(*values, s + 1.0) - sampleAt(*values, s - 1.0);
      const double v = (slope_end - slope_start) * slope_scale;
      squared += d * d + v * v;
    }
    return rotations.empty() ? 0.0 : std::sqrt(squared / rotations.size());
  };
  // Two stages keep long clips fast: every start at the estimated stride, then stride lengths
  // within the slack (quarter-frame steps) around the best starts only.
  constexpr size_t kStarts = 100;
  const int steps = static_cast<int>(std::ceil(period_slack * period_s / (0.25 * dt)));
  std::vector<AnalysisWindow> all;
  for (int strides = 1; strides <= std::max(1, max_strides); ++strides) {
    const double length = strides * period_s;
    if (length > duration + 1e-9) break;
    const int starts = static_cast<int>(std::floor((duration - length) / dt + 1e-9)) + 1;
    const int frames_in = static_cast<int>(std::floor(length / dt));
    // A still stretch fits any model and closes any loop (the dog that stands for 3 s before it
    // trots would be analysed standing): windows need half the activity of the most active one.
    std::vector<double> active(starts);
    double most = 0.0;
    for (int s = 0; s < starts; ++s) most = std::max(most, active[s] = activity(s, frames_in));
    std::vector<AnalysisWindow> first_stage;
    for (int s = 0; s < starts; ++s) {
      if (active[s] >= 0.5 * most) first_stage.push_back({s * dt, strides, period_s, seam(s, length, period_s)});
    }
    const auto by_seam = [](const AnalysisWindow& a, const AnalysisWindow& b) { return a.seam < b.seam; };
    const size_t keep = std::min(kStarts, first_stage.size());
    std::partial_sort(first_stage.begin(), first_stage.begin() + keep, first_stage.end(), by_seam);
    first_stage.resize(keep);
    for (const AnalysisWindow& window : first_stage) {
      const int s = static_cast<int>(std::lround(window.start_s / dt));
      for (int step = -steps; step <= steps; ++step) {
        const double period = period_s + step * 0.25 * dt;
        const double stretched = strides * period;
        if (step != 0 && s * dt + stretched <= duration + 1e-9) {
          all.push_back({s * dt, strides, period, seam(s, stretched, period)});
        } else if (step == 0) {
          all.push_back(window);
        }
      }
    }
  }
  if (all.empty()) return {{0.0, 1, period_s, 0.0}};  // shorter than a stride: take it as it is
  std::sort(all.begin(), all.end(),
            [](const AnalysisWindow& a, const AnalysisWindow& b) { return a.seam < b.seam; });
  std::vector<AnalysisWindow> chosen;
  for (const AnalysisWindow& window : all) {
    bool distinct = true;
    for (const AnalysisWindow& other : chosen) {
      distinct = distinct && std::abs(window.start_s - other.start_s) >= 2.0 * dt - 1e-9;
    }
    if (distinct) chosen.push_back(window);
    if (static_cast<int>(chosen.size()) >= count) break;
  }
  return chosen;
}

}  // namespace sinew::spectral
