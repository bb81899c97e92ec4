#include "sinew/search/genetic.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "state_json.h"

namespace sinew::search {
namespace {

using nlohmann::json;

constexpr int kMaxDimension = 1 << 20;
constexpr int kMaxPopulation = 1 << 24;

bool inUnit(double x) {
  return x >= 0.0 && x <= 1.0;
}

const char* crossoverName(Crossover c) {
  return c == Crossover::kBlend ? "blend" : "uniform";
}

}  // namespace

Status GeneticSettings::validate(int dimension) const {
  if (dimension < 1 || dimension > kMaxDimension)
    return Status::error("dimension must be in [1, " + std::to_string(kMaxDimension) + "], got " +
                         std::to_string(dimension));
  if (population < 2 || population > kMaxPopulation)
    return Status::error("population must be in [2, " + std::to_string(kMaxPopulation) + "], got " +
                         std::to_string(population));
  if (elites < 0 || elites >= population)
    return Status::error("elites must be in [0, population), got " + std::to_string(elites));
  if (tournament_size < 1 || tournament_size > population)
    return Status::error("tournament_size must be in [1, population], got " +
                         std::to_string(tournament_size));
  if (crossover != Crossover::kUniform && crossover != Crossover::kBlend)
    return Status::error("crossover must be kUniform or kBlend");
  if (!inUnit(crossover_rate)) return Status::error("crossover_rate must be in [0, 1]");
  if (!(std::isfinite(blend_alpha) && blend_alpha >= 0.0))
    return Status::error("blend_alpha must be >= 0");
  if (!inUnit(mutation_rate))
    return Status::error("mutation_rate must be in [0, 1] (0: 1 / dimension)");
  if (!(std::isfinite(mutation_scale) && mutation_scale > 0.0))
    return Status::error("mutation_scale must be > 0 (normalised units)");
  if (!initial_point.empty()) {
    if (initial_point.size() != static_cast<size_t>(dimension))
      return Status::error("initial_point must have " + std::to_string(dimension) +
                           " values (or none), got " + std::to_string(initial_point.size()));
    for (size_t i = 0; i < initial_point.size(); ++i)
      if (!inUnit(initial_point[i]))
        return Status::error("initial_point[" + std::to_string(i) + "] must be in [0, 1]");
  }
  if (!(std::isfinite(initial_spread) && initial_spread > 0.0))
    return Status::error("initial_spread must be > 0 (normalised units)");
  return {};
}

Genetic::Genetic(int dimension, const GeneticSettings& settings)
    : Optimizer(dimension), settings_(settings), random_(settings.seed) {}

Result<std::unique_ptr<Genetic>> Genetic::create(int dimension, const GeneticSettings& settings) {
  if (Status s = settings.validate(dimension); !s.ok())
    return Status::error("genetic settings: " + s.message());
  std::unique_ptr<Genetic> g(new Genetic(dimension, settings));
  const size_t n = static_cast<size_t>(dimension);
  g->points_.assign(static_cast<size_t>(settings.population), std::vector<double>(n));
  for (size_t p = 0; p < g->points_.size(); ++p) {
    std::vector<double>& point = g->points_[p];
    for (size_t i = 0; i < n; ++i) {
      if (settings.initial_point.empty()) {
        point[i] = g->random_.uniform();
      } else {
        const double noise = p == 0 ? 0.0 : settings.initial_spread * g->random_.normal();
        point[i] = std::clamp(settings.initial_point[i] + noise, 0.0, 1.0);
      }
    }
  }
  return g;
}

// The best of tournament_size points drawn with replacement; `rank` is each point's place.
int Genetic::tournament(const std::vector<int>& rank) {
  int winner = random_.below(population());
  for (int t = 1; t < settings_.tournament_size; ++t) {
    const int rival = random_.below(population());
    if (rank[static_cast<size_t>(rival)] < rank[static_cast<size_t>(winner)]) winner = rival;
  }
  return winner;
}

void Genetic::advance(std::span<const double> /*costs*/, const std::vector<int>& order) {
  const size_t n = static_cast<size_t>(dimension());
  std::vector<int> rank(order.size());
  for (size_t r = 0; r < order.size(); ++r)
    rank[static_cast<size_t>(order[r])] = static_cast<int>(r);
  const double rate =
      settings_.mutation_rate > 0.0 ? settings_.mutation_rate : 1.0 / static_cast<double>(n);

  std::vector<std::vector<double>> next;
  next.reserve(points_.size());
  for (int e = 0; e < settings_.elites; ++e)
    next.push_back(points_[static_cast<size_t>(order[static_cast<size_t>(e)])]);
  while (next.size() < points_.size()) {
    std::vector<double> child = points_[static_cast<size_t>(tournament(rank))];
    if (random_.uniform() < settings_.crossover_rate) {
      const std::vector<double>& other = points_[static_cast<size_t>(tournament(rank))];
      for (size_t i = 0; i < n; ++i) {
        if (settings_.crossover == Crossover::kUniform) {
          if (random_.uniform() < 0.5) child[i] = other[i];
        } else {
          const double lo = std::min(child[i], other[i]);
          const double width = std::max(child[i], other[i]) - lo;
          child[i] = lo - settings_.blend_alpha * width +
                     random_.uniform() * width * (1.0 + 2.0 * settings_.blend_alpha);
        }
      }
    }
    for (size_t i = 0; i < n; ++i) {
      if (random_.uniform() < rate) child[i] += settings_.mutation_scale * random_.normal();
      child[i] = std::clamp(child[i], 0.0, 1.0);
    }
    next.push_back(std::move(child));
  }
  points_ = std::move(next);
}

void Genetic::saveDetails(json& state) const {
  state["settings"] = {{"population", settings_.population},
                       {"elites", settings_.elites},
                       {"tournament_size", settings_.tournament_size},
                       {"crossover", crossoverName(settings_.crossover)},
                       {"crossover_rate", settings_.crossover_rate},
                       {"blend_alpha", settings_.blend_alpha},
                       {"mutation_rate", settings_.mutation_rate},
                       {"mutation_scale", settings_.mutation_scale},
                       {"initial_point", settings_.initial_point},
                       {"initial_spread", settings_.initial_spread},
                       {"seed", settings_.seed}};
  state["rng"] = random_.saveState();
}

Result<std::unique_ptr<Genetic>> Genetic::load(const json& state) {
  namespace sj = state_json;
  const std::string where = "optimizer state";
  int n = 0;
  if (Status s = sj::readInt(state, "dimension", where, 1, kMaxDimension, n); !s.ok()) return s;

  Result<const json*> settings_json = sj::field(state, "settings", where);
  if (!settings_json.ok()) return settings_json.status();
  const json& js = *settings_json.value();
  const std::string in_settings = where + ": settings";
  GeneticSettings settings;
  std::string crossover;
  Status s = sj::readInt(js, "population", in_settings, 2, kMaxPopulation, settings.population);
  if (s.ok()) s = sj::readInt(js, "elites", in_settings, 0, kMaxPopulation, settings.elites);
  if (s.ok())
    s = sj::readInt(js, "tournament_size", in_settings, 1, kMaxPopulation,
                    settings.tournament_size);
  if (s.ok()) s = sj::readString(js, "crossover", in_settings, crossover);
  if (s.ok() && crossover != "uniform" && crossover != "blend")
    s = Status::error(in_settings + ": crossover: expected \"uniform\" or \"blend\"");
  settings.crossover = crossover == "blend" ? Crossover::kBlend : Crossover::kUniform;
  if (s.ok()) s = sj::readNumber(js, "crossover_rate", in_settings, settings.crossover_rate);
  if (s.ok()) s = sj::readNumber(js, "blend_alpha", in_settings, settings.blend_alpha);
  if (s.ok()) s = sj::readNumber(js, "mutation_rate", in_settings, settings.mutation_rate);
  if (s.ok()) s = sj::readNumber(js, "mutation_scale", in_settings, settings.mutation_scale);
  if (s.ok())
    s = sj::readVector(js, "initial_point", in_settings, sj::kAnySize, settings.initial_point);
  if (s.ok()) s = sj::readNumber(js, "initial_spread", in_settings, settings.initial_spread);
  if (s.ok()) s = sj::readUint64(js, "seed", in_settings, settings.seed);
  if (!s.ok()) return s;
  if (Status v = settings.validate(n); !v.ok())
    return Status::error(in_settings + ": " + v.message());

  std::unique_ptr<Genetic> g(new Genetic(n, settings));
  s = g->loadCommon(state);
  if (s.ok() && g->population() != settings.population)
    s = Status::error(
        where + ": points: expected settings.population = " + std::to_string(settings.population) +
        " arrays, found " + std::to_string(g->population()));
  Result<const json*> rng = sj::field(state, "rng", where);
  if (s.ok() && !rng.ok()) s = rng.status();
  if (!s.ok()) return s;
  Result<Random> random = Random::load(*rng.value(), where + ": rng");
  if (!random.ok()) return random.status();
  g->random_ = random.value();
  return g;
}

}  // namespace sinew::search
