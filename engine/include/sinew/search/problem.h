// What the evolutionary search optimises: the genome (a controller's Fourier coefficients, its
// stride frequency and its balance gains, in normalised coordinates with ranges derived from the
// analysed motion), the fitness of a simulated run, and the parallel evaluation of a generation.
//
// Genome (GenomeLayout). For every rotation channel of a joint that moves a body (a joint in some
// link's chain, or the base's), in the seed target's channel order: the offset A, then (B_n, D_n)
// for each kept harmonic; then omega_0; then the balance gains (physics::balanceGainName order;
// `heading` only for characters with two or more leg pairs, from 1; `stance_yield` from 0, as
// every other gain from its default; a character with no leg pair (no balance feedback): only
// `swing_lift`). Coordinate x in [0, 1] maps
//   A     = A0 + (2x - 1) offset_range_rad
//   B     = B0 * amplitude_factor^(2x - 1)              (x = 0.5: B0; never negative; a prior
//           below 1e-4 rad gets the linear range [0, 1e-4 amplitude_factor] instead)
//   D     = D0 + (2x - 1) phase_range_rad
//   omega = omega0 * (1 + (2x - 1) omega_range)
//   gains = lo + x (hi - lo)  (cd, cv, the ankle and the stance gains in [-gain_range,
//           gain_range]; torso and heading in [0, 1]; swing_lift in [0, 0.05];
//           stance_yield in [0, 0.9])
// so the seed point (the DFT prior) is x = 0.5 for the coefficients and the defaults' place for
// the gains. No prior (`no_prior`): the same structure (channels, harmonic numbers) but generic
// ranges that know nothing of the clip: base rotations at the rig's rest pose, A in +-1 rad,
// B in [0, 0.5] rad, D in +-pi, omega in [0.5, 2] x omega0, and a random start.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::search {

struct GenomeSettings {
  double offset_range_rad = 0.17;  // A within +-10 degrees of the clip's, > 0
  double amplitude_factor = 2.0;   // B within [B0 / f, B0 f], > 1
  double phase_range_rad = 0.5;    // D within +-0.5 rad of the clip's, > 0
  double omega_range = 0.05;       // omega0 within +-5%, [0, 0.9] (+-20% until 2026-12-07: its
                                   // samples moved the tempo 0.8% a step, and bests drifted 2-3%
                                   // out of phase with the clip; docs/search.md)
  double gain_range = 1.0;         // cd, cv, ankle and stance gains within +-this, > 0
  bool no_prior = false;           // generic ranges and a random start (the baseline)

  Status validate() const;  // the message names the offending field
};

class GenomeLayout {
 public:
  static Result<GenomeLayout> create(const physics::BodyPlan& plan, const motion::Skeleton& skeleton,
                                     const spectral::TargetMotion& seed,
                                     const GenomeSettings& settings = {});

  int size() const { return static_cast<int>(lo_.size()); }
  // The start of the search: the DFT prior (or, without a prior, a uniform random point from
  // `seed`).
  std::vector<double> startPoint(std::uint64_t seed) const;
  // The starts worth trying (Portfolio), startPoint() first: with a prior, one more per
  // structural gene a small step cannot leave, today the stance yield at 0.5 (where the layout has
  // that gene: characters with a leg that balances); without a prior, startPoint() alone.
  struct Start {
    std::string name;  // for the user: "the prior", "stance yield 0.5"
    std::vector<double> point;
  };
  std::vector<Start> startPoints(std::uint64_t seed) const;
  // The controller a point describes. Precondition: x.size() == size(), each in [0, 1].
  spectral::TargetMotion decodeTarget(std::span<const double> x) const;
  physics::BalanceGains decodeGains(std::span<const double> x) const;
  // The point of a target and gains of this layout's structure (clamped into range): how an
  // evolved controller saved as JSON comes back as a genome.
  std::vector<double> encode(const spectral::TargetMotion& target,
                             const physics::BalanceGains& gains) const;
  const std::vector<std::string>& names() const { return names_; }  // (size) e.g. "LeftUpLeg.x.B3"

 private:
  enum class Kind : std::uint8_t { kOffset, kAmplitude, kPhase, kOmega, kGain };
  struct Gene {
    Kind kind = Kind::kOffset;
    int channel = -1;  // index into target channels (coefficients)
    int term = -1;     // index into that channel's terms
    int gain = -1;     // physics::balanceGain order
    bool geometric = false;  // amplitude range by factors of the prior (not for zero priors)
  };
  double value(size_t i, double x) const;
  double coordinate(size_t i, double v) const;

  spectral::TargetMotion seed_;  // the structure; its base rotations (rest pose without a prior)
  GenomeSettings settings_;
  std::vector<Gene> genes_;
  std::vector<double> lo_, hi_, prior_;  // per gene: range and the prior's value
  std::vector<std::string> names_;
};

// Weights of the fitness terms (the cost is their weighted sum; lower is better).
struct FitnessWeights {
  double fall = 10.0;       // per second of the window lost to a fall
  double tracking = 10.0;   // per radian of RMS joint-angle error against the seed target (10,
                            // not 5: real captures tracked 0.5-1.0 deg closer, docs/search.md)
  double speed = 2.0;       // per m/s between the run's speed and the reference's
  double heading = 1.0;     // per radian between the run's direction and the reference's
  double placement = 2.0;   // per metre between the mean step length and the reference's
  double upright = 2.0;     // per unit of (1 - lowest cosine of the pelvis's tilt)
  double energy = 0.002;    // per (N^2 m^2 s / kg) / s of squared torque
  double style = 0.0;       // per radian of style distance in harmonic space between the run and
                            // the seed target (spectral::runStyleDistance); 0: not measured (above
                            // 0 every evaluation records its motion at 30 fps to measure it)
  Status validate() const;  // the message names the offending field
  bool operator==(const FitnessWeights&) const = default;
};

// The weight of term `term` (0..kFitnessTermCount-1, in fitnessTermName order), to read or set.
double& fitnessWeight(FitnessWeights& weights, int term);

// One evaluation's terms (already weighted) and raw figures.
struct FitnessTerms {
  double fall = 0.0, tracking = 0.0, speed = 0.0, heading = 0.0, placement = 0.0, upright = 0.0,
         energy = 0.0, style = 0.0;
  double total = 0.0;
  double survived_s = 0.0;  // seconds before the fall (the window when it did not fall)
  double distance_m = 0.0;
  double speed_m_s = 0.0;
  double track_err_rad_rms = 0.0;
  bool fell = false;
  std::string fall_reason;  // when it fell: what touched the ground or dropped (for the user)
  bool diverged = false;  // the simulation diverged (or could not run): total is +inf, a
                          // failure the optimisers rank last; never written as a number
};
inline constexpr int kFitnessTermCount = 8;
const char* fitnessTermName(int term);            // "fall", "tracking", ...
double fitnessTerm(const FitnessTerms& t, int term);
// {"fall": ..., ..., "total", "survived_s", "distance_m", "speed_m_s", "track_err_rad_rms",
// "fell", and "fall_reason" when it fell}: as checkpoints and best.json carry them. Reading, a
// missing "style" is 0 (files from before the term).
nlohmann::json fitnessJson(const FitnessTerms& t);
Result<FitnessTerms> fitnessFromJson(const nlohmann::json& j);

// Everything an evaluation needs; built once per search.
struct Problem {
  physics::BodyPlan plan;
  motion::Skeleton skeleton;
  spectral::TargetMotion seed;  // the analysed (and edited) motion the controller starts from
  GenomeLayout layout;
  physics::SimulationSettings simulation;  // window (seconds), terrain, pushes
  FitnessWeights weights;
  double reference_speed_m_s = 0.0;  // horizontal: the seed's base travel over one stride / period
  glm::dvec3 reference_direction{0.0, 0.0, 1.0};
  double reference_step_m = 0.0;     // reference speed x period / 2
  // Robustness trials (setTrials): besides the nominal run, every point is run once more per
  // entry with that push added, and its cost is the mean of all its runs' costs. The figures
  // (survival, distance, fall reason) stay the nominal run's. Empty: the nominal run alone.
  std::vector<physics::Push> trial_pushes;

  static Result<Problem> create(const physics::BodyPlan& plan, const motion::Skeleton& skeleton,
                                const spectral::TargetMotion& seed, const GenomeSettings& genome,
                                const physics::SimulationSettings& simulation,
                                const FitnessWeights& weights = {});
};

// Sets problem.trial_pushes for `trials` runs per point (1: the nominal run alone, up to
// kMaxTrials): trial k >= 1 pushes the pelvis by push_m_s x body mass, to the left, right,
// back and forward of the reference direction in turn, at 1 s + 0.7 s (k - 1) (within the first
// half of the window), so the pushes meet different phases of the stride.
inline constexpr int kMaxTrials = 9;
Status setTrials(Problem& problem, int trials, double push_m_s);

// Robustness at no extra cost: adds to the run every point already makes four pushes on the
// pelvis of push_m_s x body mass, along the reference direction at 15% of the window, to its
// left at 35%, against it at 55% and to its right at 75% (1.5, 3.5, 5.5 and 7.5 s of a 10 s
// window), so a controller is scored on walking through them. 0 adds none; at most 10 m/s.
Status addRobustPushes(Problem& problem, double push_m_s);

// Simulates one point and scores it. `cancel` ends it early (the result is then not a fitness:
// `cancelled` set). `record`: keep the recorded motion in `report`.
struct Evaluation {
  FitnessTerms terms;
  bool cancelled = false;
  physics::SimulationReport report;  // motion kept only when asked
};
Evaluation evaluate(const Problem& problem, std::span<const double> x,
                    const std::atomic<bool>* cancel = nullptr, bool record = false);
// The fitness of a simulation report against the problem's references. `omega` (rad/s) is the
// stride frequency the controller ran at, where the style term measures the run's spectrum
// (0: the seed's).
FitnessTerms scoreRun(const Problem& problem, const physics::SimulationReport& report,
                      double omega = 0.0);

// A generation on `threads` workers (each evaluation builds its own world, so the results do not
// depend on the thread count). Results in the points' order.
std::vector<Evaluation> evaluateAll(const Problem& problem,
                                    const std::vector<std::vector<double>>& points, int threads,
                                    const std::atomic<bool>* cancel = nullptr, bool record = false);

}  // namespace sinew::search
