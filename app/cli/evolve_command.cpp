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
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/controller_file.h"
#include "sinew/core/file_io.h"
#include "sinew/core/text.h"
#include "sinew/search/session.h"

namespace sinew::app {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void onInterrupt(int) {
  g_interrupted = true;
}

struct EvolveArgs {
  std::string project;
  std::string rig;
  std::string clip;
  std::string target_path;
  std::string animation;
  int population = 0;
  int generations = -1;  // -1: not given
  double minutes = 0.0;
  double window = 10.0;
  std::string optimizer = "cmaes";
  bool no_prior = false;
  std::uint64_t seed = 1;
  int threads = 0;
  int harmonics = 5;
  double sigma = 0.0;
  std::string resume;
  std::string out;
  std::string terrain = "flat";
  std::vector<std::string> pushes;
  std::vector<std::string> weights;
  search::FitnessWeights project_weights;  // the project's; --weights changes them term by term
  std::map<std::string, int> joint_k;      // the project's K per joint, by name
  MotionEdits edits;                       // the project's band gains, styles, secondary motion
  ImportFlags import;
  BodyFlags body;
};

std::string historyCsv(const search::Snapshot& snap) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "generation,evaluations,wall_s,total_best,total_mean,total_worst";
  for (int k = 0; k < search::kFitnessTermCount; ++k) {
    const std::string n = search::fitnessTermName(k);
    csv << ',' << n << "_best," << n << "_mean," << n << "_worst";
  }
  csv << ",best_survived_s,best_distance_m,scored,diverged\n";
  for (const search::GenerationRecord& r : snap.history) {
    csv << r.generation << ',' << r.evaluations << ',' << r.wall_s;
    if (r.scored == 0) {  // nothing scored: empty cells, not inf or nan
      csv << std::string(3 * (search::kFitnessTermCount + 1) + 2, ',');
    } else {
      csv << ',' << r.total.best << ',' << r.total.mean << ',' << r.total.worst;
      for (const search::TermStats& t : r.terms)
        csv << ',' << t.best << ',' << t.mean << ',' << t.worst;
      csv << ',' << r.best_survived_s << ',' << r.best_distance_m;
    }
    csv << ',' << r.scored << ',' << r.diverged << '\n';
  }
  return csv.str();
}

std::string termsLine(const search::FitnessTerms& t) {
  char line[256];
  std::snprintf(line, sizeof line,
                "%.2f (fall %.1f track %.2f speed %.2f heading %.2f steps %.2f upright %.2f "
                "energy %.2f) up %.1f s, %.1f m",
                t.total, t.fall, t.tracking, t.speed, t.heading, t.placement, t.upright, t.energy,
                t.survived_s, t.distance_m);
  return t.fell && !t.fall_reason.empty() ? std::string(line) + " (fell: " + t.fall_reason + ")"
                                          : std::string(line);
}

int runEvolve(EvolveArgs args) {
  // A resumed search is the same search: the rig, motion, window and terrain come from the
  // checkpoint's "problem" (what this command wrote there).
  nlohmann::json checkpoint;
  if (!args.resume.empty()) {
    Result<std::string> text = readFile(args.resume);
    if (!text.ok()) return fail(text.message());
    try {
      checkpoint = nlohmann::json::parse(text.value());
      const nlohmann::json& problem = checkpoint.at("problem");
      args.rig = problem.at("rig").get<std::string>();
      args.clip = problem.at("clip").get<std::string>();
      args.target_path = problem.at("target").get<std::string>();
      args.animation = problem.at("animation").get<std::string>();
      args.harmonics = problem.at("harmonics").get<int>();
      args.window = problem.at("window_s").get<double>();
      args.terrain = problem.at("terrain").get<std::string>();
      args.pushes = problem.at("pushes").get<std::vector<std::string>>();
      args.body.masses = problem.at("masses").get<std::vector<std::string>>();
      args.body.fixed = problem.at("fixed").get<std::vector<std::string>>();
      args.body.hinge_limits = problem.at("hinge_limits").get<std::vector<std::string>>();
      args.no_prior = problem.at("no_prior").get<bool>();
      if (problem.contains("project")) {
        Result<Project> fragment =
            parseProject(problem.at("project").dump(), {}, args.resume + ": problem.project");
        if (!fragment.ok()) return fail(fragment.message());
        args.joint_k = fragment.value().joint_k;
        args.edits = fragment.value().edits;
      }
    } catch (const nlohmann::json::exception& e) {
      return fail(args.resume + ": not a checkpoint of sinew evolve: " + e.what());
    }
  }
  Result<LoadedRig> loaded = loadRigAndTarget(args.rig, args.clip, args.target_path, args.animation,
                                              args.harmonics, args.import, args.body, args.joint_k);
  if (!loaded.ok()) return fail(loaded.message());
  LoadedRig& rig = loaded.value();
  if (!args.edits.empty() && args.target_path.empty()) {
    // The project's edits of the model, as the editor applies them.
    std::vector<spectral::StyleVector> measured;
    measured.reserve(args.edits.styles.size());
    for (const StylePair& pair : args.edits.styles) {
      Result<spectral::StyleVector> style = measureStylePair(pair, rig.asset.skeleton);
      if (!style.ok()) return fail("style '" + pair.label + "': " + style.message());
      measured.push_back(std::move(style).value());
    }
    std::vector<const spectral::StyleVector*> styles;
    for (const spectral::StyleVector& style : measured) styles.push_back(&style);
    Result<spectral::TargetMotion> edited =
        applyMotionEdits(rig.target, rig.asset.skeleton, args.edits, styles);
    if (!edited.ok()) return fail(edited.message());
    rig.target = std::move(edited).value();
    rig.what += " with the project's edits";
  }

  Result<physics::SimulationSettings> simulation =
      simulationSettings(args.window, args.terrain, args.pushes);
  if (!simulation.ok()) return fail(simulation.message());
  search::FitnessWeights weights = args.project_weights;
  for (const std::string& text : args.weights) {
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
      return fail("--weights '" + text +
                  "': expected TERM=VALUE >= 0, TERM one of fall, tracking, "
                  "speed, heading, placement, upright, energy");
    search::fitnessWeight(weights, term) = value;
  }
  search::GenomeSettings genome;
  genome.no_prior = args.no_prior;
  Result<search::Problem> problem = search::Problem::create(
      rig.plan, rig.asset.skeleton, rig.target, genome, simulation.value(), weights);
  if (!problem.ok()) return fail(problem.message());

  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (ec) return fail(args.out + ": cannot create the output folder: " + ec.message());
  const std::filesystem::path out(args.out);

  search::EvolveSettings settings;
  settings.optimizer = args.optimizer;
  settings.population = args.population;
  settings.generations = args.generations;
  settings.minutes = args.minutes;
  if (args.generations == 0 && args.minutes == 0.0)
    return fail("--generations 0 with no --minutes gives the search no budget");
  if (args.generations < 0) settings.generations = args.minutes > 0.0 ? 0 : 40;  // not given
  if (!args.resume.empty() && (args.population > 0 || args.optimizer != "cmaes"))
    return fail(
        "--resume continues the search as it was: --population and --optimizer come "
        "from the checkpoint");
  settings.threads = args.threads;
  settings.seed = args.seed;
  if (args.sigma > 0.0) settings.initial_sigma = args.sigma;
  Result<std::unique_ptr<search::Session>> made = Status::error("no session");
  if (!args.resume.empty()) {
    made = search::Session::resume(std::move(problem).value(), checkpoint);
    if (!made.ok()) return fail(args.resume + ": " + made.message());
    if (args.generations > 0 || args.minutes > 0.0) {
      Status budget = made.value()->setBudget(std::max(0, args.generations), args.minutes);
      if (!budget.ok()) return fail(budget.message());
    }
    if (!args.weights.empty()) made.value()->setWeights(weights);  // from the next generation
    if (made.value()->finished())
      return fail(args.resume + ": the search's budget (" +
                  std::to_string(made.value()->settings().generations) + " generations, " +
                  std::to_string(made.value()->settings().minutes) +
                  " minutes) is spent: give --generations or --minutes (totals) to go on");
  } else {
    made = search::Session::create(std::move(problem).value(), settings);
    if (!made.ok()) return fail(made.message());
  }
  search::Session& session = *made.value();
  const search::EvolveSettings& used = session.settings();
  const int threads = used.threads > 0 ? used.threads : search::hardwareThreads();
  char budget[64];
  if (used.minutes > 0.0 && used.generations > 0)
    std::snprintf(budget, sizeof budget, "%d generations or %.1f min", used.generations,
                  used.minutes);
  else if (used.minutes > 0.0)
    std::snprintf(budget, sizeof budget, "%.1f min", used.minutes);
  else
    std::snprintf(budget, sizeof budget, "%d generations", used.generations);
  std::printf(
      "evolving %s: %d coordinates (%s), %s, population %d, %s, %d thread%s, window %.1f "
      "s, seed %llu%s\n",
      rig.what.c_str(), session.problem().layout.size(),
      used.optimizer == "cmaes" ? "CMA-ES" : "genetic algorithm",
      args.no_prior ? "no prior (random start, generic ranges)" : "seeded from the DFT",
      session.population(), budget, threads, threads == 1 ? "" : "s",
      session.problem().simulation.seconds, static_cast<unsigned long long>(used.seed),
      args.resume.empty() ? "" : (", resumed from " + args.resume).c_str());
  std::fflush(stdout);

  g_interrupted = false;
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  session.start();
  int printed = static_cast<int>(session.snapshot()->history.size());
  bool interrupted = false;
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
      std::string left;
      if (used.generations > 0) {
        const double per = r.wall_s / std::max(1, r.generation);
        char eta[64];
        std::snprintf(eta, sizeof eta, ", %.0f s left",
                      per * std::max(0, used.generations - r.generation));
        left = eta;
      } else if (used.minutes > 0.0) {
        char eta[64];
        std::snprintf(eta, sizeof eta, ", %.0f s left",
                      std::max(0.0, used.minutes * 60.0 - r.wall_s));
        left = eta;
      }
      const std::string diverged =
          r.diverged == 0 ? ""
          : r.scored == 0 ? "  (the whole generation diverged: " + std::to_string(r.diverged) + ")"
                          : "  (" + std::to_string(r.diverged) + " diverged)";
      if (snap->best_point.empty())
        std::printf("gen %3d  best none yet: no evaluation scored%s  %.1f eval/s%s\n", r.generation,
                    diverged.c_str(), rate, left.c_str());
      else
        std::printf("gen %3d  best %s  mean %.2f  %.1f eval/s%s%s\n", r.generation,
                    termsLine(snap->best_terms).c_str(), r.total.mean, rate, left.c_str(),
                    diverged.c_str());
      std::fflush(stdout);
    }
    if (snap->state == "finished" || snap->state == "stopped") break;
  }
  session.wait();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);

  const auto snap = session.snapshot();
  nlohmann::json saved_state = session.checkpoint();
  // Paths are bytes and JSON text is UTF-8: a Latin-1 file name is stored converted.
  saved_state["problem"] = {{"rig", toUtf8(args.rig)},
                            {"clip", toUtf8(args.clip)},
                            {"target", toUtf8(args.target_path)},
                            {"animation", args.animation},
                            {"harmonics", args.harmonics},
                            {"window_s", args.window},
                            {"terrain", args.terrain},
                            {"no_prior", args.no_prior},
                            {"pushes", args.pushes},
                            {"masses", args.body.masses},
                            {"fixed", args.body.fixed},
                            {"hinge_limits", args.body.hinge_limits}};
  {
    // K per joint and the model's edits, as a project fragment (absolute paths).
    Project fragment;
    fragment.rig = toUtf8(args.rig);
    fragment.harmonics = args.harmonics;
    fragment.joint_k = args.joint_k;
    fragment.edits = args.edits;
    saved_state["problem"]["project"] = nlohmann::json::parse(projectJson(fragment, {}));
  }
  Status saved = writeFileAtomically(
      out / "checkpoint.json",
      saved_state.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  if (!saved.ok()) return fail(saved.message());
  saved = writeFileAtomically(out / "history.csv", historyCsv(*snap));
  if (!saved.ok()) return fail(saved.message());
  if (!snap->failure.empty()) return fail(args.out + ": " + snap->failure);
  if (snap->best_point.empty()) {
    std::printf("no generation finished: wrote %s and %s only\n",
                (out / "checkpoint.json").string().c_str(), (out / "history.csv").string().c_str());
    return interrupted ? 130 : 0;
  }
  // The best controller, replayed once more with recording, written three ways.
  search::ControllerFile meta;
  meta.terrain = args.terrain;
  meta.seed = used.seed;
  meta.optimizer = used.optimizer;
  meta.no_prior = args.no_prior;
  meta.rig = args.rig;
  meta.clip = args.clip.empty() ? args.rig : args.clip;
  saved = search::exportBest(session.problem(), snap->best_point, snap->best_terms, rig.asset, out,
                             meta);
  if (!saved.ok()) return fail(saved.message());
  std::printf("best after %d generations (%lld evaluations): %s\n", snap->generation,
              snap->evaluations, termsLine(snap->best_terms).c_str());
  std::printf("wrote %s: best.bvh, best.glb, best.json, history.csv, checkpoint.json\n",
              args.out.c_str());
  return interrupted ? 130 : 0;
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
      ->check(wholeNumber())
      ->check(CLI::Range(0, 10000));
  command->add_option("--generations", args->generations, "Generations (default 40)")
      ->check(wholeNumber())
      ->check(CLI::Range(0, 1000000));
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
  command->add_option("--push", args->pushes,
                      "Robustness: every evaluation takes this push, TIME,X,Y,Z[,LINK] (seconds, "
                      "N s); repeatable");
  command
      ->add_option("--weights", args->weights,
                   "Fitness weights TERM=VALUE (fall, tracking, speed, heading, placement, "
                   "upright, energy); repeatable")
      ->delimiter(',');
  command->add_option("--resume", args->resume, "Continue from a checkpoint.json");
  command->add_option("--out", args->out, "Output folder")->required();
  args->import.addTo(*command);
  args->body.addTo(*command);
  command->callback([args, command, &exit_code]() {
    if (!args->project.empty() && !args->rig.empty()) {
      exit_code = fail("give a project or --rig, not both");
      return;
    }
    if (args->rig.empty() && args->resume.empty()) {
      const std::string path = args->project.empty() ? kDefaultProject : args->project;
      Result<Project> project = loadProject(path);
      if (!project.ok()) {
        exit_code = fail(project.message());
        return;
      }
      const Project& p = project.value();
      args->rig = p.rig;
      if (args->clip.empty()) args->clip = p.clip;
      if (args->target_path.empty()) args->target_path = p.target;
      if (args->animation.empty()) args->animation = p.animation;
      // The command line's own flags win over the project's.
      if (command->count("--harmonics") == 0) args->harmonics = p.harmonics;
      if (command->count("--terrain") == 0) args->terrain = p.terrain;
      if (command->count("--window") == 0) args->window = p.window_s;
      if (command->count("--population") == 0) args->population = p.search.population;
      if (command->count("--optimizer") == 0) args->optimizer = p.search.optimizer;
      if (command->count("--seed") == 0) args->seed = p.search.seed;
      if (command->count("--no-prior") == 0) args->no_prior = p.search.no_prior;
      args->project_weights = p.search.weights;
      args->joint_k = p.joint_k;
      args->edits = p.edits;
      args->pushes.insert(args->pushes.end(), p.pushes.begin(), p.pushes.end());
      args->body.masses.insert(args->body.masses.end(), p.body.masses.begin(), p.body.masses.end());
      args->body.fixed.insert(args->body.fixed.end(), p.body.fixed.begin(), p.body.fixed.end());
      args->body.hinge_limits.insert(args->body.hinge_limits.end(), p.body.hinge_limits.begin(),
                                     p.body.hinge_limits.end());
    }
    if (!args->resume.empty() && (!args->clip.empty() || !args->target_path.empty()))
      exit_code = fail(
          "--resume continues the search as it was: the rig, clip, window and "
          "terrain come from the checkpoint");
    else
      exit_code = runEvolve(*args);
  });
}

}  // namespace sinew::app
