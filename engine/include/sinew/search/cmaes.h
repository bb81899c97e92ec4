// CMA-ES, as in Hansen, "The CMA Evolution Strategy: A Tutorial" (2016): weighted recombination
// of the best mu = lambda / 2 points (positive log weights), cumulative step-size adaptation,
// rank-one and rank-mu covariance updates with the h_sigma stall, and an eigendecomposition of
// the covariance redone lazily (once lambda / (c1 + cmu) / n / 10 evaluations have passed).
//
// Diagonal variant (`diagonal`): sep-CMA-ES (Ros & Hansen 2008). The covariance stays diagonal,
// so a generation costs O(lambda n) instead of O(n^2) per point plus an O(n^3) decomposition,
// and its learning rates c1, cmu are (n + 2) / 3 times larger. It learns per-coordinate scales,
// not correlations: the choice for large genomes.
//
// Bounds: the distribution lives in an unbounded internal space and every sample goes through
// boundaryTransform() into [0, 1] before it is asked: identity on [a, 1 - a], quadratic on the
// zones of width a = kBoundaryZone at each bound, mirrored beyond (Hansen's pycma BoundTransform).
// The update uses the unrepaired samples, so the algorithm itself is unchanged and no penalty is
// needed; an optimum on a bound is reached smoothly (the internal mean settles at -a or 1 + a).
//
// Restarts (IPOP, Auger & Hansen 2005), off by default: when a stopping test fires and restarts
// remain, the run starts again with twice the population from a uniformly random mean. The best
// point is kept across restarts.
//
// Local restarts on a stall (`stall_generations` > 0): a run whose best cost has not improved for
// that many generations stops ("stall"), and while restarts remain it starts again from the
// initial mean with the initial step size and the same population, the random stream going on.
// For a search seeded from a prior (the DFT of the clip) the good points lie near the prior, not
// anywhere in the box; what differs between runs is where the first generations lead.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sinew/search/optimizer.h"
#include "sinew/search/random.h"

namespace sinew::search {

inline constexpr double kBoundaryZone = 0.05;  // width of the quadratic zone at each bound
inline constexpr int kMaxCmaesRestarts = 20;   // CmaesSettings::max_restarts at most

// Internal coordinate -> [0, 1] (see above); continuous with a continuous first derivative,
// periodic with period 2 (1 + 2 kBoundaryZone).
double boundaryTransform(double y);
// [0, 1] -> the internal coordinate in [-kBoundaryZone, 1 + kBoundaryZone] it comes from.
double inverseBoundaryTransform(double x);

struct CmaesSettings {
  int population = 0;                // lambda, points per generation, >= 2; 0: 4 + floor(3 ln n)
  double initial_sigma = 0.25;       // initial step size, normalised units, (0, 1] (Hansen: about a
                                     // quarter of the range)
  std::vector<double> initial_mean;  // (n) start, each in [0, 1] (e.g. a prior from the motion's
                                     // spectrum); empty: 0.5 everywhere
  bool diagonal = false;             // sep-CMA-ES: diagonal covariance (see above)
  int max_restarts = 0;              // IPOP restarts, each doubling the population, >= 0 (with
                                     // stall_generations: local restarts, same population)
  int stall_generations = 0;         // > 0: restart from the initial mean after this many
                                     // generations without a better best in the run; 0: off
  double tol_x = 1e-11;              // stop when sigma * max(sqrt(C_ii), |pc_i|) < tol_x for every
                                     // coordinate, normalised units, >= 0
  double tol_fun = 1e-12;            // stop when the generation's costs and the best costs of the
                                     // last 10 + ceil(30 n / lambda) generations lie within this
                                     // range, cost units, >= 0
  std::uint64_t seed = 1;            // the same seed gives the same run, bit for bit

  Status validate(int dimension) const;  // the message names the offending field
};

class Cmaes final : public Optimizer {
 public:
  // Fails on a dimension < 1 or invalid settings.
  static Result<std::unique_ptr<Cmaes>> create(int dimension, const CmaesSettings& settings = {});
  // A state saved by a Cmaes (kind "cmaes"); the message names the field that is wrong.
  static Result<std::unique_ptr<Cmaes>> load(const nlohmann::json& state);

  const char* kind() const override { return "cmaes"; }
  bool converged() const override { return !stop_.empty() && restarts_ >= settings_.max_restarts; }
  // The best's new cost; when it moved, the run's stall count and cost history begin again:
  // costs from before the change are on another scale (a heavier weight would read as a stall).
  void rescore(std::span<const double> costs) override;

  const CmaesSettings& settings() const { return settings_; }
  std::vector<double> mean() const;        // (n) the distribution's mean mapped into [0, 1]
  double sigma() const { return sigma_; }  // step size, normalised units
  // sqrt(largest / smallest eigenvalue) of the covariance, at the last decomposition.
  double axisRatio() const;
  int restarts() const { return restarts_; }  // restarts done (IPOP or local)
  // The stopping test that fired last ("tol_x", "tol_fun", "condition", "stall"), empty while
  // running.
  const std::string& stopReason() const { return stop_; }

 private:
  Cmaes(int dimension, const CmaesSettings& settings);
  void configure(int lambda);  // strategy parameters for a population
  void restart(const std::vector<double>& internal_mean);
  std::vector<double> initialInternalMean() const;
  void decompose();
  void sample();
  std::string stopTest(std::span<const double> costs, const std::vector<int>& order) const;

  void advance(std::span<const double> costs, const std::vector<int>& order) override;
  void saveDetails(nlohmann::json& state) const override;

  CmaesSettings settings_;
  Random random_;

  // Strategy parameters (from n, lambda, diagonal; recomputed on load).
  int lambda_ = 0;
  int mu_ = 0;
  std::vector<double> weights_;  // (mu) positive, summing to 1
  double mueff_ = 0.0;
  double cc_ = 0.0, cs_ = 0.0, c1_ = 0.0, cmu_ = 0.0, damps_ = 0.0, chin_ = 0.0;
  int history_length_ = 0;

  // Distribution, internal coordinates.
  std::vector<double> mean_;  // (n)
  double sigma_ = 0.0;
  std::vector<double> pc_, ps_;  // (n) evolution paths
  std::vector<double> cov_;      // (n x n column-major), or (n) when diagonal
  std::vector<double> basis_;    // (n x n column-major) eigenvectors of cov_ at the last
                                 // decomposition; empty when diagonal
  std::vector<double> scales_;   // (n) sqrt of the eigenvalues (diagonal: sqrt(cov_))
  long long decomposed_at_ = 0;  // evaluations() at the last decomposition
  std::vector<double> samples_;  // (lambda x n, one point after another) y = B D z of the
                                 // current points: internal point = mean + sigma y
  int run_generation_ = 0;       // generations since the last (re)start
  std::vector<double> history_;  // best cost of each of the last history_length_ generations
  int restarts_ = 0;
  double run_best_ = std::numeric_limits<double>::infinity();  // the best finite cost since the last (re)start (+inf: none yet)
  int run_best_at_ = 0;    // run_generation_ when it was found
  std::string stop_;
};

}  // namespace sinew::search
