#include "sinew/spectral/harmonics.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace sinew::spectral {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> sampleSeries(double mean, const std::vector<Harmonic>& terms, int periods,
                                 int samples) {
  std::vector<double> values(samples);
  const double omega0 = 2.0 * kPi;  // period 1 s
  for (int i = 0; i < samples; ++i) {
    values[i] = evaluate(mean, terms, omega0, periods * static_cast<double>(i) / samples);
  }
  return values;
}

const Harmonic* find(const HarmonicSeries& series, int n) {
  for (const Harmonic& h : series.harmonics) {
    if (h.n == n) return &h;
  }
  return nullptr;
}

TEST(HarmonicsTest, RecoversAnalyticSumsOfSinusoidsExactly) {
  const std::vector<Harmonic> truth = {{1, 0.8, 0.3}, {2, 0.25, -2.1}, {3, 0.1, 3.0}, {5, 0.04, -0.7}};
  for (int periods : {1, 3}) {
    const std::vector<double> samples = sampleSeries(0.4, truth, periods, periods * 64);
    double aperiodic = -1.0;
    const HarmonicSeries series = fitHarmonics(samples, periods, &aperiodic);
    EXPECT_NEAR(series.mean, 0.4, 1e-12);
    ASSERT_EQ(series.harmonics.size(), 31u);
    for (const Harmonic& h : truth) {
      const Harmonic* got = find(series, h.n);
      ASSERT_NE(got, nullptr);
      EXPECT_NEAR(got->amplitude, h.amplitude, 1e-6) << "n=" << h.n;
      EXPECT_NEAR(std::remainder(got->phase - h.phase, 2 * kPi), 0.0, 1e-6) << "n=" << h.n;
    }
    EXPECT_NEAR(find(series, 4)->amplitude, 0.0, 1e-12);
    EXPECT_NEAR(aperiodic, 0.0, 1e-20);
    // Strongest first.
    const std::vector<Harmonic> top = series.strongest(2);
    ASSERT_EQ(top.size(), 2u);
    EXPECT_EQ(top[0].n, 1);
    EXPECT_EQ(top[1].n, 2);
  }
}

TEST(HarmonicsTest, WhatChangesFromPeriodToPeriodIsAperiodic) {
  // Two periods whose second has a larger amplitude: the model keeps the average, the rest is
  // energy between the harmonic bins.
  std::vector<double> samples(128);
  for (int i = 0; i < 128; ++i) {
    const double t = 2.0 * i / 128.0;
    samples[i] = (t < 1.0 ? 1.0 : 1.2) * std::sin(2 * kPi * t);
  }
  double aperiodic = 0.0;
  const HarmonicSeries series = fitHarmonics(samples, 2, &aperiodic);
  EXPECT_NEAR(find(series, 1)->amplitude, 1.1, 1e-3);
  EXPECT_GT(aperiodic, 1e-3);
}

TEST(HarmonicsTest, NoiseStaysNearItsLevel) {
  // White noise of standard deviation 0.01 on a unit sinusoid: the fundamental is measured to
  // about the noise level divided by sqrt(samples / 2), documented in docs/spectral.md.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<double> samples = sampleSeries(0.0, {{1, 1.0, 0.5}}, 4, 256);
  for (double& v : samples) v += noise(rng);
  const HarmonicSeries series = fitHarmonics(samples, 4);
  EXPECT_NEAR(find(series, 1)->amplitude, 1.0, 0.01 * 4.0 / std::sqrt(128.0));
  EXPECT_NEAR(find(series, 1)->phase, 0.5, 0.01 * 4.0 / std::sqrt(128.0));
}

// The evaluators against a direct sum written out here: A + sum B sin(n w t + D), and its
// derivative sum B n w cos(n w t + D), for three channels of up to 12 harmonics. The recurrence
// rounds to ~1e-13 per term; a velocity multiplies that by n w (up to 69 rad/s here).
TEST(FourierEvaluatorTest, MatchesTheDirectSum) {
  const double omega0 = 2.0 * kPi / 1.1;  // a 1.1 s stride
  const std::vector<std::vector<Harmonic>> series = {
      {{1, 0.4, 0.3}, {2, 0.1, -2.0}, {5, 0.02, 1.0}},
      {{3, 1.5, 3.1}, {1, 0.7, -0.2}, {12, 0.01, 0.0}},
      {}};
  const double means[] = {0.1, -0.3, 0.25};
  std::vector<FourierEvaluator::Channel> channels(series.size());
  for (size_t c = 0; c < series.size(); ++c) {
    channels[c].mean = means[c];
    for (const Harmonic& h : series[c]) channels[c].terms.push_back(cartesian(h));
  }
  FourierEvaluator evaluator(omega0, channels);
  ASSERT_EQ(evaluator.channelCount(), 3u);
  for (double t : {0.0, 0.013, 0.5, 1.1, 3.7, 10.0, 61.3}) {
    evaluator.setTime(t);
    for (size_t c = 0; c < series.size(); ++c) {
      double value = means[c];
      double velocity = 0.0;
      for (const Harmonic& h : series[c]) {
        value += h.amplitude * std::sin(h.n * omega0 * t + h.phase);
        velocity += h.amplitude * h.n * omega0 * std::cos(h.n * omega0 * t + h.phase);
      }
      EXPECT_EQ(evaluate(means[c], series[c], omega0, t), value) << "t " << t << " c " << c;
      EXPECT_NEAR(evaluateVelocity(series[c], omega0, t), velocity, 1e-13) << t;
      EXPECT_NEAR(evaluator.value(c), value, 1e-13) << "t " << t << " c " << c;
      EXPECT_NEAR(evaluator.velocity(c), velocity, 1e-11) << "t " << t << " c " << c;
    }
  }
  // The velocity is the value's derivative.
  const double t = 0.77, h = 1e-6;
  evaluator.setTime(t + h);
  const double ahead = evaluator.value(1);
  evaluator.setTime(t - h);
  const double behind = evaluator.value(1);
  evaluator.setTime(t);
  EXPECT_NEAR(evaluator.velocity(1), (ahead - behind) / (2.0 * h), 1e-6);
  EXPECT_NEAR(evaluateVelocity(series[1], omega0, t), (ahead - behind) / (2.0 * h), 1e-6);
}

TEST(FourierEvaluatorTest, CartesianFormIsTheSameTerm) {
  const Harmonic h{4, 0.8, -1.2};
  const CartesianHarmonic c = cartesian(h);
  EXPECT_EQ(c.n, 4);
  for (double x : {0.0, 0.4, 2.0}) {
    EXPECT_NEAR(c.b_cos * std::sin(4 * x) + c.b_sin * std::cos(4 * x), 0.8 * std::sin(4 * x - 1.2),
                1e-15);
  }
  EXPECT_EQ(sinusoid(0.8, 3.0, -1.2, 0.5), 0.8 * std::sin(3.0 * 0.5 - 1.2));
}

}  // namespace
}  // namespace sinew::spectral
