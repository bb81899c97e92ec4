// libFuzzer target for the coefficient files: a spectral target (.json from `sinew style`) and
// an evolved controller (best.json), both read onto the bundled walk's skeleton. Any input must
// give a clean result or a message naming the file; whatever is accepted is a valid target that
// writes back and reads back to the same channels.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "sinew/motion/asset.h"
#include "sinew/search/controller_io.h"
#include "sinew/spectral/target_io.h"

namespace {

const sinew::motion::Skeleton& walkSkeleton() {
  // Read once, on the first input: every input is matched against this rig. Never freed, so no
  // destructor runs while libFuzzer exits from inside an input.
  static const sinew::motion::Skeleton* skeleton = [] {
    auto asset = sinew::motion::importMotion(SINEW_SOURCE_DIR "/assets/biped_walk.bvh");
    if (!asset.ok()) std::abort();
    return new sinew::motion::Skeleton(asset.value().skeleton);
  }();
  return *skeleton;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sinew;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const motion::Skeleton& skeleton = walkSkeleton();
  Result<spectral::TargetMotion> target = spectral::targetFromJson(text, skeleton, "fuzz.json");
  if (!target.ok() && target.message().rfind("fuzz.json", 0) != 0) __builtin_trap();
  if (target.ok()) {
    if (!target.value().validate(skeleton).ok()) __builtin_trap();
    const std::string written = spectral::targetToJson(target.value(), skeleton);
    Result<spectral::TargetMotion> again =
        spectral::targetFromJson(written, skeleton, "again.json");
    if (!again.ok() || again.value().channels.size() != target.value().channels.size())
      __builtin_trap();
  }
  Result<search::ControllerFile> controller =
      search::controllerFromJson(text, skeleton, "best.json");
  if (!controller.ok() && controller.message().rfind("best.json", 0) != 0) __builtin_trap();
  if (controller.ok() && !controller.value().target.validate(skeleton).ok()) __builtin_trap();
  return 0;
}
