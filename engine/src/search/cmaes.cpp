#include "sinew/search/cmaes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "state_json.h"

namespace sinew::search {
namespace {

using Eigen::Map;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using nlohmann::json;

constexpr double kMaxCondition = 1e14;  // of the covariance: beyond it, numerics are lost
constexpr int kMaxRestarts = kMaxCmaesRestarts;
constexpr long long kMaxPopulation = 1 << 24;  // after every restart
constexpr int kMaxDimension = 1 << 20;

Map<const VectorXd> constVec(const std::vector<double>& v) {
  return Map<const VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
Map<VectorXd> vec(std::vector<double>& v) {
  return Map<VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
Map<const MatrixXd> constMat(const std::vector<double>& v, int rows) {
  return Map<const MatrixXd>(v.data(), rows, static_cast<Eigen::Index>(v.size()) / rows);
}
Map<MatrixXd> mat(std::vector<double>& v, int rows) {
  return Map<MatrixXd>(v.data(), rows, static_cast<Eigen::Index>(v.size()) / rows);
}

int defaultPopulation(int n) {
  return 4 + static_cast<int>(std::floor(3.0 * std::log(static_cast<double>(n))));
}

}  // namespace

double boundaryTransform(double y) {
  constexpr double a = kBoundaryZone;
  constexpr double period = 2.0 * (1.0 + 2.0 * a);
  constexpr double start = -2.0 * a - 0.5;  // one period: [start, start + period)
  if (!std::isfinite(y)) return 0.5;        // unreachable from a finite distribution
  double x = y - period * std::floor((y - start) / period);
  if (x > 1.0 + a) x = 2.0 * (1.0 + a) - x;  // mirror at 1 + a
  if (x < -a) x = -2.0 * a - x;              // mirror at -a
  double out = x;
  if (x < a) {
    out = (x + a) * (x + a) / (4.0 * a);
  } else if (x > 1.0 - a) {
    out = 1.0 - (x - 1.0 - a) * (x - 1.0 - a) / (4.0 * a);
  }
  return std::clamp(out, 0.0, 1.0);
}

double inverseBoundaryTransform(double x) {
  constexpr double a = kBoundaryZone;
  x = std::clamp(x, 0.0, 1.0);
  if (x < a) return -a + 2.0 * std::sqrt(a * x);
  if (x > 1.0 - a) return 1.0 + a - 2.0 * std::sqrt(a * (1.0 - x));
  return x;
}

Status CmaesSettings::validate(int dimension) const {
  if (dimension < 1 || dimension > kMaxDimension)
    return Status::error("dimension must be in [1, " + std::to_string(kMaxDimension) + "], got " +
                         std::to_string(dimension));
  if (population != 0 && population < 2)
    return Status::error("population must be >= 2 (or 0 for 4 + floor(3 ln n)), got " +
                         std::to_string(population));
  if (!(std::isfinite(initial_sigma) && initial_sigma > 0.0 && initial_sigma <= 1.0))
    return Status::error("initial_sigma must be in (0, 1] (normalised units)");
  if (!initial_mean.empty()) {
    if (initial_mean.size() != static_cast<size_t>(dimension))
      return Status::error("initial_mean must have " + std::to_string(dimension) +
                           " values (or none), got " + std::to_string(initial_mean.size()));
    for (size_t i = 0; i < initial_mean.size(); ++i)
      if (!(initial_mean[i] >= 0.0 && initial_mean[i] <= 1.0))
        return Status::error("initial_mean[" + std::to_string(i) + "] must be in [0, 1]");
  }
  if (max_restarts < 0 || max_restarts > kMaxRestarts)
    return Status::error("max_restarts must be in [0, " + std::to_string(kMaxRestarts) + "]");
  if (stall_generations < 0 || stall_generations > 1000000)
    return Status::error("stall_generations must be in [0, 1000000]");
  const long long lambda = population > 0 ? population : defaultPopulation(dimension);
  if (stall_generations == 0 && (lambda << max_restarts) > kMaxPopulation)
    return Status::error("population x 2^max_restarts must stay <= " +
                         std::to_string(kMaxPopulation));
  if (!(std::isfinite(tol_x) && tol_x >= 0.0)) return Status::error("tol_x must be >= 0");
  if (!(std::isfinite(tol_fun) && tol_fun >= 0.0)) return Status::error("tol_fun must be >= 0");
  return {};
}

Cmaes::Cmaes(int dimension, const CmaesSettings& settings)
    : Optimizer(dimension), settings_(settings), random_(settings.seed) {}

Result<std::unique_ptr<Cmaes>> Cmaes::create(int dimension, const CmaesSettings& settings) {
  if (Status s = settings.validate(dimension); !s.ok())
    return Status::error("cmaes settings: " + s.message());
  std::unique_ptr<Cmaes> c(new Cmaes(dimension, settings));
  c->configure(settings.population > 0 ? settings.population : defaultPopulation(dimension));
  c->restart(c->initialInternalMean());
  c->sample();
  return c;
}

// Hansen (2016), table 1, with positive weights only (no active update).
void Cmaes::configure(int lambda) {
  const double n = static_cast<double>(dimension());
  lambda_ = lambda;
  mu_ = lambda / 2;
  weights_.resize(static_cast<size_t>(mu_));
  double sum = 0.0;
  for (int i = 0; i < mu_; ++i) {
    weights_[static_cast<size_t>(i)] =
        std::log((lambda + 1) / 2.0) - std::log(static_cast<double>(i + 1));
    sum += weights_[static_cast<size_t>(i)];
  }
  double sum_sq = 0.0;
  for (double& w : weights_) {
    w /= sum;
    sum_sq += w * w;
  }
  mueff_ = 1.0 / sum_sq;
  cc_ = (4.0 + mueff_ / n) / (n + 4.0 + 2.0 * mueff_ / n);
  cs_ = (mueff_ + 2.0) / (n + mueff_ + 5.0);
  c1_ = 2.0 / ((n + 1.3) * (n + 1.3) + mueff_);
  cmu_ =
      std::min(1.0 - c1_, 2.0 * (mueff_ - 2.0 + 1.0 / mueff_) / ((n + 2.0) * (n + 2.0) + mueff_));
  if (settings_.diagonal) {
    // Ros & Hansen (2008): a diagonal covariance has n, not n^2 / 2, free parameters.
    const double faster = (n + 2.0) / 3.0;
    c1_ = std::min(1.0, c1_ * faster);
    cmu_ = std::min(1.0 - c1_, cmu_ * faster);
  }
  damps_ = 1.0 + 2.0 * std::max(0.0, std::sqrt((mueff_ - 1.0) / (n + 1.0)) - 1.0) + cs_;
  chin_ = std::sqrt(n) * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n));
  history_length_ = 10 + static_cast<int>(std::ceil(30.0 * n / lambda));
}

// The settings' initial mean (the centre when none is given) in internal coordinates.
std::vector<double> Cmaes::initialInternalMean() const {
  std::vector<double> mean(static_cast<size_t>(dimension()), 0.5);
  if (!settings_.initial_mean.empty()) mean = settings_.initial_mean;
  for (double& m : mean) m = inverseBoundaryTransform(m);
  return mean;
}

void Cmaes::restart(const std::vector<double>& internal_mean) {
  const size_t n = static_cast<size_t>(dimension());
  mean_ = internal_mean;
  sigma_ = settings_.initial_sigma;
  pc_.assign(n, 0.0);
  ps_.assign(n, 0.0);
  scales_.assign(n, 1.0);
  if (settings_.diagonal) {
    cov_.assign(n, 1.0);
    basis_.clear();
  } else {
    cov_.assign(n * n, 0.0);
    mat(cov_, dimension()).setIdentity();
    basis_ = cov_;
  }
  decomposed_at_ = evaluations();
  run_generation_ = 0;
  history_.clear();
  run_best_ = std::numeric_limits<double>::infinity();
  run_best_at_ = 0;
  stop_.clear();
}

void Cmaes::rescore(std::span<const double> costs) {
  const bool moved = !best().empty() && costs[0] != bestCost();  // a resume of the same problem: no
  Optimizer::rescore(costs);
  if (!moved) return;
  history_.clear();
  run_best_ = std::numeric_limits<double>::infinity();
  run_best_at_ = run_generation_;
}

void Cmaes::sample() {
  const int n = dimension();
  const size_t un = static_cast<size_t>(n);
  samples_.resize(static_cast<size_t>(lambda_) * un);
  for (double& z : samples_)
    z = random_.normal();  // point after point, coordinate after coordinate
  Map<MatrixXd> y = mat(samples_, n);
  y = vec(scales_).asDiagonal() * y;
  if (!settings_.diagonal) {
    const MatrixXd scaled = y;
    y.noalias() = mat(basis_, n) * scaled;  // y = B D z
  }
  points_.assign(static_cast<size_t>(lambda_), std::vector<double>(un));
  for (size_t k = 0; k < static_cast<size_t>(lambda_); ++k)
    for (size_t i = 0; i < un; ++i)
      points_[k][i] = boundaryTransform(mean_[i] + sigma_ * samples_[k * un + i]);
}

// Keeps the previous basis (and reports "condition") when the covariance lost definiteness.
void Cmaes::decompose() {
  const int n = dimension();
  Map<MatrixXd> c = mat(cov_, n);
  // Only the lower triangle is read; copying it up keeps C exactly symmetric.
  c.triangularView<Eigen::StrictlyUpper>() = c.transpose();
  const Eigen::SelfAdjointEigenSolver<MatrixXd> solver(c);
  decomposed_at_ = evaluations();
  if (solver.info() != Eigen::Success || !solver.eigenvalues().allFinite() ||
      !(solver.eigenvalues().minCoeff() > 0.0)) {
    stop_ = "condition";
    return;
  }
  mat(basis_, n) = solver.eigenvectors();
  vec(scales_) = solver.eigenvalues().cwiseSqrt();
}

std::string Cmaes::stopTest(std::span<const double> costs, const std::vector<int>& order) const {
  const size_t n = static_cast<size_t>(dimension());
  bool small = true;
  for (size_t i = 0; i < n && small; ++i) {
    const double variance = settings_.diagonal ? cov_[i] : cov_[i * n + i];
    small = sigma_ * std::max(std::sqrt(variance), std::abs(pc_[i])) < settings_.tol_x;
  }
  if (small) return "tol_x";

  if (run_generation_ >= history_length_ &&
      std::isfinite(costs[static_cast<size_t>(order.back())])) {
    double lo = costs[static_cast<size_t>(order.front())];
    double hi = costs[static_cast<size_t>(order.back())];
    bool finite = true;
    for (double h : history_) {
      finite = finite && std::isfinite(h);
      lo = std::min(lo, h);
      hi = std::max(hi, h);
    }
    if (finite && hi - lo < settings_.tol_fun) return "tol_fun";
  }

  const auto [lo, hi] = std::minmax_element(scales_.begin(), scales_.end());
  if ((*hi / *lo) * (*hi / *lo) > kMaxCondition) return "condition";
  if (settings_.stall_generations > 0 && run_generation_ - run_best_at_ >= settings_.stall_generations)
    return "stall";
  return {};
}

void Cmaes::advance(std::span<const double> costs, const std::vector<int>& order) {
  const int n = dimension();
  const size_t un = static_cast<size_t>(n);
  const double dn = static_cast<double>(n);
  const Map<const MatrixXd> y = constMat(samples_, n);

  // Recombination: the weighted mean of the mu best steps.
  VectorXd yw = VectorXd::Zero(n);
  for (int i = 0; i < mu_; ++i)
    yw += weights_[static_cast<size_t>(i)] * y.col(order[static_cast<size_t>(i)]);
  vec(mean_) += sigma_ * yw;

  // Step-size path, in the coordinates where the distribution is isotropic: C^-1/2 yw.
  VectorXd whitened;
  if (settings_.diagonal) {
    whitened = yw.cwiseQuotient(constVec(scales_));
  } else {
    const Map<const MatrixXd> b = constMat(basis_, n);
    whitened = b * (b.transpose() * yw).cwiseQuotient(constVec(scales_));
  }
  vec(ps_) = (1.0 - cs_) * vec(ps_) + std::sqrt(cs_ * (2.0 - cs_) * mueff_) * whitened;
  ++run_generation_;
  const double ps_norm = vec(ps_).norm();
  // h_sigma stalls the rank-one path while the step size is still growing fast.
  const bool hsig = ps_norm / std::sqrt(1.0 - std::pow(1.0 - cs_, 2.0 * run_generation_)) <
                    (1.4 + 2.0 / (dn + 1.0)) * chin_;
  vec(pc_) = (1.0 - cc_) * vec(pc_) + (hsig ? std::sqrt(cc_ * (2.0 - cc_) * mueff_) : 0.0) * yw;

  // Covariance: rank-one (pc) and rank-mu (the selected steps); the weights sum to 1.
  const double lost = hsig ? 0.0 : cc_ * (2.0 - cc_);
  const double keep = 1.0 - c1_ - cmu_ + c1_ * lost;
  if (settings_.diagonal) {
    for (size_t i = 0; i < un; ++i) {
      double rank_mu = 0.0;
      for (int k = 0; k < mu_; ++k) {
        const double step = y(static_cast<Eigen::Index>(i), order[static_cast<size_t>(k)]);
        rank_mu += weights_[static_cast<size_t>(k)] * step * step;
      }
      cov_[i] = keep * cov_[i] + c1_ * pc_[i] * pc_[i] + cmu_ * rank_mu;
    }
  } else {
    MatrixXd selected(n, mu_);
    for (int k = 0; k < mu_; ++k)
      selected.col(k) =
          y.col(order[static_cast<size_t>(k)]) * std::sqrt(weights_[static_cast<size_t>(k)]);
    Map<MatrixXd> c = mat(cov_, n);
    c *= keep;
    c.noalias() += c1_ * vec(pc_) * vec(pc_).transpose();
    c.noalias() += cmu_ * selected * selected.transpose();
  }

  // Cumulative step-size adaptation: lengthen when the path is longer than a random walk's.
  sigma_ *= std::exp((cs_ / damps_) * (ps_norm / chin_ - 1.0));

  const double generation_best = costs[static_cast<size_t>(order.front())];
  history_.push_back(generation_best);
  if (history_.size() > static_cast<size_t>(history_length_)) history_.erase(history_.begin());
  if (std::isfinite(generation_best) && generation_best < run_best_) {
    run_best_ = generation_best;
    run_best_at_ = run_generation_;
  }

  stop_.clear();
  if (settings_.diagonal) {
    vec(scales_) = vec(cov_).cwiseSqrt();
  } else if (static_cast<double>(evaluations() - decomposed_at_) >
             lambda_ / (c1_ + cmu_) / dn / 10.0) {
    decompose();  // lazily: O(n^3), the covariance moves little in the meantime
  }
  if (stop_.empty()) stop_ = stopTest(costs, order);

  if (!stop_.empty() && restarts_ < settings_.max_restarts && settings_.stall_generations > 0) {
    ++restarts_;  // local: the initial mean, the same population
    restart(initialInternalMean());
  } else if (!stop_.empty() && restarts_ < settings_.max_restarts) {
    ++restarts_;
    configure(2 * lambda_);
    std::vector<double> mean(un);
    for (double& m : mean) m = inverseBoundaryTransform(random_.uniform());
    restart(mean);
  }
  sample();
}

std::vector<double> Cmaes::mean() const {
  std::vector<double> out(mean_.size());
  std::transform(mean_.begin(), mean_.end(), out.begin(), boundaryTransform);
  return out;
}

double Cmaes::axisRatio() const {
  const auto [lo, hi] = std::minmax_element(scales_.begin(), scales_.end());
  return *hi / *lo;
}

void Cmaes::saveDetails(json& state) const {
  const size_t n = static_cast<size_t>(dimension());
  state["settings"] = {
      {"population", settings_.population},     {"initial_sigma", settings_.initial_sigma},
      {"initial_mean", settings_.initial_mean}, {"diagonal", settings_.diagonal},
      {"max_restarts", settings_.max_restarts}, {"tol_x", settings_.tol_x},
      {"tol_fun", settings_.tol_fun},           {"seed", settings_.seed},
      {"stall_generations", settings_.stall_generations}};
  state["rng"] = random_.saveState();
  state["lambda"] = lambda_;
  state["mean"] = mean_;
  state["sigma"] = sigma_;
  state["pc"] = pc_;
  state["ps"] = ps_;
  if (settings_.diagonal) {
    state["covariance"] = cov_;
  } else {
    state["covariance"] = state_json::rows(cov_, n);
    state["basis"] = state_json::rows(basis_, n);
  }
  state["scales"] = scales_;
  state["decomposed_at"] = decomposed_at_;
  state["samples"] = state_json::rows(samples_, n);
  state["run_generation"] = run_generation_;
  json history = json::array();
  for (double h : history_) history.push_back(state_json::cost(h));
  state["history"] = history;
  state["restarts"] = restarts_;
  state["run_best"] = state_json::cost(run_best_);
  state["run_best_at"] = run_best_at_;
  state["stop"] = stop_;
}

Result<std::unique_ptr<Cmaes>> Cmaes::load(const json& state) {
  namespace sj = state_json;
  const std::string where = "optimizer state";
  int n = 0;
  if (Status s = sj::readInt(state, "dimension", where, 1, kMaxDimension, n); !s.ok()) return s;
  const size_t un = static_cast<size_t>(n);

  Result<const json*> settings_json = sj::field(state, "settings", where);
  if (!settings_json.ok()) return settings_json.status();
  const json& js = *settings_json.value();
  const std::string in_settings = where + ": settings";
  CmaesSettings settings;
  Status s = sj::readInt(js, "population", in_settings, 0, static_cast<int>(kMaxPopulation),
                         settings.population);
  if (s.ok()) s = sj::readNumber(js, "initial_sigma", in_settings, settings.initial_sigma);
  if (s.ok())
    s = sj::readVector(js, "initial_mean", in_settings, sj::kAnySize, settings.initial_mean);
  if (s.ok()) s = sj::readBool(js, "diagonal", in_settings, settings.diagonal);
  if (s.ok())
    s = sj::readInt(js, "max_restarts", in_settings, 0, kMaxRestarts, settings.max_restarts);
  if (s.ok()) s = sj::readNumber(js, "tol_x", in_settings, settings.tol_x);
  if (s.ok()) s = sj::readNumber(js, "tol_fun", in_settings, settings.tol_fun);
  if (s.ok()) s = sj::readUint64(js, "seed", in_settings, settings.seed);
  if (s.ok() && js.contains("stall_generations"))  // states from before local restarts: off
    s = sj::readInt(js, "stall_generations", in_settings, 0, 1000000, settings.stall_generations);
  if (!s.ok()) return s;
  if (Status v = settings.validate(n); !v.ok())
    return Status::error(in_settings + ": " + v.message());

  std::unique_ptr<Cmaes> c(new Cmaes(n, settings));
  s = c->loadCommon(state);
  Result<const json*> rng = sj::field(state, "rng", where);
  if (s.ok() && !rng.ok()) s = rng.status();
  if (!s.ok()) return s;
  Result<Random> random = Random::load(*rng.value(), where + ": rng");
  if (!random.ok()) return random.status();
  c->random_ = random.value();

  int lambda = 0;
  s = sj::readInt(state, "lambda", where, 2, static_cast<int>(kMaxPopulation), lambda);
  if (s.ok() && c->population() != lambda)
    s = Status::error(where + ": points: expected lambda = " + std::to_string(lambda) +
                      " arrays, found " + std::to_string(c->population()));
  if (!s.ok()) return s;
  c->configure(lambda);
  s = sj::readVector(state, "mean", where, un, c->mean_);
  if (s.ok()) s = sj::readNumber(state, "sigma", where, c->sigma_);
  if (s.ok() && !(c->sigma_ > 0.0)) s = Status::error(where + ": sigma: expected a number > 0");
  if (s.ok()) s = sj::readVector(state, "pc", where, un, c->pc_);
  if (s.ok()) s = sj::readVector(state, "ps", where, un, c->ps_);
  if (s.ok() && settings.diagonal) s = sj::readVector(state, "covariance", where, un, c->cov_);
  if (s.ok() && !settings.diagonal) s = sj::readRows(state, "covariance", where, un, un, c->cov_);
  if (s.ok() && !settings.diagonal) s = sj::readRows(state, "basis", where, un, un, c->basis_);
  if (s.ok()) s = sj::readVector(state, "scales", where, un, c->scales_);
  if (s.ok() &&
      !std::all_of(c->scales_.begin(), c->scales_.end(), [](double d) { return d > 0.0; }))
    s = Status::error(where + ": scales: expected numbers > 0");
  if (s.ok())
    s = sj::readInt(state, "decomposed_at", where, 0LL, c->evaluations(), c->decomposed_at_);
  if (s.ok())
    s = sj::readRows(state, "samples", where, static_cast<size_t>(lambda), un, c->samples_);
  if (s.ok())
    s = sj::readInt(state, "run_generation", where, 0, c->generation(), c->run_generation_);
  if (s.ok())
    s = sj::readCosts(state, "history", where, static_cast<size_t>(c->history_length_),
                      c->history_);
  if (s.ok()) s = sj::readInt(state, "restarts", where, 0, settings.max_restarts, c->restarts_);
  if (s.ok() && state.contains("run_best")) {  // states from before local restarts: recomputed
    s = sj::readCost(state, "run_best", where, c->run_best_);
    if (s.ok())
      s = sj::readInt(state, "run_best_at", where, 0, c->run_generation_, c->run_best_at_);
  } else if (s.ok()) {
    c->run_best_ = std::numeric_limits<double>::infinity();
    const size_t kept = c->history_.size();  // the last entry is run_generation_'s
    for (size_t g = 0; g < kept; ++g)
      if (std::isfinite(c->history_[g]) && c->history_[g] < c->run_best_) {
        c->run_best_ = c->history_[g];
        c->run_best_at_ = c->run_generation_ - static_cast<int>(kept - 1 - g);
      }
  }
  if (s.ok()) s = sj::readString(state, "stop", where, c->stop_);
  if (s.ok() && !(c->stop_.empty() || c->stop_ == "tol_x" || c->stop_ == "tol_fun" ||
                  c->stop_ == "condition" || c->stop_ == "stall"))
    s = Status::error(where +
                      ": stop: expected \"\", \"tol_x\", \"tol_fun\", \"condition\" or \"stall\"");
  if (!s.ok()) return s;
  return c;
}

}  // namespace sinew::search
