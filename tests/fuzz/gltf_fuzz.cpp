// libFuzzer target for the glTF reader (.glb and .gltf bytes): any input must give a clean result
// or a message naming the file, never a crash, hang or sanitizer report. Whatever it accepts must
// survive export -> import with the same joints and, for each animation, the same frame count.
#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "sinew/motion/asset.h"
#include "sinew/motion/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sinew::motion;
  // A folder of its own, so a .gltf's external buffer URIs find nothing they could be fed.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("sinew_gltf_fuzz_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  sinew::Result<MotionAsset> asset = readGltf(bytes, dir / "fuzz.glb");
  if (!asset.ok()) {
    if (asset.message().rfind((dir / "fuzz.glb").string() + ":", 0) != 0) __builtin_trap();
    return 0;
  }
  const MotionAsset& read = asset.value();
  if (read.clips.empty()) return 0;
  const std::filesystem::path written = dir / "written.glb";
  if (!exportMotion(written, read, read.clips[0]).ok()) return 0;  // refused: a message, fine
  sinew::Result<MotionAsset> again = importMotion(written);
  if (!again.ok() || again.value().skeleton.names != read.skeleton.names ||
      again.value().clips.empty() ||
      again.value().clips[0].frame_count != read.clips[0].frame_count) {
    __builtin_trap();
  }
  return 0;
}
