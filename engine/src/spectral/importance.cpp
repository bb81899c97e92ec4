#include "sinew/spectral/importance.h"

#include <algorithm>
#include <string>

namespace sinew::spectral {

Status ImportanceSettings::validate() const {
  if (rank_by != ImportanceRank::kFrozenError && rank_by != ImportanceRank::kEnergy &&
      rank_by != ImportanceRank::kWeightedEnergy) {
    return Status::error("rank_by must be frozen error, energy or weighted energy, got " +
                         std::to_string(static_cast<int>(rank_by)));
  }
  return {};
}

Result<ImportanceReport> jointImportance(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                         const MotionSpectrum& spectrum,
                                         const ImportanceSettings& settings) {
  if (Status status = clip.validate(skeleton); !status.ok()) return status;
  const MotionSignals& signals = spectrum.signals;
  const int joints = skeleton.jointCount();
  if (signals.frame_count != clip.frame_count ||
      spectrum.series.size() != signals.channels.size() ||
      static_cast<int>(spectrum.joint_k.size()) != joints) {
    return Status::error("the spectrum is not this clip's analysis (" +
                         std::to_string(signals.frame_count) + " frames against " +
                         std::to_string(clip.frame_count) + ")");
  }
  if (Status status = settings.validate(); !status.ok()) return status;

  // Energy of the kept harmonics and the mean rotation, per joint.
  std::vector<double> energy(joints, 0.0);
  std::vector<bool> rotates(joints, false);
  std::vector<glm::dvec3> mean_vector(joints, glm::dvec3(0.0));
  for (size_t c = 0; c < signals.channels.size(); ++c) {
    const SignalChannel& channel = signals.channels[c];
    if (channel.kind != SignalKind::kRotation) continue;
    rotates[channel.joint] = true;
    mean_vector[channel.joint][channel.axis] = spectrum.series[c].mean;
    for (const Harmonic& h : spectrum.series[c].strongest(spectrum.joint_k[channel.joint])) {
      energy[channel.joint] += h.amplitude * h.amplitude;
    }
  }

  // Lever arms in the model's mean pose.
  const motion::Clip original = windowFrames(clip, spectrum);
  std::vector<int> none(joints, 0);
  const motion::Clip mean_pose = reconstruct(skeleton, spectrum, none);
  std::vector<glm::dmat4> world(joints);
  motion::worldTransforms(skeleton, mean_pose, 0, world);
  std::vector<double> lever(joints, 0.0);
  for (int j = 0; j < joints; ++j) {
    std::vector<glm::dvec3> points{glm::dvec3(world[j][3])};
    if (skeleton.end_sites[j])
      points.emplace_back(world[j] * glm::dvec4(*skeleton.end_sites[j], 1.0));
    // Every ancestor carries this joint and its End Site.
    for (int a = skeleton.parents[j]; a != motion::kNoParent; a = skeleton.parents[a]) {
      for (const glm::dvec3& p : points) {
        lever[a] = std::max(lever[a], glm::length(p - glm::dvec3(world[a][3])));
      }
    }
    if (skeleton.end_sites[j]) lever[j] = std::max(lever[j], glm::length(points[1] - points[0]));
  }

  ImportanceReport report;
  const motion::Clip model = reconstruct(skeleton, spectrum);
  JointError total;
  measureError(skeleton, original, model, signals, &total);
  report.model_cm_mean = total.pos_err_cm_mean;
  report.model_cm_max = total.pos_err_cm_max;
  motion::Clip frozen = model;
  for (int j = 0; j < joints; ++j) {
    if (!rotates[j]) continue;
    const glm::dquat still =
        glm::normalize(signals.mean_rotations[j] * fromRotationVector(mean_vector[j]));
    for (int f = 0; f < frozen.frame_count; ++f) {
      frozen.rotations[static_cast<size_t>(f) * joints + j] = still;
    }
    measureError(skeleton, original, frozen, signals, &total);
    for (int f = 0; f < frozen.frame_count; ++f) {
      const size_t n = static_cast<size_t>(f) * joints + j;
      frozen.rotations[n] = model.rotations[n];
    }
    report.joints.push_back({j, energy[j], lever[j], energy[j] * lever[j] * lever[j],
                             total.pos_err_cm_mean, total.pos_err_cm_max});
  }
  const auto key = [&](const JointImportance& i) {
    switch (settings.rank_by) {
      case ImportanceRank::kEnergy:
        return i.energy_rad2;
      case ImportanceRank::kWeightedEnergy:
        return i.weighted_energy_m2;
      case ImportanceRank::kFrozenError:
        break;
    }
    return i.frozen_cm_mean;
  };
  std::stable_sort(
      report.joints.begin(), report.joints.end(),
      [&](const JointImportance& a, const JointImportance& b) { return key(a) > key(b); });
  return report;
}

}  // namespace sinew::spectral
