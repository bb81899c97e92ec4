#include "sinew/search/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#ifdef __linux__
#include <sys/resource.h>
#include <unistd.h>
#endif

#include "sinew/physics/tracking.h"
#include "sinew/search/cmaes.h"
#include "sinew/search/genetic.h"
#include "sinew/search/portfolio.h"
#include "state_json.h"

namespace sinew::search {
namespace {

constexpr const char* kSessionFormat = "sinew.search_session";
constexpr int kSessionVersion = 1;
// Above this many coordinates CMA-ES keeps a diagonal covariance (sep-CMA-ES): O(n) per sample.
constexpr int kDiagonalAbove = 100;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

nlohmann::json statsJson(const TermStats& s) {
  return {s.best, s.mean, s.worst};
}
// Three finite numbers (checkpoints before divergence was detected could hold null for inf).
Result<TermStats> statsFromJson(const nlohmann::json& j, const std::string& where) {
  const auto finiteAt = [&j](size_t i) {
    return j[i].is_number() && std::isfinite(j[i].get<double>());
  };
  if (!j.is_array() || j.size() != 3 || !finiteAt(0) || !finiteAt(1) || !finiteAt(2))
    return Status::error(where + ": expected [best, mean, worst], three finite numbers");
  return TermStats{j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

nlohmann::json weightsJson(const FitnessWeights& w) {
  return {{"fall", w.fall},       {"tracking", w.tracking},   {"speed", w.speed},
          {"heading", w.heading}, {"placement", w.placement}, {"upright", w.upright},
          {"energy", w.energy},   {"style", w.style}};
}

// Linux keeps a niceness per thread, inherited by the threads it creates.
void lowerThisThreadsPriority(int nice) {
#ifdef __linux__
  if (nice > 0) setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice);
#else
  (void)nice;
#endif
}

}  // namespace

int hardwareThreads() {
  return std::max(1u, std::thread::hardware_concurrency());
}

const char* optimizerName(OptimizerKind kind) {
  return kind == OptimizerKind::kGa ? "ga" : "cmaes";
}

Result<OptimizerKind> optimizerFromName(const std::string& name) {
  if (name == "cmaes") return OptimizerKind::kCmaes;
  if (name == "ga") return OptimizerKind::kGa;
  return Status::error("expected \"cmaes\" or \"ga\", got \"" + name + "\"");
}

const char* sessionStateName(SessionState state) {
  switch (state) {
    case SessionState::kReady:
      return "ready";
    case SessionState::kRunning:
      return "running";
    case SessionState::kPaused:
      return "paused";
    case SessionState::kStopped:
      return "stopped";
    case SessionState::kFinished:
      return "finished";
  }
  return "ready";
}

Status EvolveSettings::validate() const {
  if (population < 0 || population > kMaxPopulation)
    return Status::error("population must be 0 (the optimiser's default) to 100000");
  if (generations < 0) return Status::error("generations must be >= 0");
  if (!(std::isfinite(minutes) && minutes >= 0.0)) return Status::error("minutes must be >= 0");
  if (generations == 0 && minutes == 0.0)
    return Status::error("generations and minutes are both 0: give the search a budget");
  if (threads < 0 || threads > 1024) return Status::error("threads must be 0 (every core) to 1024");
  if (nice < 0 || nice > 19) return Status::error("nice must be 0..19");
  if (!(std::isfinite(initial_sigma) && initial_sigma > 0.0 && initial_sigma <= 1.0))
    return Status::error("initial_sigma must be in (0, 1]");
  if (restart_after < 0 || restart_after > 100000)
    return Status::error("restart_after must be 0 (never) to 100000 generations");
  if (start_generations < 0 || start_generations > 100000)
    return Status::error("start_generations must be 0 (the first start alone) to 100000");
  return Status();
}

Session::Session(Problem problem, const EvolveSettings& settings)
    : problem_(std::move(problem)), settings_(settings), pending_weights_(problem_.weights) {}

Session::~Session() {
  stop();
}

namespace {

// One optimiser of `settings`' kind from `start`.
Result<std::unique_ptr<Optimizer>> makeOptimizer(const EvolveSettings& settings,
                                                 const std::vector<double>& start) {
  const int n = static_cast<int>(start.size());
  if (settings.optimizer == OptimizerKind::kCmaes) {
    CmaesSettings c;
    c.population = settings.population;
    c.initial_sigma = settings.initial_sigma;
    c.initial_mean = start;
    c.diagonal = n > kDiagonalAbove;
    c.seed = settings.seed;
    c.stall_generations = settings.restart_after;
    c.max_restarts = settings.restart_after > 0 ? kMaxCmaesRestarts : 0;
    Result<std::unique_ptr<Cmaes>> made = Cmaes::create(n, c);
    if (!made.ok()) return made.status();
    return std::unique_ptr<Optimizer>(std::move(made).value());
  }
  GeneticSettings g;
  g.population = settings.population > 0 ? settings.population : 32;
  g.initial_point = start;
  g.initial_spread = settings.initial_sigma;
  g.mutation_scale = settings.initial_sigma;
  g.seed = settings.seed;
  Result<std::unique_ptr<Genetic>> made = Genetic::create(n, g);
  if (!made.ok()) return made.status();
  return std::unique_ptr<Optimizer>(std::move(made).value());
}

// The optimiser of a new search: from the layout's first start, or, when it offers more and
// settings.start_generations > 0, a Portfolio trying each (the same seed for every member).
Result<std::unique_ptr<Optimizer>> makeSearch(const std::vector<GenomeLayout::Start>& starts,
                                              const EvolveSettings& settings) {
  std::vector<std::unique_ptr<Optimizer>> members;
  for (const GenomeLayout::Start& start : starts) {
    Result<std::unique_ptr<Optimizer>> made = makeOptimizer(settings, start.point);
    if (!made.ok()) return made.status();
    members.push_back(std::move(made).value());
  }
  if (members.size() == 1) return std::move(members.front());
  Result<std::unique_ptr<Portfolio>> portfolio =
      Portfolio::create(std::move(members), settings.start_generations);
  if (!portfolio.ok()) return portfolio.status();
  return std::unique_ptr<Optimizer>(std::move(portfolio).value());
}

// Which of a portfolio's starts asks for the current generation (0 for a single start).
int askingStart(const Optimizer& optimizer) {
  const auto* portfolio = dynamic_cast<const Portfolio*>(&optimizer);
  return portfolio == nullptr ? 0 : portfolio->current();
}

// A portfolio still trying starts keeps start `asking` once the best run of the generation it
// asked for walked the whole window: a start that works costs no more than a search from it.
void keepStartThatWalks(Optimizer& optimizer, int asking, const FitnessTerms& best) {
  auto* portfolio = dynamic_cast<Portfolio*>(&optimizer);
  if (portfolio == nullptr || portfolio->chosen() >= 0) return;
  if (std::isfinite(best.total) && !best.fell) portfolio->keep(asking);
}

// For the user: which start the search is on ("" for a single start).
std::string startNote(const Optimizer& optimizer, const std::vector<std::string>& names) {
  const auto* portfolio = dynamic_cast<const Portfolio*>(&optimizer);
  if (portfolio == nullptr) return {};
  const int i = portfolio->current();
  const std::string which = "start " + std::to_string(i + 1) + " of " +
                            std::to_string(portfolio->members()) +
                            (static_cast<size_t>(i) < names.size() ? " (" + names[i] + ")" : "");
  return portfolio->chosen() < 0 ? "trying " + which : which + " kept";
}

}  // namespace

Result<std::unique_ptr<Session>> Session::create(Problem problem, const EvolveSettings& settings) {
  if (Status s = settings.validate(); !s.ok())
    return Status::error("search settings: " + s.message());
  std::unique_ptr<Session> session(new Session(std::move(problem), settings));
  std::vector<GenomeLayout::Start> starts = session->problem_.layout.startPoints(settings.seed);
  if (settings.start_generations == 0) starts.resize(1);
  for (const GenomeLayout::Start& start : starts) session->start_names_.push_back(start.name);
  Result<std::unique_ptr<Optimizer>> optimizer = makeSearch(starts, settings);
  if (!optimizer.ok()) return optimizer.status();
  session->optimizer_ = std::move(optimizer).value();
  session->publish(SessionState::kReady);
  return session;
}

Result<std::unique_ptr<Session>> Session::resume(Problem problem,
                                                 const nlohmann::json& checkpoint) {
  try {
    if (checkpoint.at("format").get<std::string>() != kSessionFormat)
      return Status::error("checkpoint: format is not " + std::string(kSessionFormat));
    if (checkpoint.at("version").get<int>() != kSessionVersion)
      return Status::error("checkpoint: version " + checkpoint.at("version").dump() + " is not " +
                           std::to_string(kSessionVersion));
    const nlohmann::json& s = checkpoint.at("settings");
    EvolveSettings settings;
    Result<OptimizerKind> kind = optimizerFromName(s.at("optimizer").get<std::string>());
    if (!kind.ok()) return Status::error("checkpoint: settings.optimizer: " + kind.message());
    settings.optimizer = kind.value();
    settings.population = s.at("population").get<int>();
    settings.generations = s.at("generations").get<int>();
    settings.minutes = s.at("minutes").get<double>();
    settings.threads = s.at("threads").get<int>();
    settings.seed = s.at("seed").get<std::uint64_t>();
    settings.initial_sigma = s.at("initial_sigma").get<double>();
    settings.record_population = s.at("record_population").get<bool>();
    settings.restart_after = s.value("restart_after", 0);  // checkpoints from before: off
    settings.start_generations = s.value("start_generations", 0);  // before: one start
    if (Status st = settings.validate(); !st.ok())
      return Status::error("checkpoint: settings: " + st.message());
    if (checkpoint.at("genome_size").get<int>() != problem.layout.size())
      return Status::error("checkpoint: its genome has " + checkpoint.at("genome_size").dump() +
                           " coordinates, this rig and clip give " +
                           std::to_string(problem.layout.size()) + ": not the same search");
    const nlohmann::json& w = checkpoint.at("weights");
    problem.weights = {w.at("fall").get<double>(),      w.at("tracking").get<double>(),
                       w.at("speed").get<double>(),     w.at("heading").get<double>(),
                       w.at("placement").get<double>(), w.at("upright").get<double>(),
                       w.at("energy").get<double>(),    w.value("style", 0.0)};  // absent before the style term
    // Searched with the servos' lead it had (none in a checkpoint from before the lead).
    const double lead = checkpoint.value("servo_lead_s", 0.0);
    if (!physics::validServoLead(lead))
      return Status::error("checkpoint: servo_lead_s: expected seconds in [0, 1]");
    problem.simulation.tracking.servo_lead_s = lead;
    problem.simulation.tracking.lead_yielding_legs = false;  // a checkpoint from before it
    if (checkpoint.contains("lead_yielding_legs"))
      if (Status read = state_json::readBool(checkpoint, "lead_yielding_legs", "checkpoint",
                                          problem.simulation.tracking.lead_yielding_legs);
          !read.ok())
        return read;
    std::unique_ptr<Session> session(new Session(std::move(problem), settings));
    Result<std::unique_ptr<Optimizer>> optimizer = Optimizer::load(checkpoint.at("optimizer"));
    if (!optimizer.ok()) return Status::error("checkpoint: " + optimizer.message());
    session->optimizer_ = std::move(optimizer).value();
    for (const GenomeLayout::Start& start : session->problem_.layout.startPoints(settings.seed))
      session->start_names_.push_back(start.name);
    const nlohmann::json& history = checkpoint.at("history");
    for (size_t i = 0; i < history.size(); ++i) {
      const nlohmann::json& h = history.at(i);
      const std::string where = "checkpoint: history[" + std::to_string(i) + "].";
      GenerationRecord r;
      r.generation = h.at("generation").get<int>();
      r.evaluations = h.at("evaluations").get<long long>();
      r.wall_s = h.at("wall_s").get<double>();
      Result<TermStats> total = statsFromJson(h.at("total"), where + "total");
      if (!total.ok()) return total.status();
      r.total = total.value();
      for (int k = 0; k < kFitnessTermCount; ++k) {
        if (!h.contains(fitnessTermName(k)) && std::string(fitnessTermName(k)) == "style")
          continue;  // a checkpoint from before the style term: it was 0
        Result<TermStats> term =
            statsFromJson(h.at(fitnessTermName(k)), where + fitnessTermName(k));
        if (!term.ok()) return term.status();
        r.terms[static_cast<size_t>(k)] = term.value();
      }
      r.scored = h.value("scored", 1);  // older checkpoints: generations were scored
      r.diverged = h.value("diverged", 0);
      r.best_survived_s = h.at("best_survived_s").get<double>();
      r.best_distance_m = h.at("best_distance_m").get<double>();
      session->history_.push_back(r);
    }
    session->best_point_ = checkpoint.at("best_point").get<std::vector<double>>();
    if (!session->best_point_.empty()) {
      Result<FitnessTerms> terms = fitnessFromJson(checkpoint.at("best_terms"));
      if (!terms.ok()) return Status::error("checkpoint: best_terms: " + terms.message());
      session->best_terms_ = terms.value();
    }
    // Scored again before the first generation (applyFitnessChange): the problem may push it
    // differently now (`sinew evolve --resume --trials`), and its joint figures are not kept.
    session->best_stale_ = !session->best_point_.empty();
    session->wall_offset_s_ = checkpoint.at("wall_s").get<double>();
    session->publish(SessionState::kReady);
    return session;
  } catch (const nlohmann::json::exception& e) {
    return Status::error(std::string("checkpoint: ") + e.what());
  }
}

nlohmann::json Session::checkpoint() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json history = nlohmann::json::array();
  for (const GenerationRecord& r : history_) {
    nlohmann::json h = {{"generation", r.generation},
                        {"evaluations", r.evaluations},
                        {"wall_s", r.wall_s},
                        {"total", statsJson(r.total)},
                        {"best_survived_s", r.best_survived_s},
                        {"best_distance_m", r.best_distance_m},
                        {"scored", r.scored},
                        {"diverged", r.diverged}};
    for (int k = 0; k < kFitnessTermCount; ++k)
      h[fitnessTermName(k)] = statsJson(r.terms[static_cast<size_t>(k)]);
    history.push_back(h);
  }
  return {{"format", kSessionFormat},
          {"version", kSessionVersion},
          {"settings",
           {{"optimizer", optimizerName(settings_.optimizer)},
            {"population", settings_.population},
            {"generations", settings_.generations},
            {"minutes", settings_.minutes},
            {"threads", settings_.threads},
            {"seed", settings_.seed},
            {"initial_sigma", settings_.initial_sigma},
            {"record_population", settings_.record_population},
            {"restart_after", settings_.restart_after},
            {"start_generations", settings_.start_generations}}},
          {"genome_size", problem_.layout.size()},
          {"weights", weightsJson(problem_.weights)},
          {"servo_lead_s", problem_.simulation.tracking.servo_lead_s},
          {"lead_yielding_legs", problem_.simulation.tracking.lead_yielding_legs},
          {"optimizer", optimizer_->saveState()},
          {"history", history},
          {"best_point", best_point_},
          {"best_terms", best_point_.empty() ? nlohmann::json::object() : fitnessJson(best_terms_)},
          {"wall_s", history_.empty() ? wall_offset_s_ : history_.back().wall_s}};
}

int Session::population() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return optimizer_->population();
}

bool Session::finished() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const int done = optimizer_->generation();
  const bool generations_spent = settings_.generations > 0 && done >= settings_.generations;
  const double wall = history_.empty() ? wall_offset_s_ : history_.back().wall_s;
  const bool time_spent = settings_.minutes > 0.0 && wall >= settings_.minutes * 60.0;
  return generations_spent || time_spent || optimizer_->converged() || nothingFinite();
}

bool Session::nothingFinite() const {
  if (history_.size() < static_cast<size_t>(kGenerationsWithoutScore) || !best_point_.empty())
    return false;
  for (const GenerationRecord& r : history_)
    if (r.scored > 0) return false;
  return true;
}

std::string Session::failureLocked() const {
  if (!nothingFinite()) return {};
  const GenerationRecord& last = history_.back();
  return "every evaluation of the first " + std::to_string(history_.size()) +
         " generations failed (" + std::to_string(last.diverged) + " of " +
         std::to_string(last.diverged + last.scored) +
         " in the last diverged): nothing finite to keep; check the balance gains, pushes, "
         "masses and the clip's frame time";
}

// New weights from setWeights() apply here, and the kept bests are scored again under them (and
// after a resume, under the problem as it is now): the session's and those the optimiser
// compares with (a portfolio's members', which choose the start that goes on). With their old
// costs kept, a heavier weight left them out of the new points' reach (every cost rose but
// theirs) and a lighter one let a worse point replace them. False when cancelled while scoring;
// the next call scores them again.
bool Session::applyFitnessChange() {
  std::vector<std::vector<double>> points;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (weights_changed_) {
      problem_.weights = pending_weights_;
      weights_changed_ = false;
      best_stale_ = !best_point_.empty();
    }
    if (!best_stale_) return true;
    points = optimizer_->bests();
    points.push_back(best_point_);
  }
  // One point often stands in several places (the session's best is usually the optimiser's, a
  // portfolio's is one of its members'): each distinct point is evaluated once.
  std::vector<std::vector<double>> distinct;
  std::vector<size_t> which(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    auto found = std::find(distinct.begin(), distinct.end(), points[i]);
    which[i] = static_cast<size_t>(found - distinct.begin());
    if (found == distinct.end()) distinct.push_back(points[i]);
  }
  const int threads = settings_.threads > 0 ? settings_.threads : hardwareThreads();
  std::vector<Evaluation> results = evaluateAll(problem_, distinct, threads, &cancel_, false);
  for (const Evaluation& e : results)
    if (e.cancelled) return false;
  std::vector<double> costs(points.size() - 1);
  for (size_t i = 0; i < costs.size(); ++i) costs[i] = results[which[i]].terms.total;
  const Evaluation& best = results[which.back()];
  std::lock_guard<std::mutex> lock(mutex_);
  optimizer_->rescore(costs);
  best_terms_ = best.terms;
  best_joints_ = physics::jointFigures(best.report);
  best_stale_ = false;
  return true;
}

bool Session::runGeneration() {
  if (finished()) return false;
  if (!applyFitnessChange()) return false;
  if (started_at_ == 0.0) started_at_ = now();
  const std::vector<std::vector<double>> points = optimizer_->ask();
  const int asking = askingStart(*optimizer_);
  const int threads = settings_.threads > 0 ? settings_.threads : hardwareThreads();
  std::vector<Evaluation> results =
      evaluator_ ? evaluator_(problem_, points, threads, &cancel_, settings_.record_population)
                 : evaluateAll(problem_, points, threads, &cancel_, settings_.record_population);
  for (const Evaluation& e : results)
    if (e.cancelled) return false;  // abandoned: the same points are asked again later

  std::vector<double> costs(results.size());
  for (size_t i = 0; i < results.size(); ++i) costs[i] = results[i].terms.total;
  GenerationRecord record;
  record.total = {std::numeric_limits<double>::infinity(), 0.0,
                  -std::numeric_limits<double>::infinity()};
  for (TermStats& t : record.terms) t = record.total;
  size_t best = 0, finite = 0;
  for (size_t i = 0; i < results.size(); ++i) {
    const FitnessTerms& t = results[i].terms;
    if (t.diverged) ++record.diverged;
    if (!std::isfinite(t.total)) continue;
    ++finite;
    if (!std::isfinite(costs[best]) || t.total < costs[best]) best = i;
    auto add = [](TermStats& s, double v) {
      s.best = std::min(s.best, v);
      s.worst = std::max(s.worst, v);
      s.mean += v;
    };
    add(record.total, t.total);
    for (int k = 0; k < kFitnessTermCount; ++k)
      add(record.terms[static_cast<size_t>(k)], fitnessTerm(t, k));
  }
  record.scored = static_cast<int>(finite);
  if (finite > 0) {
    record.total.mean /= static_cast<double>(finite);
    for (TermStats& s : record.terms) s.mean /= static_cast<double>(finite);
  } else {  // nothing scored: no statistics, and no inf for a file to carry
    record.total = {};
    for (TermStats& s : record.terms) s = {};
  }
  record.best_survived_s = results[best].terms.survived_s;
  record.best_distance_m = results[best].terms.distance_m;

  {
    // Under the lock: checkpoint() reads the optimiser's state from other threads.
    std::lock_guard<std::mutex> lock(mutex_);
    if (Status told = optimizer_->tell(costs); !told.ok()) return false;
    keepStartThatWalks(*optimizer_, asking, results[best].terms);
    record.generation = optimizer_->generation();
    record.evaluations = optimizer_->evaluations();
    record.wall_s = wall_offset_s_ + (now() - started_at_);
    history_.push_back(record);
    if (std::isfinite(costs[best]) && (best_point_.empty() || costs[best] < best_terms_.total)) {
      best_point_ = points[best];
      best_terms_ = results[best].terms;
      best_joints_ = physics::jointFigures(results[best].report);
    }
  }
  auto snap = std::make_shared<Snapshot>();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    snap->generation = optimizer_->generation();
    snap->evaluations = optimizer_->evaluations();
    snap->history = history_;
    snap->best_point = best_point_;
    snap->best_terms = best_terms_;
    snap->best_joints = best_joints_;
    snap->population = points;
    for (Evaluation& e : results) {
      snap->population_terms.push_back(e.terms);
      if (settings_.record_population)
        snap->population_motions.push_back(std::move(e.report.motion));
    }
    snap->state = running_ ? SessionState::kRunning : SessionState::kReady;
    snap->failure = failureLocked();
    snap->start = startNote(*optimizer_, start_names_);
    snapshot_ = std::move(snap);
  }
  return true;
}

void Session::publish(SessionState state) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto snap = snapshot_ ? std::make_shared<Snapshot>(*snapshot_) : std::make_shared<Snapshot>();
  if (!snapshot_) {
    snap->generation = optimizer_->generation();
    snap->evaluations = optimizer_->evaluations();
    snap->history = history_;
    snap->best_point = best_point_;
    snap->best_terms = best_terms_;
    snap->best_joints = best_joints_;
    snap->start = startNote(*optimizer_, start_names_);
  }
  snap->state = state;
  snap->failure = failureLocked();
  snapshot_ = std::move(snap);
}

std::shared_ptr<const Snapshot> Session::snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return snapshot_;
}

Status Session::setBudget(int generations, double minutes) {
  std::lock_guard<std::mutex> lock(mutex_);
  EvolveSettings changed = settings_;
  changed.generations = generations;
  changed.minutes = minutes;
  if (Status s = changed.validate(); !s.ok()) return s;
  settings_ = changed;
  return Status();
}

void Session::setWeights(const FitnessWeights& weights) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_weights_ = weights;
  weights_changed_ = true;
}

void Session::setEvaluator(GenerationEvaluator evaluator) { evaluator_ = std::move(evaluator); }

void Session::workerLoop() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return !paused_ || stopping_; });
      if (stopping_) break;
    }
    if (runGeneration()) continue;
    if (finished()) break;  // budget spent or converged
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) break;
    // Cancelled by pause(): the abandoned generation runs again on resume().
    if (!paused_) cancel_ = false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  running_ = false;
}

void Session::start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (running_ || worker_.joinable()) return;
  running_ = true;
  stopping_ = false;
  paused_ = false;
  cancel_ = false;
  worker_ = std::thread([this] {
    lowerThisThreadsPriority(settings_.nice);  // the evaluation threads it starts inherit it
    publish(SessionState::kRunning);
    workerLoop();
    bool stopped = false;
    {
      std::lock_guard<std::mutex> guard(mutex_);
      stopped = stopping_;
    }
    publish(stopped ? SessionState::kStopped : SessionState::kFinished);
  });
}

void Session::pause() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!running_) return;
    paused_ = true;
    cancel_ = true;
  }
  publish(SessionState::kPaused);
}

void Session::resume() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!paused_) return;
    paused_ = false;
    cancel_ = false;
  }
  wake_.notify_all();
  publish(SessionState::kRunning);
}

void Session::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    cancel_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
  cancel_ = false;
}

void Session::wait() {
  if (worker_.joinable()) worker_.join();
}

}  // namespace sinew::search
