#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sinew/search/cmaes.h"
#include "sinew/search/genetic.h"
#include "sinew/search/optimizer.h"
#include "sinew/search/portfolio.h"
#include "sinew/search/random.h"

namespace sinew::search {
namespace {

using nlohmann::json;
using Point = std::vector<double>;
using CostFunction = std::function<double(const Point&)>;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The test functions' optimum: inside [0, 1]^n but away from the centre, 0.3 ... 0.7.
Point shiftedOptimum(int n) {
  Point c(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) c[static_cast<size_t>(i)] = 0.3 + 0.4 * i / std::max(n - 1, 1);
  return c;
}

CostFunction sphere(Point centre) {
  return [centre](const Point& x) {
    double f = 0.0;
    for (size_t i = 0; i < x.size(); ++i) f += (x[i] - centre[i]) * (x[i] - centre[i]);
    return f;
  };
}

// Axis-parallel ellipsoid, condition 1e6: scales 10^(6 i / (n - 1)) on the squares.
CostFunction ellipsoid(Point centre) {
  return [centre](const Point& x) {
    const double n = static_cast<double>(x.size());
    double f = 0.0;
    for (size_t i = 0; i < x.size(); ++i)
      f += std::pow(1e6, static_cast<double>(i) / (n - 1.0)) * (x[i] - centre[i]) *
           (x[i] - centre[i]);
    return f;
  };
}

// Rosenbrock on z = 4x - 2 in [-2, 2]: optimum z = 1, x = 0.75.
double rosenbrock(const Point& x) {
  double f = 0.0;
  for (size_t i = 0; i + 1 < x.size(); ++i) {
    const double z = 4.0 * x[i] - 2.0, next = 4.0 * x[i + 1] - 2.0;
    f += 100.0 * (next - z * z) * (next - z * z) + (1.0 - z) * (1.0 - z);
  }
  return f;
}

// Rastrigin on u = 10.24 (x - centre): many local minima, the global one at the centre.
CostFunction rastrigin(Point centre) {
  return [centre](const Point& x) {
    double f = 10.0 * static_cast<double>(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
      const double u = 10.24 * (x[i] - centre[i]);
      f += u * u - 10.0 * std::cos(2.0 * std::numbers::pi * u);
    }
    return f;
  };
}

bool insideUnitCube(const std::vector<Point>& points) {
  for (const Point& p : points)
    for (double x : p)
      if (!(x >= 0.0 && x <= 1.0)) return false;
  return true;
}

// One generation: evaluate ask(), tell the costs. Returns the costs.
std::vector<double> step(Optimizer& optimizer, const CostFunction& f) {
  std::vector<double> costs;
  for (const Point& p : optimizer.ask()) costs.push_back(f(p));
  EXPECT_TRUE(optimizer.tell(costs).ok());
  return costs;
}

// Generations until the best cost reaches `target` or the budget is spent.
void runUntil(Optimizer& optimizer, const CostFunction& f, double target, long long budget) {
  while (optimizer.bestCost() > target && optimizer.evaluations() < budget) {
    ASSERT_TRUE(insideUnitCube(optimizer.ask()));
    step(optimizer, f);
  }
}

std::unique_ptr<Cmaes> cmaes(int n, CmaesSettings settings = {}) {
  Result<std::unique_ptr<Cmaes>> c = Cmaes::create(n, settings);
  EXPECT_TRUE(c.ok()) << c.message();
  return std::move(c).value();
}

std::unique_ptr<Genetic> genetic(int n, GeneticSettings settings = {}) {
  Result<std::unique_ptr<Genetic>> g = Genetic::create(n, settings);
  EXPECT_TRUE(g.ok()) << g.message();
  return std::move(g).value();
}

// ---------------------------------------------------------------------------------------------
// Refusals

TEST(SearchSettings, InvalidSettingsAreRefusedNamingTheField) {
  auto cmaesRefused = [](int n, const CmaesSettings& s, const std::string& field) {
    Result<std::unique_ptr<Cmaes>> c = Cmaes::create(n, s);
    EXPECT_FALSE(c.ok()) << field;
    EXPECT_NE(c.message().find(field), std::string::npos) << c.message();
  };
  CmaesSettings c;
  cmaesRefused(0, c, "dimension");
  c.population = 1;
  cmaesRefused(4, c, "population");
  c = {};
  c.initial_sigma = 0.0;
  cmaesRefused(4, c, "initial_sigma");
  c.initial_sigma = kNan;
  cmaesRefused(4, c, "initial_sigma");
  c = {};
  c.initial_mean = {0.5, 0.5, 0.5};
  cmaesRefused(4, c, "initial_mean");
  c.initial_mean = {0.5, 0.5, 1.5, 0.5};
  cmaesRefused(4, c, "initial_mean[2]");
  c = {};
  c.max_restarts = -1;
  cmaesRefused(4, c, "max_restarts");
  c = {};
  c.tol_x = -1.0;
  cmaesRefused(4, c, "tol_x");
  c = {};
  c.tol_fun = kInf;
  cmaesRefused(4, c, "tol_fun");
  EXPECT_TRUE(Cmaes::create(1).ok());

  auto geneticRefused = [](int n, const GeneticSettings& s, const std::string& field) {
    Result<std::unique_ptr<Genetic>> g = Genetic::create(n, s);
    EXPECT_FALSE(g.ok()) << field;
    EXPECT_NE(g.message().find(field), std::string::npos) << g.message();
  };
  GeneticSettings g;
  geneticRefused(0, g, "dimension");
  g.population = 1;
  geneticRefused(4, g, "population");
  g = {};
  g.elites = g.population;
  geneticRefused(4, g, "elites");
  g = {};
  g.tournament_size = 0;
  geneticRefused(4, g, "tournament_size");
  g.tournament_size = g.population + 1;
  geneticRefused(4, g, "tournament_size");
  g = {};
  g.crossover_rate = 1.5;
  geneticRefused(4, g, "crossover_rate");
  g = {};
  g.blend_alpha = -0.1;
  geneticRefused(4, g, "blend_alpha");
  g = {};
  g.mutation_rate = kNan;
  geneticRefused(4, g, "mutation_rate");
  g = {};
  g.mutation_scale = 0.0;
  geneticRefused(4, g, "mutation_scale");
  g = {};
  g.initial_point = {0.1};
  geneticRefused(4, g, "initial_point");
  g.initial_point = {0.1, -0.1, 0.5, 0.5};
  geneticRefused(4, g, "initial_point[1]");
  g = {};
  g.initial_spread = -1.0;
  geneticRefused(4, g, "initial_spread");
}

TEST(SearchOptimizer, TellRefusesTheWrongNumberOfCosts) {
  std::unique_ptr<Cmaes> c = cmaes(5);
  const Point before = c->ask()[0];
  Status s = c->tell(std::vector<double>(static_cast<size_t>(c->population()) - 1, 1.0));
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("costs"), std::string::npos) << s.message();
  EXPECT_EQ(c->generation(), 0);
  EXPECT_EQ(c->ask()[0], before);  // nothing changed
  EXPECT_EQ(c->ask(), c->ask());   // ask() draws nothing
}

// ---------------------------------------------------------------------------------------------
// Building blocks

TEST(SearchRandom, SameSeedSameNumbersAndStateRoundTrips) {
  Random a(42), b(42), other(43);
  for (int i = 0; i < 1000; ++i) {
    EXPECT_EQ(a.uniform(), b.uniform());
    EXPECT_EQ(a.normal(), b.normal());
  }
  EXPECT_NE(Random(42).uniform(), other.uniform());

  // Moments of the normals and the range of below().
  Random r(7);
  double sum = 0.0, sum_sq = 0.0;
  const int count = 200000;
  for (int i = 0; i < count; ++i) {
    const double z = r.normal();
    sum += z;
    sum_sq += z * z;
  }
  EXPECT_NEAR(sum / count, 0.0, 0.01);
  EXPECT_NEAR(sum_sq / count, 1.0, 0.01);
  std::vector<int> hits(7, 0);
  for (int i = 0; i < 7000; ++i) {
    const int k = r.below(7);
    ASSERT_GE(k, 0);
    ASSERT_LT(k, 7);
    ++hits[static_cast<size_t>(k)];
  }
  for (int h : hits) EXPECT_NEAR(h, 1000, 150);

  // Saved in the middle of a Box-Muller pair: the cached half comes back too.
  r.normal();
  const json saved = r.saveState();
  EXPECT_FALSE(saved["cached_normal"].is_null());
  Result<Random> loaded = Random::load(json::parse(saved.dump()), "rng");
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  Random copy = loaded.value();
  EXPECT_TRUE(copy == r);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(copy.normal(), r.normal());

  json broken = saved;
  broken["engine"] = "1 2 3";
  Result<Random> refused = Random::load(broken, "rng");
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("rng: engine"), std::string::npos) << refused.message();
}

TEST(SearchOptimizer, FailedCostsRankLast) {
  const std::vector<double> costs = {3.0, kNan, 1.0, kInf, -kInf, 2.0, 1.0};
  EXPECT_EQ(rankOrder(costs), (std::vector<int>{2, 6, 5, 0, 1, 3, 4}));
}

TEST(SearchBounds, TransformIsIdentityInsideAndStaysInTheUnitInterval) {
  const double a = kBoundaryZone;
  for (double x = a; x <= 1.0 - a; x += 0.01) EXPECT_EQ(boundaryTransform(x), x);
  double previous = boundaryTransform(-10.0);
  for (double y = -10.0; y <= 10.0; y += 1e-4) {
    const double x = boundaryTransform(y);
    ASSERT_GE(x, 0.0) << y;
    ASSERT_LE(x, 1.0) << y;
    ASSERT_LT(std::abs(x - previous), 1.01e-4) << y;  // continuous, slope at most 1
    previous = x;
  }
  EXPECT_EQ(boundaryTransform(1.0 + a), 1.0);  // the bounds are reached
  EXPECT_EQ(boundaryTransform(-a), 0.0);
  EXPECT_NEAR(boundaryTransform(0.3 + 2.0 * (1.0 + 2.0 * a)), 0.3, 1e-12);  // periodic
  EXPECT_NEAR(boundaryTransform(1.2), boundaryTransform(0.9), 1e-12);       // mirrored at 1 + a
  for (double x = 0.0; x <= 1.0; x += 0.001)
    EXPECT_NEAR(boundaryTransform(inverseBoundaryTransform(x)), x, 1e-12) << x;
}

// ---------------------------------------------------------------------------------------------
// CMA-ES convergence

TEST(SearchCmaes, SolvesSphereAndEllipsoidIn10D) {
  const int n = 10;
  const Point centre = shiftedOptimum(n);
  std::unique_ptr<Cmaes> on_sphere = cmaes(n);
  runUntil(*on_sphere, sphere(centre), 1e-8, 20000);
  std::printf("  sphere 10-D: %.2e after %d generations, %lld evaluations (lambda %d)\n",
              on_sphere->bestCost(), on_sphere->generation(), on_sphere->evaluations(),
              on_sphere->population());
  EXPECT_LE(on_sphere->bestCost(), 1e-8);
  EXPECT_LT(on_sphere->evaluations(), 3000);  // Hansen: about 1,500 from this distance

  std::unique_ptr<Cmaes> on_ellipsoid = cmaes(n);
  runUntil(*on_ellipsoid, ellipsoid(centre), 1e-8, 50000);
  std::printf(
      "  ellipsoid 10-D (condition 1e6): %.2e after %d generations, %lld evaluations, "
      "axis ratio %.0f (sqrt of 1e6: 1000)\n",
      on_ellipsoid->bestCost(), on_ellipsoid->generation(), on_ellipsoid->evaluations(),
      on_ellipsoid->axisRatio());
  EXPECT_LE(on_ellipsoid->bestCost(), 1e-8);
  EXPECT_LT(on_ellipsoid->evaluations(), 10000);
  // The covariance learnt the scaling: its axis ratio is about sqrt(condition).
  EXPECT_GT(on_ellipsoid->axisRatio(), 300.0);
  EXPECT_LT(on_ellipsoid->axisRatio(), 3000.0);
  for (size_t i = 0; i < centre.size(); ++i)
    EXPECT_NEAR(on_ellipsoid->best()[i], centre[i], 1e-4) << i;
}

TEST(SearchCmaes, SolvesRosenbrockIn10D) {
  std::unique_ptr<Cmaes> c = cmaes(10);
  runUntil(*c, rosenbrock, 1e-8, 20000);
  std::printf("  Rosenbrock 10-D: %.2e after %d generations, %lld evaluations\n", c->bestCost(),
              c->generation(), c->evaluations());
  EXPECT_LE(c->bestCost(), 1e-8);
  for (double x : c->best()) EXPECT_NEAR(x, 0.75, 1e-4);
}

TEST(SearchCmaes, DiagonalVariantSolvesTheSeparableEllipsoidIn30DFaster) {
  const int n = 30;
  const CostFunction f = ellipsoid(shiftedOptimum(n));
  CmaesSettings settings;
  settings.diagonal = true;
  std::unique_ptr<Cmaes> diagonal = cmaes(n, settings);
  runUntil(*diagonal, f, 1e-8, 400000);
  std::unique_ptr<Cmaes> full = cmaes(n);
  runUntil(*full, f, 1e-8, 400000);
  std::printf("  separable ellipsoid 30-D to 1e-8: diagonal %lld evaluations, full %lld (%.1fx)\n",
              diagonal->evaluations(), full->evaluations(),
              static_cast<double>(full->evaluations()) / diagonal->evaluations());
  EXPECT_LE(diagonal->bestCost(), 1e-8);
  EXPECT_LE(full->bestCost(), 1e-8);
  // Ros & Hansen (2008): on separable functions the diagonal learning rates pay off several times.
  EXPECT_LT(diagonal->evaluations() * 3, full->evaluations());
}

TEST(SearchCmaes, OptimumOutsideTheBoxIsReachedOnItsBoundary) {
  const int n = 10;
  Point centre(static_cast<size_t>(n));
  for (size_t i = 0; i < centre.size(); ++i) centre[i] = i % 2 == 0 ? 1.3 : -0.3;
  for (bool diagonal : {false, true}) {
    CmaesSettings settings;
    settings.diagonal = diagonal;
    std::unique_ptr<Cmaes> c = cmaes(n, settings);
    const CostFunction f = sphere(centre);
    double worst = 1.0;
    while (c->generation() < 1000 && worst > 1e-6) {
      ASSERT_TRUE(insideUnitCube(c->ask())) << "generation " << c->generation();
      step(*c, f);
      worst = 0.0;
      for (size_t i = 0; i < centre.size(); ++i)
        worst = std::max(worst, std::abs(c->best()[i] - (centre[i] > 1.0 ? 1.0 : 0.0)));
    }
    std::printf("  %s: every coordinate within %.1e of its bound after %d generations\n",
                diagonal ? "diagonal" : "full", worst, c->generation());
    EXPECT_LE(worst, 1e-6);
  }
}

// ---------------------------------------------------------------------------------------------
// Determinism and checkpoints

using Factory = std::function<std::unique_ptr<Optimizer>(std::uint64_t seed)>;

void expectDeterministic(const Factory& make, const CostFunction& f, const char* name) {
  std::unique_ptr<Optimizer> a = make(11), b = make(11), other = make(12);
  EXPECT_NE(a->ask(), other->ask()) << name << ": another seed, another sample";
  for (int g = 0; g < 25; ++g) EXPECT_EQ(step(*a, f), step(*b, f)) << name << " generation " << g;
  EXPECT_EQ(a->best(), b->best()) << name;
  EXPECT_EQ(a->bestCost(), b->bestCost()) << name;
  EXPECT_EQ(a->ask(), b->ask()) << name;
}

void expectCheckpointIsSeamless(const Factory& make, const CostFunction& f, const char* name) {
  std::unique_ptr<Optimizer> straight = make(5);
  for (int g = 0; g < 30; ++g) step(*straight, f);

  std::unique_ptr<Optimizer> first = make(5);
  for (int g = 0; g < 12; ++g) step(*first, f);
  const std::string text = first->saveState().dump();
  first.reset();
  Result<std::unique_ptr<Optimizer>> loaded = Optimizer::load(json::parse(text));
  ASSERT_TRUE(loaded.ok()) << name << ": " << loaded.message();
  std::unique_ptr<Optimizer> resumed = std::move(loaded).value();
  EXPECT_STREQ(resumed->kind(), straight->kind());
  EXPECT_EQ(resumed->generation(), 12);
  for (int g = 0; g < 18; ++g) step(*resumed, f);

  EXPECT_EQ(resumed->generation(), straight->generation()) << name;
  EXPECT_EQ(resumed->evaluations(), straight->evaluations()) << name;
  EXPECT_EQ(resumed->best(), straight->best()) << name;
  EXPECT_EQ(resumed->bestCost(), straight->bestCost()) << name;
  EXPECT_EQ(resumed->ask(), straight->ask()) << name;
  // Everything else too: the whole states are the same text.
  EXPECT_EQ(resumed->saveState().dump(), straight->saveState().dump()) << name;
}

Factory cmaesFactory(int n, CmaesSettings settings) {
  return [n, settings](std::uint64_t seed) -> std::unique_ptr<Optimizer> {
    CmaesSettings s = settings;
    s.seed = seed;
    return cmaes(n, s);
  };
}

Factory geneticFactory(int n, GeneticSettings settings) {
  return [n, settings](std::uint64_t seed) -> std::unique_ptr<Optimizer> {
    GeneticSettings s = settings;
    s.seed = seed;
    return genetic(n, s);
  };
}

TEST(SearchCheckpoint, SameSeedSameRunDifferentSeedDifferentSample) {
  const int n = 8;
  const CostFunction f = rastrigin(shiftedOptimum(n));
  expectDeterministic(cmaesFactory(n, {}), f, "cmaes");
  CmaesSettings diagonal;
  diagonal.diagonal = true;
  expectDeterministic(cmaesFactory(n, diagonal), f, "sep-cmaes");
  expectDeterministic(geneticFactory(n, {}), f, "genetic");
}

TEST(SearchCheckpoint, LoadAndContinueEqualsTheUninterruptedRun) {
  const int n = 8;
  const CostFunction f = rastrigin(shiftedOptimum(n));
  expectCheckpointIsSeamless(cmaesFactory(n, {}), f, "cmaes");
  CmaesSettings diagonal;
  diagonal.diagonal = true;
  expectCheckpointIsSeamless(cmaesFactory(n, diagonal), f, "sep-cmaes");
  GeneticSettings blend;
  blend.crossover = Crossover::kBlend;
  expectCheckpointIsSeamless(geneticFactory(n, {}), f, "genetic");
  expectCheckpointIsSeamless(geneticFactory(n, blend), f, "genetic blend");
}

TEST(SearchCheckpoint, RestartsDoubleThePopulationAndSurviveACheckpoint) {
  const int n = 6;
  CmaesSettings ipop;
  ipop.max_restarts = 4;
  ipop.tol_x = 0.2;  // coarse, so that restarts happen within a few generations
  const CostFunction f = sphere(shiftedOptimum(n));
  std::unique_ptr<Cmaes> c = cmaes(n, ipop);
  const int lambda = c->population();
  std::vector<int> populations;
  for (int g = 0; g < 30; ++g) {
    step(*c, f);
    if (c->population() != (populations.empty() ? lambda : populations.back()))
      std::printf("  IPOP: restart after generation %d\n", g + 1);
    populations.push_back(c->population());
  }
  std::printf("  IPOP: %d restarts in 30 generations, population %d -> %d\n", c->restarts(), lambda,
              c->population());
  ASSERT_GE(c->restarts(), 2);
  EXPECT_EQ(c->population(), lambda << c->restarts());
  EXPECT_TRUE(std::is_sorted(populations.begin(), populations.end()));
  expectCheckpointIsSeamless(cmaesFactory(n, ipop), f, "ipop");
}

// Local restarts: after stall_generations without a better best the run starts again at the
// initial mean with the initial step size and the same population (not IPOP's random mean and
// doubled population), the best kept; the stream of samples goes on, so the new run differs.
TEST(SearchCheckpoint, LocalRestartsStartAgainAtTheInitialMeanAfterAStall) {
  const int n = 6;
  CmaesSettings local;
  local.max_restarts = 3;
  local.stall_generations = 3;
  local.initial_mean.assign(n, 0.3);
  const CostFunction flat = [](const std::vector<double>&) { return 1.0; };
  std::unique_ptr<Cmaes> c = cmaes(n, local);
  const int lambda = c->population();
  const std::vector<std::vector<double>> first = c->ask();
  std::vector<int> restarted_after;
  for (int g = 1; g <= 16; ++g) {
    const int before = c->restarts();
    step(*c, flat);
    if (c->restarts() != before) {
      restarted_after.push_back(g);
      for (double m : c->mean()) EXPECT_NEAR(m, 0.3, 1e-12);
      EXPECT_EQ(c->sigma(), local.initial_sigma);
      EXPECT_EQ(c->population(), lambda);
      EXPECT_NE(c->ask(), first);  // a new sample, not the first run again
    }
  }
  // The first generation finds the best (1.0); nothing beats it, so each run stops after it
  // has gone 3 generations without a better one: generations 4, 8 and 12; at 16 the last run
  // stalls with no restart left.
  EXPECT_EQ(restarted_after, (std::vector<int>{4, 8, 12}));
  EXPECT_EQ(c->bestCost(), 1.0);
  EXPECT_EQ(c->stopReason(), "stall");
  EXPECT_TRUE(c->converged());
  // A run that keeps improving does not restart (a generation's best is noisy: 8, not 3).
  CmaesSettings patient = local;
  patient.stall_generations = 8;
  std::unique_ptr<Cmaes> improving = cmaes(n, patient);
  const CostFunction f = sphere(shiftedOptimum(n));
  for (int g = 0; g < 30; ++g) step(*improving, f);
  std::printf("  local restarts on the sphere in 30 generations: %d\n", improving->restarts());
  EXPECT_EQ(improving->restarts(), 0);
  expectCheckpointIsSeamless(cmaesFactory(n, local), rastrigin(shiftedOptimum(n)), "local");
}

// A changed fitness (Optimizer::rescore) begins the stall count again: the run's best from before
// is on another scale, and a heavier weight would otherwise read as generations without a better
// best. Flat costs 1.0 for three generations, then 2.0 for every point, the best rescored to 2.0:
// the stall counts from generation 4 (restart after 7), not from generation 1 (restart after 4).
TEST(SearchCheckpoint, ARescoredBestBeginsTheStallCountAgain) {
  const int n = 6;
  CmaesSettings local;
  local.max_restarts = 1;
  local.stall_generations = 3;
  std::unique_ptr<Cmaes> c = cmaes(n, local);
  const CostFunction before = [](const std::vector<double>&) { return 1.0; };
  const CostFunction after = [](const std::vector<double>&) { return 2.0; };
  for (int g = 1; g <= 3; ++g) step(*c, before);
  ASSERT_EQ(c->bests().size(), 1u);
  const double rescored[] = {after(c->bests()[0])};
  c->rescore(rescored);
  EXPECT_EQ(c->bestCost(), 2.0);
  std::vector<int> restarted_after;
  for (int g = 4; g <= 8; ++g) {
    const int restarts = c->restarts();
    step(*c, after);
    if (c->restarts() != restarts) restarted_after.push_back(g);
  }
  EXPECT_EQ(restarted_after, (std::vector<int>{7}));
}

// A state Optimizer::load must refuse, with a message naming `field`.
void expectRefused(const json& state, const std::string& field) {
  Result<std::unique_ptr<Optimizer>> loaded = Optimizer::load(state);
  EXPECT_FALSE(loaded.ok()) << field;
  EXPECT_NE(loaded.message().find(field), std::string::npos) << loaded.message();
}

TEST(SearchCheckpoint, CorruptedStatesAreRefusedNamingTheField) {
  const int n = 4;
  const CostFunction f = sphere(shiftedOptimum(n));
  std::unique_ptr<Cmaes> c = cmaes(n);
  std::unique_ptr<Genetic> g = genetic(n);
  for (int k = 0; k < 3; ++k) {
    step(*c, f);
    step(*g, f);
  }
  const json cmaes_state = c->saveState();
  const json genetic_state = g->saveState();
  ASSERT_TRUE(Optimizer::load(cmaes_state).ok());
  ASSERT_TRUE(Optimizer::load(genetic_state).ok());

  expectRefused(json::array(), "optimizer state");
  json s = cmaes_state;
  s["format"] = "sinew.target";
  expectRefused(s, "format");
  s = cmaes_state;
  s["kind"] = "annealing";
  expectRefused(s, "kind");
  s = cmaes_state;
  s.erase("mean");
  expectRefused(s, "mean: missing");
  s = cmaes_state;
  s["covariance"].erase(0);
  expectRefused(s, "covariance: expected 4 arrays of 4 finite numbers, found 3");
  s = cmaes_state;
  s["covariance"][1][2] = "x";
  expectRefused(s, "covariance[1]");
  s = cmaes_state;
  s["basis"][3].erase(0);
  expectRefused(s, "basis[3]");
  s = cmaes_state;
  s["samples"].erase(0);
  expectRefused(s, "samples");
  s = cmaes_state;
  s["sigma"] = -0.1;
  expectRefused(s, "sigma");
  s = cmaes_state;
  s["points"][0][1] = 1.5;
  expectRefused(s, "points");
  s = cmaes_state;
  s["points"].erase(0);
  expectRefused(s, "points");
  s = cmaes_state;
  s["rng"]["engine"] = "not a generator";
  expectRefused(s, "rng: engine");
  s = cmaes_state;
  s["settings"]["population"] = 1;
  expectRefused(s, "settings: population");
  s = cmaes_state;
  s["settings"].erase("seed");
  expectRefused(s, "settings: seed");
  s = cmaes_state;
  s["best_cost"] = "nan";
  expectRefused(s, "best_cost");
  s = cmaes_state;
  s["best"].erase(0);
  expectRefused(s, "best");
  s = cmaes_state;
  s["history"][0] = "a lot";
  expectRefused(s, "history[0]");

  s = genetic_state;
  s["points"].erase(0);
  expectRefused(s, "points");
  s = genetic_state;
  s["settings"]["crossover"] = "one-point";
  expectRefused(s, "settings: crossover");
  s = genetic_state;
  s["settings"]["elites"] = 64;
  expectRefused(s, "settings: elites");
  s = genetic_state;
  s.erase("rng");
  expectRefused(s, "rng: missing");
  s = genetic_state;
  s["dimension"] = 5;
  expectRefused(s, "best: expected an array of 5 finite numbers, found 4");
}

// ---------------------------------------------------------------------------------------------
// Genetic algorithm

TEST(SearchGenetic, ElitismNeverLosesTheBestAndSphereImproves) {
  const int n = 10;
  const Point centre = shiftedOptimum(n);
  for (const auto& [name, f] : std::vector<std::pair<const char*, CostFunction>>{
           {"Rastrigin", rastrigin(centre)}, {"sphere", sphere(centre)}}) {
    std::unique_ptr<Genetic> g = genetic(n);
    double previous = kInf, first = kInf;
    for (int generation = 0; generation < 100; ++generation) {
      ASSERT_TRUE(insideUnitCube(g->ask()));
      const std::vector<double> costs = step(*g, f);
      const double best = *std::min_element(costs.begin(), costs.end());
      if (generation == 0) first = best;
      ASSERT_LE(best, previous) << name << " generation " << generation;
      EXPECT_EQ(best, g->bestCost()) << name;  // the elite is re-evaluated, never lost
      previous = best;
    }
    std::printf("  GA on %s 10-D: best %.3g -> %.3g in 100 generations (%.0fx)\n", name, first,
                g->bestCost(), first / g->bestCost());
    EXPECT_GT(first / g->bestCost(), name == std::string("sphere") ? 1000.0 : 20.0) << name;
  }
}

// ---------------------------------------------------------------------------------------------
// Failed evaluations

TEST(SearchFailures, NanAndInfiniteCostsRankLastAndBreakNothing) {
  const int n = 6;
  const CostFunction f = sphere(shiftedOptimum(n));
  // Every 5th evaluation fails (NaN, +inf, -inf in turn); whole generations fail at first.
  auto flaky = [&f](const Point& x, long long index, int generation) {
    if (generation < 5) return kNan;
    if (index % 5 == 0) return std::array<double, 3>{kNan, kInf, -kInf}[(index / 5) % 3];
    return f(x);
  };
  CmaesSettings diagonal;
  diagonal.diagonal = true;
  std::vector<std::pair<const char*, std::unique_ptr<Optimizer>>> optimizers;
  optimizers.emplace_back("cmaes", cmaes(n));
  optimizers.emplace_back("sep-cmaes", cmaes(n, diagonal));
  optimizers.emplace_back("genetic", genetic(n));
  for (auto& [name, o] : optimizers) {
    long long index = 0;
    for (int generation = 0; generation < 400 && o->bestCost() > 1e-8; ++generation) {
      ASSERT_TRUE(insideUnitCube(o->ask())) << name << " generation " << generation;
      std::vector<double> costs;
      for (const Point& p : o->ask()) costs.push_back(flaky(p, index++, generation));
      ASSERT_TRUE(o->tell(costs).ok());
      if (generation < 5) {
        EXPECT_TRUE(o->best().empty()) << name;
        EXPECT_EQ(o->bestCost(), kInf) << name;
      }
    }
    std::printf("  %s with failed evaluations: best %.2e after %lld evaluations\n", name,
                o->bestCost(), o->evaluations());
    ASSERT_EQ(o->best().size(), static_cast<size_t>(n)) << name;
    EXPECT_EQ(o->bestCost(), f(o->best())) << name;  // the best is a real, finite evaluation
    const double target = std::string(name) == "genetic" ? 1e-2 : 1e-8;  // GA: no convergence
    EXPECT_LE(o->bestCost(), target) << name;
    // A state with failed costs in it saves and loads.
    EXPECT_TRUE(Optimizer::load(json::parse(o->saveState().dump())).ok()) << name;
  }
}

// ---------------------------------------------------------------------------------------------
// Portfolio: several starts tried in turn, the best going on

// Two CMA-ES runs (one seed) from the given starts, tried `trial` generations each.
std::unique_ptr<Portfolio> portfolio(const std::vector<Point>& starts, int trial,
                                     std::uint64_t seed = 1) {
  std::vector<std::unique_ptr<Optimizer>> members;
  for (const Point& start : starts) {
    CmaesSettings s;
    s.initial_mean = start;
    s.initial_sigma = 0.05;
    s.seed = seed;
    members.push_back(cmaes(static_cast<int>(start.size()), s));
  }
  Result<std::unique_ptr<Portfolio>> p = Portfolio::create(std::move(members), trial);
  EXPECT_TRUE(p.ok()) << p.message();
  return std::move(p).value();
}

// The start near the optimum wins whichever place it has, each member's trial is the run a
// search from its start alone would make (bit for bit), and the winner goes on as it would alone.
TEST(SearchPortfolio, TriesEachStartInTurnThenKeepsTheBest) {
  const int n = 6;
  const Point optimum(n, 0.8);
  const CostFunction f = sphere(optimum);
  const Point far(n, 0.1), near(n, 0.7);
  for (const bool near_first : {false, true}) {
    const std::vector<Point> starts = near_first ? std::vector<Point>{near, far}
                                                 : std::vector<Point>{far, near};
    std::unique_ptr<Portfolio> p = portfolio(starts, 10);
    std::unique_ptr<Cmaes> alone[2];
    for (int m = 0; m < 2; ++m) {
      CmaesSettings s;
      s.initial_mean = starts[static_cast<size_t>(m)];
      s.initial_sigma = 0.05;
      s.seed = 1;
      alone[m] = cmaes(n, s);
    }
    for (int g = 0; g < 20; ++g) {
      const int m = g < 10 ? 0 : 1;
      EXPECT_EQ(p->current(), m) << "generation " << g;
      EXPECT_EQ(p->chosen(), -1) << "generation " << g;
      EXPECT_EQ(p->ask(), alone[m]->ask()) << "generation " << g;
      step(*p, f);
      step(*alone[m], f);
    }
    const int winner = near_first ? 0 : 1;
    EXPECT_EQ(p->chosen(), winner) << near_first;
    EXPECT_EQ(p->current(), winner);
    EXPECT_LT(p->member(winner).bestCost(), p->member(1 - winner).bestCost());
    EXPECT_EQ(p->bestCost(), p->member(winner).bestCost());
    for (int g = 0; g < 15; ++g) {
      EXPECT_EQ(p->ask(), alone[winner]->ask()) << "after the choice, generation " << g;
      step(*p, f);
      step(*alone[winner], f);
    }
    EXPECT_EQ(p->generation(), 35);
    EXPECT_EQ(p->evaluations(), 35LL * p->population());
    EXPECT_EQ(p->bestCost(), alone[winner]->bestCost());
  }
}

// keep() ends the trials at once: the member goes on alone, the others are never asked.
TEST(SearchPortfolio, KeepEndsTheTrialsWithTheMemberItNames) {
  const int n = 4;
  const CostFunction f = sphere(Point(n, 0.6));
  std::unique_ptr<Portfolio> p = portfolio({Point(n, 0.5), Point(n, 0.2)}, 10);
  CmaesSettings s;
  s.initial_mean = Point(n, 0.5);
  s.initial_sigma = 0.05;
  std::unique_ptr<Cmaes> alone = cmaes(n, s);
  for (int g = 0; g < 3; ++g) {
    step(*p, f);
    step(*alone, f);
  }
  p->keep(0);
  EXPECT_EQ(p->chosen(), 0);
  for (int g = 0; g < 20; ++g) {
    EXPECT_EQ(p->current(), 0);
    EXPECT_EQ(p->ask(), alone->ask()) << g;
    step(*p, f);
    step(*alone, f);
  }
  EXPECT_EQ(p->member(1).generation(), 0);
  EXPECT_EQ(p->bestCost(), alone->bestCost());
}

// Deterministic, and a checkpoint taken within a trial resumes through the choice to the same
// state as the uninterrupted run (the generic checks of every optimiser, with trials of 8: the
// checkpoint at generation 12 is within the second member's trial, the choice comes at 16).
TEST(SearchPortfolio, DeterministicAndCheckpointsAreSeamless) {
  constexpr int kN = 5;
  const CostFunction f = rastrigin(shiftedOptimum(kN));
  const Factory make = [](std::uint64_t seed) -> std::unique_ptr<Optimizer> {
    return portfolio({Point(kN, 0.5), Point(kN, 0.3)}, 8, seed);
  };
  expectDeterministic(make, f, "portfolio");
  expectCheckpointIsSeamless(make, f, "portfolio");
}

TEST(SearchPortfolio, BadMembersAndCorruptedStatesAreRefused) {
  const int n = 3;
  auto members = [](std::vector<int> dimensions) {
    std::vector<std::unique_ptr<Optimizer>> m;
    for (int d : dimensions) m.push_back(cmaes(d));
    return m;
  };
  auto refusedCreate = [](std::vector<std::unique_ptr<Optimizer>> m, int trial,
                          const std::string& why) {
    Result<std::unique_ptr<Portfolio>> p = Portfolio::create(std::move(m), trial);
    EXPECT_FALSE(p.ok()) << why;
    EXPECT_NE(p.message().find(why), std::string::npos) << p.message();
  };
  refusedCreate(members({n}), 5, "expected 2 to 8 members, got 1");
  refusedCreate(members({n, n + 1}), 5, "member 1 has 4 coordinates");
  refusedCreate(members({n, n}), 0, "trial_generations");
  std::vector<std::unique_ptr<Optimizer>> told = members({n, n});
  step(*told[1], sphere(Point(n, 0.5)));
  refusedCreate(std::move(told), 5, "member 1 has been told generations already");

  std::unique_ptr<Portfolio> p = portfolio({Point(n, 0.5), Point(n, 0.4)}, 2);
  for (int g = 0; g < 3; ++g) step(*p, sphere(Point(n, 0.6)));
  const json state = p->saveState();
  EXPECT_EQ(state["kind"], "portfolio");
  ASSERT_TRUE(Optimizer::load(state).ok());
  json s = state;
  s.erase("members");
  expectRefused(s, "members: missing");
  s = state;
  s["members"].erase(0);
  expectRefused(s, "expected 2 to 8 members, got 1");
  s = state;
  s["members"][1]["sigma"] = -1.0;
  expectRefused(s, "members[1]: optimizer state: sigma");
  s = state;
  s["members"][0] = state;
  expectRefused(s, "members[0]: a portfolio cannot hold a portfolio");
  s = state;
  s["current"] = 2;
  expectRefused(s, "current");
  s = state;
  s["chosen"] = 0;
  expectRefused(s, "chosen: the chosen member is the one asking");
  s = state;
  s["points"] = s["members"][0]["points"];
  expectRefused(s, "points: not the current member's");
  s = state;
  s["dimension"] = 4;
  expectRefused(s, "dimension");
}

}  // namespace
}  // namespace sinew::search
