// The bytes a generation travels as between processes (`sinew evolve` under mpirun): the points a
// worker evaluates and the terms it sends back. Doubles go bit for bit (+inf included), so a
// distributed search reaches the single process's best point and cost exactly. No MPI here: the
// transport is the caller's. Every process must have the same byte order and double format (one
// architecture across the cluster).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/search/problem.h"

namespace sinew::search::wire {

using Bytes = std::vector<std::uint8_t>;

// A share of a generation: its id, then the points (each of the same dimension).
struct Points {
  std::uint64_t id = 0;
  std::vector<std::vector<double>> points;
};
Bytes packPoints(std::uint64_t id, std::span<const std::vector<double>> points);
Result<Points> unpackPoints(std::span<const std::uint8_t> bytes);

// What a worker sends back: per point the fitness terms and whether it was cancelled (the
// recorded motion stays with the worker).
struct Results {
  std::uint64_t id = 0;
  std::vector<Evaluation> results;
};
Bytes packResults(std::uint64_t id, std::span<const Evaluation> results);
Result<Results> unpackResults(std::span<const std::uint8_t> bytes);

// Two processes that built the same problem (rig, clip, settings) agree on this number; one
// built from another file or other flags almost surely does not.
std::uint64_t fingerprint(const Problem& problem);

}  // namespace sinew::search::wire
