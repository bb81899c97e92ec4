// The physical loop of a search's best, as files: what `sinew evolve` and the editor write.
#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/motion/asset.h"
#include "sinew/pipeline/physical_loop.h"
#include "sinew/pipeline/run_style.h"

namespace sinew::pipeline {

BestReplay replayBest(const search::Problem& problem, std::span<const double> point) {
  BestReplay best;
  best.run = search::evaluate(problem, point, nullptr, true).report;
  best.stride_s = problem.layout.decodeTarget(point).period();
  return best;
}

Result<LoopFiles> writeLoopFiles(const search::Problem& problem, const BestReplay& best,
                                 const MotionEdits& edits, const motion::MotionAsset& rig,
                                 const LoopSettings& settings, const std::filesystem::path& dir) {
  Result<PhysicalLoop> loop = physicalLoop(problem.skeleton, best.run, best.stride_s, settings);
  if (!loop.ok()) return loop.status();
  LoopFiles files{std::move(loop).value(), {}};
  nlohmann::json json = files.loop.json();
  json["in_place"] = settings.in_place;
  if (!edits.styles.empty()) {
    Result<RunStyleReport> style = measureRunStyle(problem.skeleton, problem.seed,
                                                   files.loop.played(2), 0.0,
                                                   files.loop.period_s, edits);
    if (!style.ok()) return style.status();
    files.style = std::move(style).value();
    json["style"] = files.style.json();
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status::error(dir.string() + ": cannot create the folder: " + ec.message());
  for (const char* name : {"best_loop.bvh", "best_loop.glb"})
    if (Status s = motion::exportMotion(dir / name, rig, files.loop.clip); !s.ok()) return s;
  if (Status s = writeFileAtomically(dir / "loop.json", json.dump(2) + "\n"); !s.ok()) return s;
  return files;
}

}  // namespace sinew::pipeline
