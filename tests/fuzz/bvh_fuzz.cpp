// libFuzzer target for the BVH reader: any bytes must give a clean result or a message, never a
// crash, hang or sanitizer report. Whatever it accepts must also survive write -> read with the
// same hierarchy.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sinew/motion/bvh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sinew::motion;
  using sinew::Result;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Result<MotionAsset> asset = readBvh(text, "fuzz.bvh");
  if (!asset.ok()) {
    if (asset.message().rfind("fuzz.bvh:", 0) != 0) __builtin_trap();  // must name the file
    return 0;
  }
  const MotionAsset& read = asset.value();
  const std::string written = writeBvh(read.skeleton, read.clips[0], read.skeleton.source);
  Result<MotionAsset> again = readBvh(written, "written.bvh");
  if (!again.ok() || again.value().skeleton.names != read.skeleton.names ||
      again.value().skeleton.parents != read.skeleton.parents ||
      again.value().clips[0].frame_count != read.clips[0].frame_count) {
    __builtin_trap();
  }
  return 0;
}
