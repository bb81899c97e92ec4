#include "sinew/spectral/harmonics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <utility>

#include <kissfft/kissfft.hh>

#include "sinew/core/assert.h"

namespace sinew::spectral {

std::vector<Harmonic> HarmonicSeries::strongest(int k) const {
  // Descending amplitude, ties in ascending n (the order `harmonics` is in): what a stable sort
  // by amplitude gives, for the first k only.
  std::vector<Harmonic> sorted = harmonics;
  const auto stronger = [](const Harmonic& a, const Harmonic& b) {
    return a.amplitude > b.amplitude || (a.amplitude == b.amplitude && a.n < b.n);
  };
  const size_t keep = std::min(sorted.size(), static_cast<size_t>(std::max(k, 0)));
  std::partial_sort(sorted.begin(), sorted.begin() + keep, sorted.end(), stronger);
  sorted.resize(keep);
  return sorted;
}

double sinusoid(double amplitude, double omega, double phase, double t) {
  return amplitude * std::sin(omega * t + phase);
}

double evaluate(double mean, std::span<const Harmonic> terms, double omega0, double t) {
  double value = mean;
  for (const Harmonic& h : terms) value += sinusoid(h.amplitude, h.n * omega0, h.phase, t);
  return value;
}

double evaluateVelocity(std::span<const Harmonic> terms, double omega0, double t) {
  double velocity = 0.0;
  for (const Harmonic& h : terms) {
    const double omega = h.n * omega0;
    velocity += h.amplitude * omega * std::cos(omega * t + h.phase);
  }
  return velocity;
}

CartesianHarmonic cartesian(const Harmonic& h) {
  return {h.n, h.amplitude * std::cos(h.phase), h.amplitude * std::sin(h.phase)};
}

FourierEvaluator::FourierEvaluator(double omega0, std::vector<Channel> channels)
    : omega0_(omega0), channels_(std::move(channels)) {
  int highest = 0;
  for (const Channel& channel : channels_) {
    for (const CartesianHarmonic& term : channel.terms) highest = std::max(highest, term.n);
  }
  sines_.assign(static_cast<size_t>(highest) + 1, 0.0);
  cosines_.assign(static_cast<size_t>(highest) + 1, 1.0);
}

void angleMultiples(double x, std::span<double> sines, std::span<double> cosines) {
  SINEW_ASSERT(!sines.empty() && sines.size() == cosines.size(), "one table size, at least 1");
  const double s1 = std::sin(x);
  const double c1 = std::cos(x);
  sines[0] = 0.0;
  cosines[0] = 1.0;
  for (size_t n = 1; n < sines.size(); ++n) {
    sines[n] = sines[n - 1] * c1 + cosines[n - 1] * s1;
    cosines[n] = cosines[n - 1] * c1 - sines[n - 1] * s1;
  }
}

void FourierEvaluator::setTime(double t) {
  angleMultiples(omega0_ * t, sines_, cosines_);
}

double FourierEvaluator::value(size_t c) const {
  const Channel& channel = channels_[c];
  double value = channel.mean;
  for (const CartesianHarmonic& term : channel.terms) {
    const size_t n = static_cast<size_t>(term.n);
    value += term.b_cos * sines_[n] + term.b_sin * cosines_[n];
  }
  return value;
}

double FourierEvaluator::velocity(size_t c) const {
  double velocity = 0.0;
  for (const CartesianHarmonic& term : channels_[c].terms) {
    const size_t n = static_cast<size_t>(term.n);
    velocity += term.n * omega0_ * (term.b_cos * cosines_[n] - term.b_sin * sines_[n]);
  }
  return velocity;
}

struct HarmonicPlan::Fft {
  explicit Fft(size_t half) : transform(half, false) {}
  kissfft<double> transform;  // complex, half the real length (KissFFT's transform_real)
};

HarmonicPlan::HarmonicPlan(size_t samples)
    : samples_(samples), fft_(std::make_unique<const Fft>(samples / 2)) {}
HarmonicPlan::~HarmonicPlan() = default;
HarmonicPlan::HarmonicPlan(HarmonicPlan&&) noexcept = default;
HarmonicPlan& HarmonicPlan::operator=(HarmonicPlan&&) noexcept = default;

void HarmonicPlan::transform(std::span<const double> samples,
                             std::span<std::complex<double>> bins) const {
  // Real DFT of length `size` as a complex DFT of half the length.
  fft_->transform.transform_real(samples.data(), bins.data());
}

HarmonicSeries HarmonicPlan::fit(std::span<const double> samples, int periods,
                                 double* aperiodic_energy,
                                 std::vector<std::complex<double>>& bins) const {
  bins.resize(samples.size() / 2);
  transform(samples, bins);
  return seriesFromBins(bins, samples.size(), periods, aperiodic_energy);
}

HarmonicSeries seriesFromBins(std::span<const std::complex<double>> bins, size_t samples,
                              int periods, double* aperiodic_energy) {
  const size_t size = samples;
  const double scale = 2.0 / static_cast<double>(size);
  HarmonicSeries series;
  series.mean = bins[0].real() / static_cast<double>(size);
  series.harmonics.reserve(size / 2 / periods);
  double other = 0.0;
  // Bins 1 .. size/2 - 1 (the Nyquist bin, packed in bins[0].imag(), has no phase to speak of).
  for (size_t k = 1; k < size / 2; ++k) {
    const double amplitude = std::abs(bins[k]) * scale;
    if (k % periods != 0) {
      other += amplitude * amplitude;
      continue;
    }
    // X_k = (size / 2) B e^{i phi} for B cos(w t + phi); sin(w t + D) = cos(w t + D - pi / 2).
    double phase = std::arg(bins[k]) + std::numbers::pi / 2.0;
    if (phase > std::numbers::pi) phase -= 2.0 * std::numbers::pi;
    series.harmonics.push_back({static_cast<int>(k / periods), amplitude, phase});
  }
  if (aperiodic_energy != nullptr) *aperiodic_energy = other;
  return series;
}

HarmonicSeries fitHarmonics(std::span<const double> samples, int periods,
                            double* aperiodic_energy) {
  std::vector<std::complex<double>> bins;
  return HarmonicPlan(samples.size()).fit(samples, periods, aperiodic_energy, bins);
}

}  // namespace sinew::spectral
