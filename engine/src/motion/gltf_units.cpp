#include "gltf_units.h"

#include <cmath>
#include <sstream>

#include "sinew/core/assert.h"
#include "sinew/motion/anatomy.h"

namespace sinew::motion::gltf {
namespace {

// float32 noise on a scale of 1 (RiggedFigure's 1.0000001), relative.
constexpr double kScaleTolerance = 1e-6;

bool near(double a, double b) {
  return std::abs(a - b) <= kScaleTolerance * std::abs(b);
}

bool uniform(const glm::dvec3& s) {
  return s.x > 0.0 && near(s.y, s.x) && near(s.z, s.x);
}

bool animatesScale(const std::vector<Clip>& clips, int joint, const glm::dvec3& rest) {
  for (const Clip& clip : clips) {
    if (clip.scales.empty()) continue;
    for (int f = 0; f < clip.frame_count; ++f) {
      const glm::dvec3 s = clip.scale(f, joint);
      if (!near(s.x, rest.x) || !near(s.y, rest.y) || !near(s.z, rest.z)) return true;
    }
  }
  return false;
}

// Drops a clip's scales when every one is 1 (forward kinematics skips an empty array).
void dropUnitScales(Clip& clip) {
  for (const glm::dvec3& s : clip.scales) {
    if (!near(s.x, 1.0) || !near(s.y, 1.0) || !near(s.z, 1.0)) return;
  }
  clip.scales.clear();
}

glm::dmat4 uniformScale(double s) {
  glm::dmat4 m(s);
  m[3][3] = 1.0;
  return m;
}

// The figure's first pose (the first clip, else the rest pose) measured in the numbers as they
// now are.
FrameDetection detect(const MotionAsset& asset, const ImportOptions& options) {
  const Clip rest = restClip(asset.skeleton, 1, 1.0 / 30.0);
  const Clip& pose = asset.clips.empty() ? rest : asset.clips.front();
  const SourceFrame stated{options.unit.value_or(LengthUnit::kMetres), UpAxis::kY};
  FrameDetection detection = detectStatedFrame(asset.skeleton, pose, stated);
  if (options.unit) {
    detection.frame = stated;
    detection.height_m = detection.height_in_file_units * metresPerUnit(stated.unit);
    detection.reason = "unit set by the user (--units); " + detection.reason;
  }
  return detection;
}

// "armature scale 0.01 on 'Armature' applied; " for the folded joints, or nothing.
std::string foldedNote(const Skeleton& skeleton, const std::vector<double>& folded) {
  std::ostringstream note;
  note.precision(4);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (folded[j] == 1.0) continue;
    note << "node scale " << folded[j] << " on '" << skeleton.names[j] << "' applied; ";
  }
  return note.str();
}

}  // namespace

std::vector<double> foldableScales(const Skeleton& skeleton, const std::vector<Clip>& clips) {
  std::vector<double> folded(static_cast<size_t>(skeleton.jointCount()), 1.0);
  if (skeleton.jointCount() == 0) return folded;
  for (int j = pelvisJoint(skeleton); j != kNoParent; j = skeleton.parents[j]) {
    const glm::dvec3& s = skeleton.rest_scales[j];
    if (uniform(s) && !near(s.x, 1.0) && !animatesScale(clips, j, s)) folded[j] = s.x;
  }
  return folded;
}

std::vector<double> foldScales(MotionAsset& asset, const std::vector<double>& folded) {
  Skeleton& skeleton = asset.skeleton;
  const int joints = skeleton.jointCount();
  std::vector<double> above(static_cast<size_t>(joints), 1.0);      // ancestors' scales
  std::vector<double> inclusive(static_cast<size_t>(joints), 1.0);  // and the joint's own
  for (int j = 0; j < joints; ++j) {
    const int parent = skeleton.parents[j];
    above[j] = parent == kNoParent ? 1.0 : inclusive[parent];
    inclusive[j] = above[j] * folded[j];
    skeleton.offsets[j] *= above[j];
    if (folded[j] != 1.0) skeleton.rest_scales[j] = glm::dvec3(1.0);
  }
  for (Clip& clip : asset.clips) {
    for (int f = 0; f < clip.frame_count; ++f) {
      for (int j = 0; j < joints; ++j) {
        const size_t n = static_cast<size_t>(f) * clip.joint_count + j;
        clip.translations[n] *= above[j];
        if (!clip.scales.empty()) clip.scales[n] /= folded[j];
      }
    }
    dropUnitScales(clip);
  }
  for (SkinnedMesh& mesh : asset.meshes) {
    for (size_t j = 0; j < mesh.inverse_bind.size() && j < inclusive.size(); ++j)
      mesh.inverse_bind[j] = uniformScale(inclusive[j]) * mesh.inverse_bind[j];
  }
  return above;
}

void scaleLengths(MotionAsset& asset, double metres_per_number) {
  const double k = metres_per_number;
  for (glm::dvec3& offset : asset.skeleton.offsets) offset *= k;
  for (Clip& clip : asset.clips) {
    for (glm::dvec3& t : clip.translations) t *= k;
  }
  for (SkinnedMesh& mesh : asset.meshes) {
    for (glm::vec3& p : mesh.positions) p *= static_cast<float>(k);
    // k * M * (1/k) for an affine M: its linear part stays, its translation scales.
    for (glm::dmat4& m : mesh.inverse_bind) m[3] = glm::dvec4(glm::dvec3(m[3]) * k, m[3][3]);
    mesh.mesh_to_world[3] =
        glm::dvec4(glm::dvec3(mesh.mesh_to_world[3]) * k, mesh.mesh_to_world[3][3]);
  }
}

void toMetres(MotionAsset& asset, const ImportOptions& options, GltfSource& source) {
  const std::vector<double> folded = foldableScales(asset.skeleton, asset.clips);
  std::vector<double> factor = foldScales(asset, folded);
  asset.detection = detect(asset, options);
  asset.detection.reason = foldedNote(asset.skeleton, folded) + asset.detection.reason;
  const double unit = metresPerUnit(asset.detection.frame.unit);
  if (unit != 1.0) scaleLengths(asset, unit);
  for (double& f : factor) f *= unit;
  asset.skeleton.source = asset.detection.frame;
  source.metres_per_number = std::move(factor);
  source.folded_scale = folded;
}

glm::dvec3 translationToFile(const GltfSource& source, int joint, const glm::dvec3& metres) {
  if (source.metres_per_number.empty()) return metres;
  return metres / source.metres_per_number[static_cast<size_t>(joint)];
}

glm::dvec3 scaleToFile(const GltfSource& source, int joint, const glm::dvec3& scale) {
  if (source.folded_scale.empty()) return scale;
  return scale * source.folded_scale[static_cast<size_t>(joint)];
}

Clip clipToFile(const Clip& clip, const GltfSource& source) {
  SINEW_ASSERT(source.metres_per_number.empty() ||
                   source.metres_per_number.size() == static_cast<size_t>(clip.joint_count),
               "the clip has the rig's joints");
  Clip out = clip;
  for (int f = 0; f < clip.frame_count; ++f) {
    for (int j = 0; j < clip.joint_count; ++j) {
      const size_t n = static_cast<size_t>(f) * clip.joint_count + j;
      out.translations[n] = translationToFile(source, j, clip.translations[n]);
      if (!out.scales.empty()) out.scales[n] = scaleToFile(source, j, clip.scales[n]);
    }
  }
  return out;
}

}  // namespace sinew::motion::gltf
