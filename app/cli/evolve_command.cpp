// sinew evolve: the DFT-seeded evolutionary search. Evolves the Fourier controller of a rig's
// physical character until its motion keeps the clip's style without falling; prints a line per
// generation; Ctrl-C stops cleanly, keeping the best so far and a checkpoint. Writes best.bvh,
// best.glb, best.json (loadable by `sinew simulate --controller`), history.csv and
// checkpoint.json into --out.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/controller_file.h"
#include "cli/distributed.h"
#include "cli/evolve.h"
#include "cli/report_lines.h"
#include "sinew/core/file_io.h"
#include "sinew/core/text.h"
#include "sinew/pipeline/physical_loop.h"
#include "sinew/pipeline/pipeline.h"
#include "sinew/pipeline/run_style.h"
#include "sinew/search/session.h"

namespace sinew::app {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void onInterrupt(int) {
  g_interrupted = true;
}

std::string termsLine(const search::FitnessTerms& t) {
  char style[32] = "";
  if (t.style > 0.0) std::snprintf(style, sizeof style, " style %.2f", t.style);
  char line[288];
  std::snprintf(line, sizeof line,
                "%.2f (fall %.1f track %.2f speed %.2f heading %.2f steps %.2f upright %.2f "
                "energy %.2f%s) up %.1f s, %.1f m",
                t.total, t.fall, t.tracking, t.speed, t.heading, t.placement, t.upright, t.energy,
                style, t.survived_s, t.distance_m);
  return t.fell && !t.fall_reason.empty() ? std::string(line) + " (fell: " + t.fall_reason + ")"
                                          : std::string(line);
}

// --weights TERM=VALUE, term by term over `weights`.
Status applyWeightFlags(const std::vector<std::string>& flags, search::FitnessWeights& weights) {
  for (const std::string& text : flags) {
    const size_t eq = text.find('=');
    int term = -1;
    for (int k = 0; k < search::kFitnessTermCount; ++k)
      if (eq != std::string::npos && text.substr(0, eq) == search::fitnessTermName(k)) term = k;
    double value = -1.0;
    try {
      size_t used = 0;
      if (term >= 0) value = std::stod(text.substr(eq + 1), &used);
      if (term >= 0 && used != text.size() - eq - 1) value = -1.0;
    } catch (const std::exception&) {
      value = -1.0;
    }
    if (term < 0 || !(value >= 0.0))
      return Status::error("--weights '" + text +
                           "': expected TERM=VALUE >= 0, TERM one of fall, tracking, "
                           "speed, heading, placement, upright, energy, style");
    search::fitnessWeight(weights, term) = value;
  }
  return Status();
}

// --style NEUTRAL,STYLED[:WEIGHT] (weight 1 when not given; label: the styled file's stem).
Result<pipeline::StylePair> parseStyleFlag(const std::string& text) {
  const std::string usage = "--style '" + text + "': expected NEUTRAL,STYLED[:WEIGHT]";
  const size_t comma = text.find(',');
  if (comma == std::string::npos || comma == 0 || comma + 1 == text.size())
    return Status::error(usage);
  pipeline::StylePair pair;
  pair.neutral = text.substr(0, comma);
  pair.styled = text.substr(comma + 1);
  pair.weight = 1.0;
  if (const size_t colon = pair.styled.rfind(':'); colon != std::string::npos) {
    const std::string number = pair.styled.substr(colon + 1);
    size_t used = 0;
    double weight = 0.0;
    try {
      weight = std::stod(number, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != number.size() || !(weight >= -1.0 && weight <= 2.0))
      return Status::error("--style '" + text + "': WEIGHT after ':' must be a number in [-1, 2]");
    pair.weight = weight;
    pair.styled = pair.styled.substr(0, colon);
  }
  if (pair.styled.empty() || pair.styled.find(',') != std::string::npos)
    return Status::error(usage);
  pair.label = toUtf8(std::filesystem::path(pair.styled).stem().string());
  return pair;
}

// The robustness flags over the search settings: a new search's, or a resumed one's (hardening a
// gait found without pushes: the session scores its best again under them).
void applyRobustnessFlags(const EvolveArgs& args, pipeline::SearchSettings& search) {
  if (args.has("--trials")) search.trials = args.trials;
  if (args.has("--trial-push")) search.trial_push_m_s = args.trial_push;
  if (args.has("--robust-push")) search.robust_push_m_s = args.robust_push;
}

// The project (or --rig and the defaults), then the command line's own flags over it.
Result<pipeline::ProjectSettings> chosenSettings(const EvolveArgs& args) {
  pipeline::ProjectSettings s;
  if (args.rig.empty()) {
    const std::string path = args.project.empty() ? kDefaultProject : args.project;
    std::vector<std::string> warnings;
    Result<Project> project = loadProject(path, &warnings);
    if (!project.ok()) return project.status();
    for (const std::string& warning : warnings)
      std::fprintf(stderr, "warning: %s\n", warning.c_str());
    s = project.value();
  } else {
    s.rig = args.rig;
  }
  if (!args.clip.empty()) s.clip = args.clip;
  if (!args.target_path.empty()) s.target = args.target_path;
  if (!args.animation.empty()) s.animation = args.animation;
  if (args.has("--harmonics")) s.harmonics = args.harmonics;
  if (args.has("--window")) s.physics.window_s = args.window;
  if (args.has("--population")) s.search.population = args.population;
  if (args.has("--seed")) s.search.seed = args.seed;
  if (args.has("--no-prior")) s.search.no_prior = args.no_prior;
  applyRobustnessFlags(args, s.search);
  if (args.has("--restart-after")) s.search.restart_after = args.restart_after;
  if (args.has("--start-generations")) s.search.start_generations = args.start_generations;
  if (args.has("--optimizer")) {
    Result<search::OptimizerKind> kind = search::optimizerFromName(args.optimizer);
    if (!kind.ok()) return Status::error("--optimizer: " + kind.message());
    s.search.optimizer = kind.value();
  }
  if (args.has("--terrain")) {
    Result<physics::TerrainSettings> terrain = parseTerrain(args.terrain);
    if (!terrain.ok()) return terrain.status();
    s.physics.terrain = terrain.value();
  }
  // Pushes and body overrides: the flags' first, then the project's.
  std::vector<physics::Push> pushes;
  for (const std::string& text : args.pushes) {
    Result<physics::Push> push = parsePush(text);
    if (!push.ok()) return push.status();
    pushes.push_back(push.value());
  }
  pushes.insert(pushes.end(), s.physics.pushes.begin(), s.physics.pushes.end());
  s.physics.pushes = std::move(pushes);
  Result<BodyOverrides> flags = args.body.overrides();
  if (!flags.ok()) return flags.status();
  BodyOverrides body = std::move(flags).value();
  const BodyOverrides& own = s.physics.body;
  body.masses.insert(body.masses.end(), own.masses.begin(), own.masses.end());
  body.fixed.insert(body.fixed.end(), own.fixed.begin(), own.fixed.end());
  body.hinge_limits.insert(body.hinge_limits.end(), own.hinge_limits.begin(),
                           own.hinge_limits.end());
  s.physics.body = std::move(body);
  if (Status w = applyWeightFlags(args.weights, s.search.weights); !w.ok()) return w;
  if (args.has("--style-weight")) s.search.weights.style = args.style_weight;
  for (const std::string& text : args.styles) {
    Result<pipeline::StylePair> pair = parseStyleFlag(text);
    if (!pair.ok()) return pair.status();
    s.edits.styles.push_back(std::move(pair).value());
  }
  return s;
}

// A resumed search is the same search: its settings are the checkpoint's "problem" (the project
// JSON this command wrote there; checkpoints from before carry the same fields flat).
Result<pipeline::ProjectSettings> checkpointSettings(const nlohmann::json& checkpoint,
                                                     const std::string& name) {
  try {
    const nlohmann::json& problem = checkpoint.at("problem");
    if (problem.contains("format")) {
      Result<Project> project = parseProject(problem.dump(), {}, name + ": problem");
      if (!project.ok()) return project.status();
      return pipeline::ProjectSettings(project.value());
    }
    nlohmann::json old = problem.contains("project") ? problem.at("project")
                                                     : nlohmann::json{{"format", "sinew.project"},
                                                                      {"version", kProjectVersion}};
    for (const char* key :
         {"rig", "clip", "target", "animation", "harmonics", "window_s", "terrain", "pushes"})
      old[key] = problem.at(key);
    old["body"] = {{"masses", problem.at("masses")},
                   {"fixed", problem.at("fixed")},
                   {"hinge_limits", problem.at("hinge_limits")}};
    old["search"] = {{"no_prior", problem.at("no_prior")}};
    Result<Project> project = parseProject(old.dump(), {}, name + ": problem");
    if (!project.ok()) return project.status();
    return pipeline::ProjectSettings(project.value());
  } catch (const nlohmann::json::exception& e) {
    return Status::error(name + ": not a checkpoint of sinew evolve: " + e.what());
  }
}

// The session: a new one, or the checkpoint's continued with a new budget and weights.
Result<std::unique_ptr<search::Session>> makeSession(const EvolveArgs& args,
                                                     const pipeline::ProjectSettings& chosen,
                                                     search::Problem problem,
                                                     const nlohmann::json& checkpoint) {
  if (args.resume.empty()) {
    if (args.generations == 0 && args.minutes == 0.0)
      return Status::error("--generations 0 with no --minutes gives the search no budget");
    search::EvolveSettings settings = pipeline::evolveSettings(chosen.search);
    settings.minutes = args.minutes;
    settings.generations = args.generations >= 0 ? args.generations  // -1: not given
                                                 : (args.minutes > 0.0 ? 0 : 40);
    settings.threads = args.threads;
    if (args.sigma > 0.0) settings.initial_sigma = args.sigma;
    return search::Session::create(std::move(problem), settings);
  }
  Result<std::unique_ptr<search::Session>> made =
      search::Session::resume(std::move(problem), checkpoint);
  if (!made.ok()) return Status::error(args.resume + ": " + made.message());
  search::Session& session = *made.value();
  if (args.generations > 0 || args.minutes > 0.0) {
    if (Status budget = session.setBudget(std::max(0, args.generations), args.minutes);
        !budget.ok())
      return budget;
  }
  if (!args.weights.empty() || args.has("--style-weight"))
    session.setWeights(chosen.search.weights);  // from the next generation
  if (session.finished())
    return Status::error(args.resume + ": the search's budget (" +
                         std::to_string(session.settings().generations) + " generations, " +
                         std::to_string(session.settings().minutes) +
                         " minutes) is spent: give --generations or --minutes (totals) to go on");
  return made;
}

void printStart(const search::Session& session, const std::string& what, const EvolveArgs& args,
                const pipeline::ProjectSettings& chosen, const distributed::Ranks& ranks) {
  const search::EvolveSettings& used = session.settings();
  const int threads = used.threads > 0 ? used.threads : search::hardwareThreads();
  char where[48] = "";
  if (ranks.size > 1) std::snprintf(where, sizeof where, "%d MPI ranks x ", ranks.size);
  char budget[64];
  if (used.minutes > 0.0 && used.generations > 0)
    std::snprintf(budget, sizeof budget, "%d generations or %.1f min", used.generations,
                  used.minutes);
  else if (used.minutes > 0.0)
    std::snprintf(budget, sizeof budget, "%.1f min", used.minutes);
  else
    std::snprintf(budget, sizeof budget, "%d generations", used.generations);
  char trials[96] = "";
  if (!session.problem().trial_pushes.empty())
    std::snprintf(trials, sizeof trials, ", %zu runs a point (%zu pushed %.0f N s)",
                  session.problem().trial_pushes.size() + 1, session.problem().trial_pushes.size(),
                  glm::length(session.problem().trial_pushes.front().impulse_ns));
  if (chosen.search.robust_push_m_s > 0.0) {
    const size_t used_chars = std::strlen(trials);
    std::snprintf(trials + used_chars, sizeof trials - used_chars,
                  ", 4 pushes of %.0f N s in every run",
                  chosen.search.robust_push_m_s * session.problem().plan.total_mass_kg);
  }
  std::printf(
      "evolving %s: %d coordinates (%s), %s, population %d, %s, %s%d thread%s, window %.1f "
      "s%s, seed %llu%s\n",
      what.c_str(), session.problem().layout.size(),
      used.optimizer == search::OptimizerKind::kCmaes ? "CMA-ES" : "genetic algorithm",
      chosen.search.no_prior ? "no prior (random start, generic ranges)" : "seeded from the DFT",
      session.population(), budget, where, threads, threads == 1 ? "" : "s",
      session.problem().simulation.seconds, trials, static_cast<unsigned long long>(used.seed),
      args.resume.empty() ? "" : (", resumed from " + args.resume).c_str());
  if (ranks.size > 1)  // mpirun ends every rank when one dies or on Ctrl-C: say what survives
    std::printf(
        "checkpoint after every generation: %s/checkpoint.json (sinew evolve --resume "
        "it, on one machine or under mpirun)\n",
        args.out.c_str());
  std::fflush(stdout);
}

// Runs the session to its end (or Ctrl-C), a line per generation, calling `each_generation`
// after each line. Returns whether interrupted.
bool runWithProgress(search::Session& session, const std::function<void()>& each_generation) {
  const search::EvolveSettings& used = session.settings();
  g_interrupted = false;
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  session.start();
  int printed = static_cast<int>(session.snapshot()->history.size());
  bool interrupted = false;
  std::string start;  // the start the search is on, as last printed
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (g_interrupted && !interrupted) {
      interrupted = true;
      std::printf("\ninterrupted: stopping, keeping the best so far\n");
      session.stop();
    }
    const auto snap = session.snapshot();
    for (; printed < static_cast<int>(snap->history.size()); ++printed) {
      const search::GenerationRecord& r = snap->history[static_cast<size_t>(printed)];
      const double rate = r.wall_s > 0.0 ? static_cast<double>(r.evaluations) / r.wall_s : 0.0;
      double left_s = -1.0;
      if (used.generations > 0)
        left_s =
            r.wall_s / std::max(1, r.generation) * std::max(0, used.generations - r.generation);
      else if (used.minutes > 0.0)
        left_s = std::max(0.0, used.minutes * 60.0 - r.wall_s);
      char left[64] = "";
      if (left_s >= 0.0) std::snprintf(left, sizeof left, ", %.0f s left", left_s);
      const std::string diverged =
          r.diverged == 0 ? ""
          : r.scored == 0 ? "  (the whole generation diverged: " + std::to_string(r.diverged) + ")"
                          : "  (" + std::to_string(r.diverged) + " diverged)";
      if (snap->best_point.empty())
        std::printf("gen %3d  best none yet: no evaluation scored%s  %.1f eval/s%s\n", r.generation,
                    diverged.c_str(), rate, left);
      else
        std::printf("gen %3d  best %s  mean %.2f  %.1f eval/s%s%s\n", r.generation,
                    termsLine(snap->best_terms).c_str(), r.total.mean, rate, left,
                    diverged.c_str());
      std::fflush(stdout);
      each_generation();
    }
    if (snap->start != start) {  // the search moved to another start, or kept one
      start = snap->start;
      std::printf("search: %s\n", start.c_str());
    }
    if (search::ended(snap->state)) break;
  }
  session.wait();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  return interrupted;
}

// The best run's style against the styles the search was given: printed, and style.json in `out`.
Status reportStyle(const search::Problem& problem, const pipeline::BestReplay& best,
                   const pipeline::MotionEdits& edits, const std::filesystem::path& out) {
  if (edits.styles.empty()) return Status();
  Result<pipeline::RunStyleReport> report = pipeline::measureRunStyle(
      problem.skeleton, problem.seed, best.run.motion, best.stride_s, best.stride_s, edits);
  if (!report.ok()) return report.status();
  for (const std::string& line : report.value().lines()) std::printf("style %s\n", line.c_str());
  return writeFileAtomically(out / "style.json", report.value().json().dump(2) + "\n");
}

// The best run as a seamless loop with planted feet (pipeline::writeLoopFiles), and a line
// saying what it is. A run that gives no loop (it fell in its first strides) is said on stderr,
// not a failure of the search. Returns whether the loop was written.
Result<bool> writeLoop(const search::Problem& problem, const pipeline::BestReplay& best,
                       const EvolveArgs& args, const pipeline::MotionEdits& edits,
                       const motion::MotionAsset& rig) {
  if (args.loop_strides == 0) return false;
  pipeline::LoopSettings settings;
  settings.strides = args.loop_strides;
  settings.in_place = args.in_place;
  Result<pipeline::LoopFiles> loop =
      pipeline::writeLoopFiles(problem, best, edits, rig, settings, args.out);
  if (!loop.ok() && loop.message().rfind("loop: ", 0) == 0) {
    std::fprintf(stderr, "sinew: warning: no best_loop: %s\n", loop.message().c_str());
    return false;
  }
  if (!loop.ok()) return loop.status();
  const pipeline::PhysicalLoop& l = loop.value().loop;
  for (const std::string& line : loop.value().style.lines())
    std::printf("loop style %s\n", line.c_str());
  std::printf(
      "loop: %d strides of %.3f s from %.2f s of the run, %d frames; seam %.2f deg %.2f cm (one "
      "frame moves up to %.2f deg %.2f cm); foot slide %.2f -> %.2f cm mean per contact (%zu "
      "contacts, plant up to %.1f deg); %.1f deg RMS from the run\n",
      l.strides, l.period_s, l.run_start_s, l.clip.frame_count, l.seam_deg, l.seam_cm,
      l.step_deg_max, l.step_cm_max, l.slideBeforeMeanCm(), l.slideAfterMeanCm(), l.contacts.size(),
      l.correction_deg_max, l.deviation_deg_rms);
  return true;
}

// Evaluation threads of this process: the flag, or every core (shared among the ranks mpirun
// started on this machine).
int threadsOf(const EvolveArgs& args, const distributed::Ranks& ranks) {
  if (args.threads > 0 || ranks.size == 1) return args.threads;
  return std::max(1, search::hardwareThreads() / std::min(ranks.size, distributed::localRanks()));
}

}  // namespace

int runEvolveOn(const EvolveArgs& args, const distributed::Ranks& ranks) {
  // Settings: the checkpoint's (a resumed search), or the project's with the flags over them.
  nlohmann::json checkpoint;
  Result<pipeline::ProjectSettings> chosen = Status::error("no settings");
  if (!args.resume.empty()) {
    Result<std::string> text = readFile(args.resume);
    if (!text.ok()) return fail(text.message());
    try {
      checkpoint = nlohmann::json::parse(text.value());
    } catch (const nlohmann::json::exception& e) {
      return fail(args.resume + ": not a checkpoint of sinew evolve: " + e.what());
    }
    chosen = checkpointSettings(checkpoint, args.resume);
    if (chosen.ok()) {
      if (Status w = applyWeightFlags(args.weights, chosen.value().search.weights); !w.ok())
        return fail(w.message());
      if (args.has("--style-weight")) chosen.value().search.weights.style = args.style_weight;
      applyRobustnessFlags(args, chosen.value().search);
    }
  } else {
    chosen = chosenSettings(args);
  }
  if (!chosen.ok()) return fail(chosen.message());
  const pipeline::ProjectSettings& settings = chosen.value();

  // The problem: the engine's one path from settings to a search.
  Result<LoadedRig> loaded = loadRig(settings, args.import);
  if (!loaded.ok()) return fail(loaded.message());
  const LoadedRig& rig = loaded.value();
  Result<pipeline::SearchSetup> setup =
      pipeline::prepareSearch(rig.asset.skeleton, rig.clip(), settings);
  if (!setup.ok()) return fail(setup.message());
#if SINEW_HAVE_MPI
  if (ranks.rank > 0)
    return distributed::serve(ranks, setup.value().problem, threadsOf(args, ranks));
#endif
  EvolveArgs used = args;
  used.threads = threadsOf(args, ranks);
  Result<std::unique_ptr<search::Session>> made =
      makeSession(used, settings, std::move(setup.value().problem), checkpoint);
  if (!made.ok()) return fail(made.message());
  search::Session& session = *made.value();
  distributed::Traffic traffic;
#if SINEW_HAVE_MPI
  if (ranks.size > 1) {
    if (Status s = distributed::handshake(ranks, session.problem()); !s.ok())
      return fail(s.message());
    session.setEvaluator(distributed::coordinator(ranks, &traffic));
  }
#endif
  printStart(session, setup.value().what, used, settings, ranks);
  const std::filesystem::path out(args.out);
  const nlohmann::json problem_json = nlohmann::json::parse(settingsJson(settings));
  bool warned = false;
  const bool interrupted = runWithProgress(session, [&] {
    if (Status s = pipeline::writeCheckpoint(session, problem_json, out); !s.ok() && !warned) {
      std::fprintf(stderr, "sinew: warning: %s (the search goes on)\n", s.message().c_str());
      warned = true;
    }
  });
#if SINEW_HAVE_MPI
  if (ranks.size > 1) {
    distributed::stopWorkers(ranks);
    std::printf("%s\n", traffic.line(ranks.size).c_str());
  }
#endif

  const auto snap = session.snapshot();
  Result<bool> wrote = pipeline::writeSearchResults(session, rig.asset, problem_json,
                                                    resultsMeta(settings, session.settings()), out);
  if (!wrote.ok()) return fail(wrote.message());
  if (!snap->failure.empty()) return fail(args.out + ": " + snap->failure);
  if (!wrote.value()) {
    std::printf("no generation finished: wrote %s and %s only\n",
                (out / "checkpoint.json").string().c_str(), (out / "history.csv").string().c_str());
    return interrupted ? 130 : 0;
  }
  std::printf("best after %d generations (%lld evaluations): %s\n", snap->generation,
              snap->evaluations, termsLine(snap->best_terms).c_str());
  const pipeline::BestReplay best = pipeline::replayBest(session.problem(), snap->best_point);
  printJointLines(physics::jointFigures(best.run), pipeline::trackedName(settings));
  if (Status s = reportStyle(session.problem(), best, settings.edits, out); !s.ok())
    return fail(s.message());
  Result<bool> looped = writeLoop(session.problem(), best, args, settings.edits, rig.asset);
  if (!looped.ok()) return fail(looped.message());
  std::printf("wrote %s: best.bvh, best.glb, best.json, history.csv, checkpoint.json%s%s\n",
              args.out.c_str(), settings.edits.styles.empty() ? "" : ", style.json",
              looped.value() ? ", best_loop.bvh, best_loop.glb, loop.json" : "");
  return interrupted ? 130 : 0;
}

namespace {

// Under mpirun every rank runs this command: one search, rank 0 driving it (cli/distributed.h).
int runEvolve(const EvolveArgs& args) {
  const int launched = distributed::launchedRanks();
  if (launched == 1) return args.batch.empty() ? runEvolveOn(args, {}) : runBatch(args, {});
#if SINEW_HAVE_MPI
  Result<distributed::Ranks> ranks = distributed::start();
  if (!ranks.ok()) return fail(ranks.message());
  const int code =
      args.batch.empty() ? runEvolveOn(args, ranks.value()) : runBatch(args, ranks.value());
  if (code != 0 && code != 130) distributed::abort(code);  // no rank may wait for this one
  distributed::finish();
  return code;
#else
  return fail("evolve: started as one of " + std::to_string(launched) +
              " MPI ranks, but this sinew was built without MPI (install libopenmpi-dev and "
              "rebuild), so every rank would run the whole search alone");
#endif
}

// The flags that shape the search a checkpoint continues (the rig and its import, the body, the
// window, the optimizer; not the robustness, which may harden a found gait), given on this
// command line: "--window comes", "--window and --seed come", or "" when none is. A resumed
// search takes them all from its checkpoint, so giving one is an error rather than a flag
// silently ignored.
std::string checkpointFlagsGiven(const CLI::App& command) {
  static const char* const kFlags[] = {
      "project", "--rig", "--clip", "--target", "--animation", "--style", "--population",
      "--optimizer", "--window", "--no-prior", "--seed", "--harmonics", "--terrain", "--sigma",
      "--restart-after", "--start-generations", "--push", "--units", "--up", "--fps",
      "--keep-glitches", "--mass", "--fixed", "--hinge-limits"};
  std::vector<std::string> given;
  for (const char* flag : kFlags)
    if (command.count(flag) > 0) given.emplace_back(flag[0] == '-' ? flag : "a project");
  std::string list;
  for (size_t i = 0; i < given.size(); ++i)
    list += (i == 0 ? "" : (i + 1 == given.size() ? " and " : ", ")) + given[i];
  return given.empty() ? "" : list + (given.size() == 1 ? " comes" : " come");
}

}  // namespace

void addEvolveCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<EvolveArgs>();
  CLI::App* command = app.add_subcommand(
      "evolve",
      "Evolve the rig's Fourier controller (seeded from the clip's DFT) until the "
      "simulated motion keeps the style without falling");
  command->add_option("project", args->project,
                      "A project file (.sinew.json: rig, clip, window, terrain...); default: the "
                      "bundled default project, the walk the editor opens");
  command->add_option("--rig", args->rig, "The rig (.bvh, .glb, .gltf), instead of a project");
  command->add_option("--clip", args->clip, "The motion (same skeleton); default: the rig's own");
  command->add_option(
      "--target", args->target_path,
      "Start from these coefficients (.json from sinew style) instead of the clip's");
  command->add_option("--animation", args->animation, "Which glTF animation (by name)");
  command
      ->add_option("--population", args->population,
                   "Individuals per generation (default: "
                   "CMA-ES 4 + 3 ln n, GA 32)")
      ->check(wholeNumber(10000));
  command->add_option("--generations", args->generations, "Generations (default 40)")
      ->check(wholeNumber(1000000));
  command->add_option("--minutes", args->minutes, "Wall-clock budget, minutes")
      ->check(CLI::Range(0.0, 100000.0));
  command->add_option("--window", args->window, "Seconds simulated per evaluation (default 10)")
      ->check(CLI::Range(0.5, 600.0));
  command->add_option("--optimizer", args->optimizer, "cmaes (default) or ga")
      ->check(CLI::IsMember({"cmaes", "ga"}));
  command->add_flag("--no-prior", args->no_prior,
                    "Random start within generic ranges (the baseline the DFT prior is measured "
                    "against)");
  command->add_option("--seed", args->seed, "Random seed (same seed, same result)")
      ->check(wholeNumber());
  command->add_option("--threads", args->threads, "Evaluation threads (default: every core)")
      ->check(CLI::Range(0, 1024));
  command->add_option("--harmonics", args->harmonics, "Harmonics per joint of the seed")
      ->check(CLI::Range(1, 64));
  command->add_option("--terrain", args->terrain,
                      "flat | slope:DEG | steps:HEIGHT,DEPTH | rough:AMPLITUDE,SEED");
  command
      ->add_option("--sigma", args->sigma,
                   "Initial step size in normalised units (default 0.02; the GA's mutation "
                   "scale)")
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option("--trials", args->trials,
                   "Robustness: runs per point, the nominal one and TRIALS - 1 pushed to the "
                   "left, right, back and forward in turn; the cost is their mean (default 1)")
      ->check(wholeNumber())
      ->check(CLI::Range(1, search::kMaxTrials));
  command
      ->add_option("--trial-push", args->trial_push,
                   "The trials' push per kg of body, m/s (default 0.3: 21 N s on 70 kg)")
      ->check(CLI::Range(0.001, 10.0));
  command
      ->add_option("--robust-push", args->robust_push,
                   "Robustness at no extra cost: every run takes 4 pushes of M_S per kg of body "
                   "(forward, left, back, right of the clip's travel at 15/35/55/75% of the "
                   "window); 0.3 is 18 N s on 60 kg (default 0: none)")
      ->check(CLI::Range(0.0, 10.0));
  command
      ->add_option("--restart-after", args->restart_after,
                   "CMA-ES: start again from the DFT prior (the best kept) after G generations "
                   "without a better best (default 0: never)")
      ->check(wholeNumber())
      ->check(CLI::Range(0, 100000));
  command
      ->add_option("--start-generations", args->start_generations,
                   "Try the starts (the stance yield off, then at half) for G generations each; "
                   "a start whose best walks the whole window is kept at once, else the best "
                   "goes on (default 50; 0: the first start alone)")
      ->check(wholeNumber())
      ->check(CLI::Range(0, 100000));
  command->add_option("--push", args->pushes,
                      "Robustness: every evaluation takes this push, TIME,X,Y,Z[,LINK] (seconds, "
                      "N s); repeatable");
  command
      ->add_option("--weights", args->weights,
                   "Fitness weights TERM=VALUE (fall, tracking, speed, heading, placement, "
                   "upright, energy, style); repeatable")
      ->delimiter(',');
  command
      ->add_option("--style-weight", args->style_weight,
                   "Weight of the style term: the run's harmonic spectrum against the target's, "
                   "per joint group, per radian (default 0: not measured)")
      ->check(CLI::Range(0.0, 1000.0));
  command->add_option(
      "--style", args->styles,
      "Evolve toward the motion with a style: NEUTRAL,STYLED[:WEIGHT] (clips of the "
      "rig's skeleton; weight in [-1, 2], default 1, 0 = the original); repeatable, "
      "added to the project's styles");
  command
      ->add_option("--loop-strides", args->loop_strides,
                   "Whole strides in best_loop.bvh/.glb, the best run as a seamless loop with "
                   "planted feet (default 2; 0: no loop)")
      ->check(wholeNumber())
      ->check(CLI::Range(0, 16));
  command->add_flag("--in-place", args->in_place,
                    "The loop's root stays in place (its horizontal travel removed)");
  command->add_option("--resume", args->resume, "Continue from a checkpoint.json");
  command->add_option("--batch", args->batch,
                      "Evolve every clip of a folder (.bvh, .glb, .gltf) or of a list file (a path "
                      "a line), each as its own rig (or as --clip of the one --rig), into "
                      "OUT/<name>/, with OUT/summary.csv and summary.json; under mpirun the ranks "
                      "share the clips");
  command
      ->add_option("--batch-index", args->batch_index,
                   "Only the batch's clip I (0-based), as one task of a scheduler's job array")
      ->check(CLI::Range(0, 1000000));
  command->add_option("--out", args->out, "Output folder")->required();
  args->import.addTo(*command);
  args->body.addTo(*command);
  command->callback([args, command, &exit_code]() {
    for (const char* flag :
         {"--harmonics", "--terrain", "--window", "--population", "--optimizer", "--seed",
          "--no-prior", "--trials", "--trial-push", "--robust-push", "--restart-after",
          "--start-generations", "--style-weight"})
      if (command->count(flag) > 0) args->given.emplace_back(flag);
    const std::string fixed_by_checkpoint = checkpointFlagsGiven(*command);
    if (!args->project.empty() && !args->rig.empty())
      exit_code = fail("give a project or --rig, not both");
    else if (!args->resume.empty() && !fixed_by_checkpoint.empty())
      exit_code = fail("--resume continues the search as it was: " + fixed_by_checkpoint +
                       " from the checkpoint (--minutes, --generations, --weights, "
                       "--style-weight, --threads, --trials, --trial-push and --robust-push may "
                       "change; start a new search to change the rest)");
    else if (!args->batch.empty() && (!args->project.empty() || !args->resume.empty() ||
                                      !args->clip.empty() || !args->target_path.empty()))
      exit_code = fail(
          "--batch takes its clips from the list or folder (each its own rig, or with --rig one "
          "rig for all): not with a project, --clip, --target or --resume");
    else if (args->batch.empty() && args->batch_index >= 0)
      exit_code = fail("--batch-index picks a clip of --batch: give --batch too");
    else if (!args->target_path.empty() && !args->styles.empty())
      exit_code = fail(
          "--style edits the clip's harmonic model; a --target file is tracked as it is (apply "
          "the style with sinew style -o X.json, or drop --target)");
    else
      exit_code = runEvolve(*args);
  });
}

}  // namespace sinew::app
