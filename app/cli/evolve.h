// sinew evolve's command line and its runs: one search (evolve_command.cpp) or a batch of clips
// (evolve_batch.cpp), on one process or over MPI ranks (cli/distributed.h).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/controller_file.h"
#include "cli/distributed.h"

namespace sinew::app {

// The command line as given; what it means for the search is a pipeline::ProjectSettings
// (chosenSettings), the same struct a project file and the editor fill.
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
  int trials = 1;
  double trial_push = 0.3;
  double robust_push = 0.0;
  int restart_after = 0;
  int start_generations = 50;
  std::string resume;
  std::string out;
  std::string batch;     // --batch LIST_OR_FOLDER: many clips, one search each
  int batch_index = -1;  // --batch-index I: only the batch's clip I (a job array's task)
  std::string terrain = "flat";
  std::vector<std::string> pushes;
  std::vector<std::string> weights;
  double style_weight = 0.0;        // --style-weight: the style term's weight
  std::vector<std::string> styles;  // --style NEUTRAL,STYLED[:WEIGHT]
  int loop_strides = 2;             // 0: no loop
  bool in_place = false;
  ImportFlags import;
  BodyFlags body;
  std::vector<std::string> given;  // the flags given ("--harmonics", ...)
  bool has(const char* flag) const {
    return std::find(given.begin(), given.end(), flag) != given.end();
  }
};

// One search as the flags say, on this process (ranks.size == 1) or as rank ranks.rank of a
// distributed one. Returns the exit code (0, 1 for bad input or a failed write, 130 when
// interrupted).
int runEvolveOn(const EvolveArgs& args, const distributed::Ranks& ranks);

// `--batch`: every clip of the list or folder evolved in turn into OUT/<name>/, or handed out to
// the ranks under mpirun, with OUT/summary.csv and OUT/summary.json. Returns the exit code.
int runBatch(const EvolveArgs& args, const distributed::Ranks& ranks);

}  // namespace sinew::app
