// The optimisers' own cost per generation (ask, a trivial sphere cost, tell), full CMA-ES against
// the diagonal variant (sep-CMA-ES) at n = 200 and n = 1000 (the biped genome is about 40
// channels x 11 coefficients = 450). Full CMA-ES decomposes its covariance lazily, every few
// generations, so its benchmark runs a fixed number of generations spanning many decompositions
// and reports their mean; the diagonal variant costs the same every generation.
// Prints full / diagonal per dimension.
#include <benchmark/benchmark.h>

#include "ratio_reporter.h"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "sinew/search/cmaes.h"

namespace {

namespace search = sinew::search;

void generations(benchmark::State& state, int n, bool diagonal) {
  search::CmaesSettings settings;
  settings.diagonal = diagonal;
  std::unique_ptr<search::Cmaes> cmaes = search::Cmaes::create(n, settings).value();
  std::vector<double> costs(static_cast<size_t>(cmaes->population()));
  for (auto _ : state) {
    const std::vector<std::vector<double>>& points = cmaes->ask();
    for (size_t k = 0; k < points.size(); ++k) {
      double f = 0.0;
      for (double x : points[k]) f += (x - 0.4) * (x - 0.4);
      costs[k] = f;
    }
    if (!cmaes->tell(costs).ok()) state.SkipWithError("tell refused the costs");
  }
  state.counters["lambda"] = cmaes->population();
}

}  // namespace

int main(int argc, char** argv) {
  // Generations per full-CMA-ES benchmark, whole decomposition periods (one decomposition every
  // 3 generations at n = 200, every 9 at n = 1000, where one takes over a second).
  const std::vector<std::pair<int, int>> sizes = {{200, 90}, {1000, 45}};
  for (const auto& [n, full_generations] : sizes) {
    benchmark::RegisterBenchmark(("cmaes_full/n=" + std::to_string(n)).c_str(),
                                 [n = n](benchmark::State& s) { generations(s, n, false); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(full_generations);
    benchmark::RegisterBenchmark(("cmaes_diagonal/n=" + std::to_string(n)).c_str(),
                                 [n = n](benchmark::State& s) { generations(s, n, true); })
        ->Unit(benchmark::kMillisecond);
  }
  const auto options = sinew::bench::consoleOptions(argc, argv);
  benchmark::Initialize(&argc, argv);
  sinew::bench::RatioReporter reporter(options);
  benchmark::RunSpecifiedBenchmarks(&reporter);

  // Names gain "/iterations:N" when the count is fixed: look them up by prefix.
  auto timeOf = [&reporter](const std::string& prefix) {
    for (const auto& [name, time] : reporter.times)
      if (name.rfind(prefix, 0) == 0) return time;
    return 0.0;
  };
  std::printf("\n%-8s %18s %18s %10s\n", "n", "full ms/gen", "diagonal ms/gen", "full/diag");
  for (const auto& size : sizes) {
    const int n = size.first;
    const double full = timeOf("cmaes_full/n=" + std::to_string(n));
    const double diagonal = timeOf("cmaes_diagonal/n=" + std::to_string(n));
    if (full > 0.0 && diagonal > 0.0)
      std::printf("%-8d %18.3f %18.3f %9.0fx\n", n, full, diagonal, full / diagonal);
  }
  benchmark::Shutdown();
  return 0;
}
