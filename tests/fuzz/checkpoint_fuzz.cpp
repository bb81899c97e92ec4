// libFuzzer target for search checkpoints (checkpoint.json from `sinew evolve`), resumed onto the
// bundled hopper's search problem: any input must give a session or a message, never a crash, a
// hang, a sanitizer report or an allocation sized by a number in the file.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sinew/motion/asset.h"
#include "sinew/physics/body_plan.h"
#include "sinew/search/session.h"
#include "sinew/spectral/analysis.h"

namespace {

// The problem a checkpoint made by `sinew evolve --rig assets/hopper_hop.bvh --window 0.5`
// belongs to (the corpus holds one). Built once, on the first input, and never freed, so no
// destructor runs while libFuzzer exits from inside an input.
const sinew::search::Problem& hopperProblem() {
  static const sinew::search::Problem* problem = [] {
    using namespace sinew;
    auto asset = motion::importMotion(SINEW_SOURCE_DIR "/assets/hopper_hop.bvh");
    if (!asset.ok()) std::abort();
    auto plan = physics::buildBodyPlan(asset.value().skeleton, &asset.value().clips[0]);
    auto spectrum = spectral::analyze(asset.value().skeleton, asset.value().clips[0]);
    if (!plan.ok() || !spectrum.ok()) std::abort();
    physics::SimulationSettings simulation;
    simulation.seconds = 0.5;
    auto made =
        search::Problem::create(plan.value(), asset.value().skeleton,
                                spectral::targetFromSpectrum(spectrum.value()), {}, simulation);
    if (!made.ok()) std::abort();
    return new search::Problem(std::move(made).value());
  }();
  return *problem;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sinew;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded()) return 0;
  auto session = search::Session::resume(hopperProblem(), json);
  if (!session.ok() && session.message().empty()) __builtin_trap();
  if (session.ok()) {
    // What was resumed checkpoints again without null (JSON's stand-in for nan and inf).
    if (session.value()->checkpoint().dump().find("null") != std::string::npos) __builtin_trap();
  }
  return 0;
}
