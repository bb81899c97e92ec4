// Placeholder while the glTF importer/exporter is being written; replaced in the same change.
#include "sinew/motion/gltf.h"
namespace sinew::motion {
Status saveGltf(const std::filesystem::path& path, const MotionAsset&, const Clip&) {
  return Status::error(path.string() + ": glTF export is not built yet");
}
}  // namespace sinew::motion
