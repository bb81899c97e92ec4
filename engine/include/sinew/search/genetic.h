// A genetic algorithm in the manner of Sims (1994): tournament selection, uniform or blend
// crossover, Gaussian mutation, elitism, everything clamped to [0, 1].
//
// From one generation to the next: the `elites` best points are copied unchanged (and asked
// again, so a noisy cost is measured anew; with a deterministic cost the best of a generation
// never gets worse). Every other child starts as a copy of a tournament winner; with probability
// crossover_rate it is crossed with a second winner; then each coordinate mutates with
// probability mutation_rate by a normal step of mutation_scale, and is clamped to [0, 1].
// The genetic algorithm has no stopping test of its own: converged() is always false.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "sinew/search/optimizer.h"
#include "sinew/search/random.h"

namespace sinew::search {

enum class Crossover {
  kUniform,  // each coordinate from either parent, 50/50
  kBlend,    // BLX-alpha: uniform in the parents' interval widened by blend_alpha x its length
             // on each side
};

struct GeneticSettings {
  int population = 64;      // points per generation, >= 2
  int elites = 2;           // best points copied unchanged, [0, population)
  int tournament_size = 3;  // points drawn (with replacement) per selection, [1, population]
  Crossover crossover = Crossover::kUniform;
  double crossover_rate = 0.9;        // share of children with two parents, [0, 1]
  double blend_alpha = 0.5;           // kBlend's widening, >= 0
  double mutation_rate = 0.0;         // probability that a coordinate of a child mutates, [0, 1];
                                      // 0: 1 / dimension
  double mutation_scale = 0.1;        // standard deviation of a mutation, normalised units, > 0
  std::vector<double> initial_point;  // (n) each in [0, 1]: the first generation is this point
                                      // and normal perturbations of it (initial_spread);
                                      // empty: uniform in [0, 1]^n
  double initial_spread = 0.1;        // around initial_point, normalised units, > 0
  std::uint64_t seed = 1;             // the same seed gives the same run, bit for bit

  Status validate(int dimension) const;  // the message names the offending field
};

class Genetic final : public Optimizer {
 public:
  // Fails on a dimension < 1 or invalid settings.
  static Result<std::unique_ptr<Genetic>> create(int dimension,
                                                 const GeneticSettings& settings = {});
  // A state saved by a Genetic (kind "genetic"); the message names the field that is wrong.
  static Result<std::unique_ptr<Genetic>> load(const nlohmann::json& state);

  const char* kind() const override { return "genetic"; }
  bool converged() const override { return false; }
  const GeneticSettings& settings() const { return settings_; }

 private:
  Genetic(int dimension, const GeneticSettings& settings);
  int tournament(const std::vector<int>& rank);
  void advance(std::span<const double> costs, const std::vector<int>& order) override;
  void saveDetails(nlohmann::json& state) const override;

  GeneticSettings settings_;
  Random random_;
};

}  // namespace sinew::search
