// Deterministic random numbers for the search. The same seed gives the same sequence, and the
// whole state (the engine and the normal generator's cached value) saves to JSON and loads back,
// so a run continued from a checkpoint draws exactly what the uninterrupted run would have.
// std::normal_distribution and std::uniform_real_distribution are not used: their algorithms
// (and the former's hidden cache) are left to each standard library.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"

namespace sinew::search {

class Random {
 public:
  explicit Random(std::uint64_t seed = 1) : engine_(seed) {}

  // Uniform in [0, 1): the top 53 bits of one draw.
  double uniform();
  // Uniform integer in [0, n), n >= 1, without modulo bias (rejection).
  int below(int n);
  // Standard normal, Box-Muller: one pair per two uniforms, the second value cached until the
  // next call (the cache is part of the saved state).
  double normal();

  // {"engine": std::mt19937_64 written with operator<<, "cached_normal": number or null}.
  nlohmann::json saveState() const;
  // `where` starts error messages, which then name the field ("optimizer state: rng.engine").
  static Result<Random> load(const nlohmann::json& state, const std::string& where);

  bool operator==(const Random&) const = default;

 private:
  std::mt19937_64 engine_;
  bool has_cached_ = false;
  double cached_ = 0.0;
};

}  // namespace sinew::search
