#include "sinew/motion/asset.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "sinew/core/file_io.h"
#include "sinew/motion/bvh.h"
#include "sinew/motion/gltf.h"

namespace sinew::motion {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Finds (and unless asked not to, repairs) each clip's glitches, and says so in the warnings.
void handleGlitches(MotionAsset& asset, const ImportOptions& options) {
  asset.glitches.clear();
  asset.glitches_repaired = options.repair_glitches;
  for (Clip& clip : asset.clips) {
    std::vector<Glitch> found = findGlitches(clip, options.glitch);
    if (options.repair_glitches) repairGlitches(clip, found);
    for (const Glitch& glitch : found) {
      asset.warnings.push_back((asset.clips.size() > 1 ? clip.name + ": " : std::string()) + "glitch " +
                               describeGlitch(asset.skeleton, glitch) +
                               (options.repair_glitches ? ", repaired" : ", kept"));
    }
    asset.glitches.push_back(std::move(found));
  }
}

Result<MotionAsset> readAny(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string ext = lowerExtension(path);
  if (ext == ".bvh") {
    Result<std::string> text = readFile(path);
    if (!text.ok()) return text.status();
    Result<MotionAsset> asset = readBvh(text.value(), path.string(), options);
    if (asset.ok()) asset.value().path = path;
    return asset;
  }
  if (ext == ".glb" || ext == ".gltf") return loadGltf(path, options);
  return Status::error(path.string() + ": unknown file type '" + ext +
                       "', expected .bvh, .glb or .gltf");
}

}  // namespace

int MotionAsset::findClip(const std::string& name) const {
  for (size_t n = 0; n < clips.size(); ++n) {
    if (clips[n].name == name) return static_cast<int>(n);
  }
  return -1;
}

Result<MotionAsset> importMotion(const std::filesystem::path& path, const ImportOptions& options) {
  if (options.fps && !(*options.fps > 0.0 && *options.fps <= 1000.0)) {
    return Status::error("fps must be in (0, 1000], got " + std::to_string(*options.fps));
  }
  if (Status status = options.glitch.validate(); !status.ok()) return status;
  Result<MotionAsset> asset = readAny(path, options);
  if (asset.ok()) handleGlitches(asset.value(), options);
  return asset;
}

Status exportMotion(const std::filesystem::path& path, const MotionAsset& asset, const Clip& clip,
                    const ExportOptions& options) {
  if (Status status = asset.skeleton.validate(); !status.ok()) {
    return Status::error(path.string() + ": cannot export: " + status.message());
  }
  if (Status status = clip.validate(asset.skeleton); !status.ok()) {
    return Status::error(path.string() + ": cannot export: " + status.message());
  }
  if (options.fps && !(*options.fps > 0.0 && *options.fps <= 1000.0)) {
    return Status::error(path.string() + ": fps must be in (0, 1000]");
  }
  const Clip resampled = options.fps ? resampleClip(clip, 1.0 / *options.fps) : clip;
  const std::string ext = lowerExtension(path);
  if (ext == ".bvh") {
    const SourceFrame frame = options.bvh_frame ? *options.bvh_frame : defaultBvhFrame(asset.skeleton);
    return writeFileAtomically(path, writeBvh(asset.skeleton, resampled, frame));
  }
  if (ext == ".glb" || ext == ".gltf") return saveGltf(path, asset, resampled);
  return Status::error(path.string() + ": unknown file type '" + ext +
                       "', expected .bvh, .glb or .gltf");
}

Clip resampleClip(const Clip& clip, double frame_time) {
  Clip out;
  out.name = clip.name;
  out.frame_time = frame_time;
  out.joint_count = clip.joint_count;
  out.euler_start = clip.euler_start;
  out.euler_range = clip.euler_range;
  out.frame_count = frameCountFor(clip.duration(), frame_time);
  const size_t size = static_cast<size_t>(out.frame_count) * clip.joint_count;
  out.rotations.resize(size);
  out.translations.resize(size);
  if (!clip.scales.empty()) out.scales.resize(size);
  for (int f = 0; f < out.frame_count; ++f) {
    const double source = std::min(f * frame_time / clip.frame_time,
                                   static_cast<double>(clip.frame_count - 1));
    const int a = static_cast<int>(std::floor(source));
    const int b = std::min(a + 1, clip.frame_count - 1);
    const double u = source - a;
    for (int j = 0; j < clip.joint_count; ++j) {
      const size_t n = static_cast<size_t>(f) * clip.joint_count + j;
      out.rotations[n] = glm::slerp(clip.rotation(a, j), clip.rotation(b, j), u);
      out.translations[n] = glm::mix(clip.translation(a, j), clip.translation(b, j), u);
      if (!clip.scales.empty()) out.scales[n] = glm::mix(clip.scale(a, j), clip.scale(b, j), u);
    }
  }
  return out;
}

}  // namespace sinew::motion
