// The optimisers of the evolutionary search, behind one ask/tell interface (docs/search.md).
//
// Contract, for every optimiser:
// - It MINIMISES a cost: lower is better.
// - Normalised coordinates: every coordinate of every point it asks for lies in [0, 1]. The
//   caller maps [0, 1] to each parameter's real range.
// - One generation at a time. ask() gives population() points; the caller evaluates them in any
//   order, on any threads, and hands the costs back in the same order with tell(), which moves
//   to the next generation. ask() draws nothing: called again before tell() it returns the same
//   points.
// - Failed evaluations: a cost that is not finite (NaN, +inf, -inf) ranks after every finite
//   cost (failed points in index order) and never becomes the best.
// - Checkpoints: saveState() holds everything, the random engine included. Loading it and
//   continuing gives the uninterrupted run bit for bit (on the same build).
#pragma once

#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"

namespace sinew::search {

// The state format's name and version ("format" and "version" in saveState()).
inline constexpr const char* kStateFormat = "sinew.optimizer";
inline constexpr int kStateVersion = 1;

class Optimizer {
 public:
  virtual ~Optimizer() = default;
  Optimizer(const Optimizer&) = delete;
  Optimizer& operator=(const Optimizer&) = delete;

  virtual const char* kind() const = 0;  // the state's "kind": "cmaes", "genetic", "portfolio"

  int dimension() const { return dimension_; }  // coordinates per point, >= 1
  // Points in the current generation (it may change between generations: IPOP restarts).
  int population() const { return static_cast<int>(points_.size()); }

  // The current generation: population() points of dimension() coordinates, each in [0, 1].
  const std::vector<std::vector<double>>& ask() const { return points_; }
  // The costs of the points of ask(), in the same order; then the next generation. Refused (and
  // nothing changes) when the number of costs is not population().
  Status tell(std::span<const double> costs);

  // The best point told so far (finite cost); empty until a finite cost has been told.
  const std::vector<double>& best() const { return best_; }
  double bestCost() const { return best_cost_; }          // +inf until a finite cost has been told
  int generation() const { return generation_; }          // generations told
  long long evaluations() const { return evaluations_; }  // costs told
  // The fitness changed (new weights, a resumed problem): the best points this optimiser compares
  // new costs with (its own, then any it holds for its parts: a portfolio's members' bests), and
  // rescore() takes their costs under the new fitness, in the same order. Nothing else moves
  // but what compares costs across generations (CMA-ES's stall count and history begin again).
  virtual std::vector<std::vector<double>> bests() const;
  virtual void rescore(std::span<const double> costs);
  // The optimiser's own stopping test (CMA-ES: tolerances reached and no restart left). The
  // caller's budget is the other end; asking and telling after convergence stays valid.
  virtual bool converged() const = 0;

  // Everything, as JSON (docs/search.md): {"format", "version", "kind", "dimension",
  // "generation", "evaluations", "best", "best_cost", "points", "settings", "rng", ...}.
  // Non-finite costs are written as the strings "nan", "inf", "-inf".
  nlohmann::json saveState() const;
  // Any optimiser's saved state; the message names the field that is missing or wrong.
  static Result<std::unique_ptr<Optimizer>> load(const nlohmann::json& state);

 protected:
  explicit Optimizer(int dimension) : dimension_(dimension) {}

  // Moves to the next generation, refilling points_. `order` lists the current points best
  // first, failed last (rankOrder of `costs`).
  virtual void advance(std::span<const double> costs, const std::vector<int>& order) = 0;
  // Adds the optimiser's own fields to the common ones.
  virtual void saveDetails(nlohmann::json& state) const = 0;
  // Reads the common fields (points included) of a state whose "kind" has been checked.
  Status loadCommon(const nlohmann::json& state);

  std::vector<std::vector<double>> points_;  // (population x dimension) in [0, 1]

 private:
  int dimension_ = 0;
  std::vector<double> best_;  // (dimension) or empty
  double best_cost_ = std::numeric_limits<double>::infinity();
  int generation_ = 0;
  long long evaluations_ = 0;
};

// Indices of `costs`, best first: finite costs ascending, then the failed ones (NaN, +-inf),
// ties and failures in index order.
std::vector<int> rankOrder(std::span<const double> costs);

}  // namespace sinew::search
