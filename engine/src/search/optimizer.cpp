#include "sinew/search/optimizer.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <nlohmann/json.hpp>

#include "sinew/core/assert.h"
#include "sinew/search/cmaes.h"
#include "sinew/search/genetic.h"
#include "sinew/search/portfolio.h"
#include "state_json.h"

namespace sinew::search {

using nlohmann::json;

std::vector<int> rankOrder(std::span<const double> costs) {
  std::vector<int> order(costs.size());
  std::iota(order.begin(), order.end(), 0);
  // Failed costs compare as one value above every finite cost: a strict weak order even with NaN.
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const double ca = costs[static_cast<size_t>(a)];
    const double cb = costs[static_cast<size_t>(b)];
    const bool fa = std::isfinite(ca), fb = std::isfinite(cb);
    if (fa != fb) return fa;
    return fa && ca < cb;
  });
  return order;
}

Status Optimizer::tell(std::span<const double> costs) {
  if (costs.size() != points_.size())
    return Status::error("costs: expected " + std::to_string(points_.size()) +
                         " values (one per point of ask()), got " + std::to_string(costs.size()));
  const std::vector<int> order = rankOrder(costs);
  const size_t first = static_cast<size_t>(order.front());
  if (std::isfinite(costs[first]) && costs[first] < best_cost_) {
    best_cost_ = costs[first];
    best_ = points_[first];
  }
  evaluations_ += static_cast<long long>(costs.size());
  ++generation_;
  advance(costs, order);
  return {};
}

std::vector<std::vector<double>> Optimizer::bests() const {
  if (best_.empty()) return {};
  return {best_};
}

void Optimizer::rescore(std::span<const double> costs) {
  SINEW_ASSERT(costs.size() == (best_.empty() ? 0u : 1u), "Optimizer::rescore: one cost a best");
  if (!best_.empty()) best_cost_ = costs[0];
}

json Optimizer::saveState() const {
  json state = {{"format", kStateFormat},
                {"version", kStateVersion},
                {"kind", kind()},
                {"dimension", dimension_},
                {"generation", generation_},
                {"evaluations", evaluations_},
                {"best", best_},
                {"best_cost", state_json::cost(best_cost_)}};
  std::vector<double> flat;
  flat.reserve(points_.size() * static_cast<size_t>(dimension_));
  for (const std::vector<double>& p : points_) flat.insert(flat.end(), p.begin(), p.end());
  state["points"] = state_json::rows(flat, static_cast<size_t>(dimension_));
  saveDetails(state);
  return state;
}

Status Optimizer::loadCommon(const json& state) {
  const std::string where = "optimizer state";
  const size_t n = static_cast<size_t>(dimension_);
  if (Status s = state_json::readInt(state, "generation", where, 0, std::numeric_limits<int>::max(),
                                     generation_);
      !s.ok())
    return s;
  if (Status s = state_json::readInt(state, "evaluations", where, 0LL,
                                     std::numeric_limits<long long>::max(), evaluations_);
      !s.ok())
    return s;
  if (Status s = state_json::readCost(state, "best_cost", where, best_cost_); !s.ok()) return s;
  if (std::isnan(best_cost_) || best_cost_ == -std::numeric_limits<double>::infinity())
    return Status::error(where + ": best_cost: expected a finite number or \"inf\"");
  const bool have_best = std::isfinite(best_cost_);
  if (Status s = state_json::readVector(state, "best", where, have_best ? n : 0, best_); !s.ok())
    return s;
  Result<const json*> points = state_json::field(state, "points", where);
  if (!points.ok()) return points.status();
  const size_t count = points.value()->is_array() ? points.value()->size() : 0;
  if (count < 2) return Status::error(where + ": points: expected at least 2 arrays");
  std::vector<double> flat;
  if (Status s = state_json::readRows(state, "points", where, count, n, flat); !s.ok()) return s;
  auto inside = [](double x) { return x >= 0.0 && x <= 1.0; };
  if (!std::all_of(flat.begin(), flat.end(), inside) ||
      !std::all_of(best_.begin(), best_.end(), inside))
    return Status::error(where + ": points and best: every coordinate must lie in [0, 1]");
  points_.assign(count, std::vector<double>(n));
  for (size_t p = 0; p < count; ++p)
    std::copy_n(flat.begin() + static_cast<std::ptrdiff_t>(p * n), n, points_[p].begin());
  return {};
}

Result<std::unique_ptr<Optimizer>> Optimizer::load(const json& state) {
  const std::string where = "optimizer state";
  std::string format, kind;
  if (Status s = state_json::readString(state, "format", where, format); !s.ok()) return s;
  if (format != kStateFormat)
    return Status::error(where + ": format: expected \"" + kStateFormat + "\", found \"" + format +
                         "\"");
  int version = 0;
  if (Status s =
          state_json::readInt(state, "version", where, kStateVersion, kStateVersion, version);
      !s.ok())
    return s;
  if (Status s = state_json::readString(state, "kind", where, kind); !s.ok()) return s;
  if (kind == "cmaes") {
    Result<std::unique_ptr<Cmaes>> cmaes = Cmaes::load(state);
    if (!cmaes.ok()) return cmaes.status();
    return std::unique_ptr<Optimizer>(std::move(cmaes).value());
  }
  if (kind == "genetic") {
    Result<std::unique_ptr<Genetic>> genetic = Genetic::load(state);
    if (!genetic.ok()) return genetic.status();
    return std::unique_ptr<Optimizer>(std::move(genetic).value());
  }
  if (kind == "portfolio") {
    Result<std::unique_ptr<Portfolio>> portfolio = Portfolio::load(state);
    if (!portfolio.ok()) return portfolio.status();
    return std::unique_ptr<Optimizer>(std::move(portfolio).value());
  }
  return Status::error(where + ": kind: expected \"cmaes\", \"genetic\" or \"portfolio\", found \"" +
                       kind + "\"");
}

}  // namespace sinew::search
