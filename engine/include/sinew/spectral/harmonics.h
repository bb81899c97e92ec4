// The harmonic model of one periodic channel: theta(t) = A + sum_n B_n sin(n omega0 t + D_n),
// t in seconds from the start of the analysed window. fitHarmonics measures it with a DFT
// (KissFFT, double precision) of samples that cover whole periods.
#pragma once

#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace sinew::spectral {

struct Harmonic {
  int n = 1;               // harmonic number: frequency n * omega0
  double amplitude = 0.0;  // B_n >= 0, in the channel's unit
  double phase = 0.0;      // D_n, radians in (-pi, pi]
};

struct HarmonicSeries {
  double mean = 0.0;                // A, in the channel's unit
  std::vector<Harmonic> harmonics;  // n = 1, 2, ... ascending (the full measured spectrum)

  // The K harmonics of largest amplitude (all when k >= size), in descending amplitude.
  std::vector<Harmonic> strongest(int k) const;
};

// The one evaluator of Fourier series theta(t) = A + sum B sin(omega t + D): the spectral model,
// the target motion, plots and the editor's curves call these; the physics controller's
// FourierTargets takes angleMultiples and cartesian from here.

// One term, B sin(omega t + D): omega = n omega0 for a harmonic, a secondary term's own omega.
double sinusoid(double amplitude, double omega, double phase, double t);

// A + sum B sin(n omega0 t + D) over `terms`, one sin per term (exact at any t), and its time
// derivative sum B n omega0 cos(n omega0 t + D), the channel's unit per second.
double evaluate(double mean, std::span<const Harmonic> terms, double omega0, double t);
double evaluateVelocity(std::span<const Harmonic> terms, double omega0, double t);

// A harmonic as B cos D and B sin D: B sin(n x + D) = B cos D sin(n x) + B sin D cos(n x).
struct CartesianHarmonic {
  int n = 1;           // harmonic number, >= 1
  double b_cos = 0.0;  // B cos D, the channel's unit
  double b_sin = 0.0;  // B sin D
};
CartesianHarmonic cartesian(const Harmonic& h);

// sin(n x) and cos(n x) for n = 0 .. size - 1 from one sincos of x by the angle-addition
// recurrence sin((n+1)x) = sin(nx) cos(x) + cos(nx) sin(x), cos((n+1)x) = cos(nx) cos(x) -
// sin(nx) sin(x): FourierEvaluator's tables, and FourierTargets'. Precondition: the spans are of
// one size, at least 1.
void angleMultiples(double x, std::span<double> sines, std::span<double> cosines);

// Many channels' series at one time from one sincos: sin(n x) and cos(n x) for every n by the
// angle-addition recurrence instead of one sin per term (its rounding grows with n, to 1e-14 rad
// by n = 64). For evaluating every channel at many times (the analysis' model, frame by frame).
class FourierEvaluator {
 public:
  struct Channel {
    double mean = 0.0;                     // A
    std::vector<CartesianHarmonic> terms;  // the kept harmonics, any order
  };

  // omega0: the fundamental, rad/s.
  FourierEvaluator(double omega0, std::vector<Channel> channels);

  // Sets the time (seconds from the series' origin) that value and velocity answer for.
  void setTime(double t);
  // Channel c's A + sum B sin(n omega0 t + D) and its derivative (per second), at that time.
  // Precondition: c < channelCount().
  double value(size_t c) const;
  double velocity(size_t c) const;
  size_t channelCount() const { return channels_.size(); }

 private:
  double omega0_ = 0.0;
  std::vector<Channel> channels_;
  std::vector<double> sines_;    // (highest n + 1) sin(n omega0 t)
  std::vector<double> cosines_;  // (highest n + 1) cos(n omega0 t)
};

// Measures the series of `samples`, which cover exactly `periods` whole periods at even spacing
// (sample i at t = i * period * periods / size). Harmonic n sits at DFT bin n * periods; bins
// between them (what changes from one period to the next) are not part of the model and are
// returned as `aperiodic_energy` (sum of squared amplitudes, the channel's unit squared).
// Precondition: samples.size() even and >= 4, periods >= 1.
HarmonicSeries fitHarmonics(std::span<const double> samples, int periods,
                            double* aperiodic_energy = nullptr);

// The series measured from a real DFT's bins (HarmonicPlan::transform of `samples` samples
// covering `periods` periods): what fitHarmonics returns.
HarmonicSeries seriesFromBins(std::span<const std::complex<double>> bins, size_t samples,
                              int periods, double* aperiodic_energy = nullptr);

// The DFT plan for one sample count (KissFFT's twiddles, whose set-up costs more than a short
// transform), built once and shared by every channel of that length. Immutable after
// construction: threads may share one. Precondition: samples even and >= 4.
class HarmonicPlan {
 public:
  explicit HarmonicPlan(size_t samples);
  ~HarmonicPlan();
  HarmonicPlan(HarmonicPlan&&) noexcept;
  HarmonicPlan& operator=(HarmonicPlan&&) noexcept;

  size_t samples() const { return samples_; }

  // The real DFT of `samples` (size samples()): bins[k] for k = 0 .. samples / 2 - 1, X_k =
  // sum x_i e^{-2 pi i k i / size}, with the Nyquist bin in bins[0].imag(). Precondition:
  // bins.size() == samples() / 2.
  void transform(std::span<const double> samples, std::span<std::complex<double>> bins) const;

  // fitHarmonics with this plan: the same result. `bins` is the caller's scratch (resized to
  // samples / 2), so a loop over channels allocates nothing. Precondition: samples.size() ==
  // samples(), periods >= 1.
  HarmonicSeries fit(std::span<const double> samples, int periods, double* aperiodic_energy,
                     std::vector<std::complex<double>>& bins) const;

 private:
  struct Fft;
  size_t samples_ = 0;
  std::unique_ptr<const Fft> fft_;
};

}  // namespace sinew::spectral
