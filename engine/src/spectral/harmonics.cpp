#include "sinew/spectral/harmonics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include <kissfft/kissfft.hh>

namespace sinew::spectral {

std::vector<Harmonic> HarmonicSeries::strongest(int k) const {
  std::vector<Harmonic> sorted = harmonics;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Harmonic& a, const Harmonic& b) { return a.amplitude > b.amplitude; });
  if (k < static_cast<int>(sorted.size())) sorted.resize(std::max(k, 0));
  return sorted;
}

double evaluate(double mean, std::span<const Harmonic> terms, double omega0, double t) {
  double value = mean;
  for (const Harmonic& h : terms) value += h.amplitude * std::sin(h.n * omega0 * t + h.phase);
  return value;
}

HarmonicSeries fitHarmonics(std::span<const double> samples, int periods,
                            double* aperiodic_energy) {
  const size_t size = samples.size();
  // Real DFT of length `size` as a complex DFT of half the length (KissFFT's transform_real).
  const kissfft<double> fft(size / 2, false);
  std::vector<std::complex<double>> bins(size / 2);
  fft.transform_real(samples.data(), bins.data());
  const double scale = 2.0 / static_cast<double>(size);
  HarmonicSeries series;
  series.mean = bins[0].real() / static_cast<double>(size);
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

}  // namespace sinew::spectral
