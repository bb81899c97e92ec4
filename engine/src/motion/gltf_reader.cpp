// Placeholder while the glTF importer/exporter is being written; replaced in the same change.
#include "sinew/motion/gltf.h"
namespace sinew::motion {
Result<MotionAsset> loadGltf(const std::filesystem::path& path, const ImportOptions&) {
  return Status::error(path.string() + ": glTF import is not built yet");
}
}  // namespace sinew::motion
