// A search session: the optimiser, the problem and a worker thread that evaluates generation
// after generation, as the editor and `sinew evolve` drive it.
//
// - start() runs generations on a background thread; pause(), resume() and stop() are honoured
//   within one simulation step of every evaluation in flight (well under 100 ms): the generation
//   in flight is abandoned and, after resume(), evaluated again from the same points, which gives
//   the same results (evaluations are deterministic), so pausing changes nothing.
// - After each generation the session publishes an immutable Snapshot (shared_ptr): per-term
//   best/mean/worst history, the best point and its terms, the population's points, terms and
//   (when `record_population`) recorded motions for live replay.
// - Fitness weights changed with setWeights() apply from the next generation, which first scores
//   the kept bests (the session's and the optimiser's) again under them, so that new points are
//   compared with them on the same scale.
// - checkpoint() is the optimiser's state, the history and the settings between generations;
//   Session::resume() continues from it to the same result as an uninterrupted run.
// - The same seed gives the same best point and cost bit for bit, whatever the thread count.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"
#include "sinew/physics/joint_figures.h"
#include "sinew/search/optimizer.h"
#include "sinew/search/problem.h"

namespace sinew::search {

inline constexpr int kMaxPopulation = 100000;

// Which optimiser a search runs. Its name ("cmaes", "ga") is what flags, projects and checkpoints
// write.
enum class OptimizerKind : std::uint8_t { kCmaes, kGa };
const char* optimizerName(OptimizerKind kind);  // "cmaes", "ga"
// The kind called `name`; the message lists the names.
Result<OptimizerKind> optimizerFromName(const std::string& name);

// Where a session is. Its name ("ready", "running", ...) is what logs print.
enum class SessionState : std::uint8_t { kReady, kRunning, kPaused, kStopped, kFinished };
const char* sessionStateName(SessionState state);
// Running or paused: a search is under way (it may be resumed).
inline bool underWay(SessionState state) {
  return state == SessionState::kRunning || state == SessionState::kPaused;
}
// Stopped or finished: the worker has ended.
inline bool ended(SessionState state) {
  return state == SessionState::kStopped || state == SessionState::kFinished;
}

struct EvolveSettings {
  OptimizerKind optimizer = OptimizerKind::kCmaes;
  int population = 0;    // 0: the optimiser's default (CMA-ES 4 + 3 ln n; GA 32),
                         // at most kMaxPopulation
  int generations = 40;  // budget in generations, >= 0 (0: only the time budget)
  double minutes = 0.0;  // wall-clock budget, minutes, >= 0 (0: none)
  int threads = 0;       // evaluation workers, >= 0 (0: every core)
  std::uint64_t seed = 1;
  double initial_sigma = 0.02;     // CMA-ES step size (GA: mutation scale), normalised units,
                                   // (0, 1]: small, the prior walks already
  int restart_after = 0;  // CMA-ES: a local restart (from the start point, a fresh stream of
                          // samples, the best kept) after this many generations without a
                          // better best; 0: never (CmaesSettings::stall_generations)
  // The layout's starts (GenomeLayout::startPoints: the stance yield off, then at half) are
  // searched in turn for this many generations each, the first start whose best walks the whole
  // window kept at once, else the one with the best cost (Portfolio); 0, or a layout with one
  // start: the first start alone.
  int start_generations = 50;
  bool record_population = false;  // keep every individual's recorded motion in the snapshots
  int nice = 0;  // 0..19: the search threads' niceness (Linux). The editor uses 10 so that its UI
                 // thread gets the cores first while the search still takes whatever is left.

  Status validate() const;  // the message names the offending field
};

struct TermStats {
  double best = 0.0, mean = 0.0, worst = 0.0;  // over the generation's scored evaluations; all 0
                                               // when none was (GenerationRecord::scored == 0)
};

struct GenerationRecord {
  int generation = 0;         // 1 for the first finished generation
  long long evaluations = 0;  // so far
  double wall_s = 0.0;        // since the session (or its first part, when resumed) started
  TermStats total;
  std::array<TermStats, kFitnessTermCount> terms{};
  double best_survived_s = 0.0;  // of the generation's best
  double best_distance_m = 0.0;
  int scored = 0;    // evaluations with a finite cost
  int diverged = 0;  // evaluations whose simulation diverged or could not run (cost +inf)
};

// A search that found nothing finite in this many generations stops (Snapshot::failure).
inline constexpr int kGenerationsWithoutScore = 3;

struct Snapshot {
  int generation = 0;
  long long evaluations = 0;
  std::vector<GenerationRecord> history;
  std::vector<double> best_point;  // best so far (empty before the first generation)
  FitnessTerms best_terms;
  // The best run's joints at their torque limit and furthest from the clip, for the user (empty
  // after a resume until a new best, and for a best evaluated by another process).
  physics::JointFigures best_joints;
  std::vector<std::vector<double>> population;  // the last finished generation's points
  std::vector<FitnessTerms> population_terms;
  std::vector<motion::Clip> population_motions;  // when record_population
  SessionState state = SessionState::kReady;
  std::string failure;  // why the search stopped without a result (every evaluation of its first
                        // kGenerationsWithoutScore generations diverged), or empty
  std::string start;    // which start the search is on, when it tries several
                        // (EvolveSettings::start_generations): "trying start 2 of 2 (stance yield
                        // 0.5)", "start 1 of 2 (the prior) kept"; empty for one start
};

// How a session evaluates a generation: evaluateAll's contract (results in the points' order,
// each `cancelled` when `cancel` was set before it finished). The default is evaluateAll on this
// process's threads; `sinew evolve` under mpirun hands shares of the points to other processes.
using GenerationEvaluator = std::function<std::vector<Evaluation>(
    const Problem& problem, const std::vector<std::vector<double>>& points, int threads,
    const std::atomic<bool>* cancel, bool record)>;

class Session {
 public:
  static Result<std::unique_ptr<Session>> create(Problem problem, const EvolveSettings& settings);
  // From checkpoint(); the problem must be built as it was (the same rig, clip and genome). Its
  // robustness (trials, pushes) may differ: the kept best is scored again under it before the
  // first generation.
  static Result<std::unique_ptr<Session>> resume(Problem problem, const nlohmann::json& checkpoint);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void start();  // runs on a background thread until the budget, stop() or convergence
  void pause();  // returns once the worker is idle
  void resume();
  void stop();  // returns once the worker has ended
  void wait();  // until the worker ends by itself or is stopped
  // One generation on the calling thread (not while started); false when the budget is spent
  // or the run was cancelled.
  bool runGeneration();

  void setWeights(const FitnessWeights& weights);  // from the next generation
  // Before start() or runGeneration(): who evaluates the generations (evaluateAll when empty).
  void setEvaluator(GenerationEvaluator evaluator);
  // A new budget (a resumed search going on): total generations and minutes, as in the settings.
  Status setBudget(int generations, double minutes);
  std::shared_ptr<const Snapshot> snapshot() const;
  nlohmann::json checkpoint() const;
  const Problem& problem() const { return problem_; }
  const EvolveSettings& settings() const { return settings_; }
  bool finished() const;   // budget spent, converged, or nothing finite found (Snapshot::failure)
  int population() const;  // individuals in the current generation

 private:
  Session(Problem problem, const EvolveSettings& settings);
  void workerLoop();
  // New weights applied and stale bests scored again; false: cancelled while scoring.
  bool applyFitnessChange();
  void publish(SessionState state);
  // With mutex_ held: whether kGenerationsWithoutScore generations scored nothing, and why.
  bool nothingFinite() const;
  std::string failureLocked() const;

  Problem problem_;
  EvolveSettings settings_;
  std::unique_ptr<Optimizer> optimizer_;
  std::vector<std::string> start_names_;  // (starts) GenomeLayout::Start::name, for Snapshot::start
  std::vector<GenerationRecord> history_;
  std::vector<double> best_point_;
  FitnessTerms best_terms_;
  physics::JointFigures best_joints_;
  double wall_offset_s_ = 0.0;  // wall time of earlier parts (resumed sessions)
  double started_at_ = 0.0;
  GenerationEvaluator evaluator_;  // empty: evaluateAll

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::shared_ptr<const Snapshot> snapshot_;
  FitnessWeights pending_weights_;
  bool weights_changed_ = false;
  bool best_stale_ = false;  // the best's terms are from other weights or another problem
  std::atomic<bool> cancel_{false};
  bool paused_ = false;
  bool stopping_ = false;
  bool running_ = false;
  std::thread worker_;
};

// The number of hardware threads (at least 1).
int hardwareThreads();

}  // namespace sinew::search
