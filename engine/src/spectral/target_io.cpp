#include "sinew/spectral/target_io.h"

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"

namespace sinew::spectral {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "sinew.target";
constexpr int kVersion = 1;

const char* axisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

// Reads a number at `where`, or says which field is missing or wrong.
Status number(const json& object, const char* key, const std::string& where, double& out) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) {
    return Status::error(where + "." + key + ": expected a number");
  }
  out = it->get<double>();
  return {};
}

Status vector(const json& object, const char* key, const std::string& where, int size,
              double* out) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_array() || static_cast<int>(it->size()) != size) {
    return Status::error(where + "." + key + ": expected an array of " + std::to_string(size) +
                         " numbers");
  }
  for (int n = 0; n < size; ++n) {
    if (!(*it)[n].is_number()) return Status::error(where + "." + key + ": expected numbers");
    out[n] = (*it)[n].get<double>();
  }
  return {};
}

}  // namespace

std::string targetToJson(const TargetMotion& target, const motion::Skeleton& skeleton) {
  json joints = json::array();
  for (int j = 0; j < target.jointCount(); ++j) {
    const glm::dquat& q = target.base_rotations[j];
    const glm::dvec3& t = target.base_translations[j];
    json joint = {{"name", skeleton.names[j]},
                  {"base_rotation_wxyz", {q.w, q.x, q.y, q.z}},
                  {"base_translation_m", {t.x, t.y, t.z}}};
    if (!target.base_scales.empty()) {
      const glm::dvec3& s = target.base_scales[j];
      joint["base_scale"] = {s.x, s.y, s.z};
    }
    joints.push_back(joint);
  }
  json channels = json::array();
  for (const ChannelModel& channel : target.channels) {
    json harmonics = json::array();
    for (const Harmonic& h : channel.terms) {
      harmonics.push_back({{"n", h.n}, {"amplitude", h.amplitude}, {"phase_rad", h.phase}});
    }
    channels.push_back({{"joint", skeleton.names[channel.joint]},
                        {"kind", channel.kind == SignalKind::kRotation ? "rotation" : "translation"},
                        {"axis", axisName(channel.axis)},
                        {"unit", channel.kind == SignalKind::kRotation ? "rad" : "m"},
                        {"mean", channel.mean},
                        {"trend_per_s", channel.trend},
                        {"harmonics", harmonics}});
  }
  json secondary = json::array();
  for (const SecondaryTerm& term : target.secondary) {
    secondary.push_back({{"joint", skeleton.names[term.joint]},
                         {"axis", axisName(term.axis)},
                         {"omega_rad_s", term.omega},
                         {"amplitude_rad", term.amplitude},
                         {"phase_rad", term.phase}});
  }
  const json document = {{"format", kFormat},
                         {"version", kVersion},
                         {"name", target.name},
                         {"omega0_rad_s", target.omega0},
                         {"period_s", target.period()},
                         {"model", "theta(t) = mean + trend t + sum amplitude sin(n omega0 t + phase)"},
                         {"joints", joints},
                         {"channels", channels},
                         {"secondary", secondary}};
  return document.dump(2) + "\n";
}

Result<TargetMotion> targetFromJson(std::string_view text, const motion::Skeleton& skeleton,
                                    std::string_view source_name) {
  const std::string source(source_name);
  const json document = json::parse(text, nullptr, false);
  if (document.is_discarded() || !document.is_object()) {
    return Status::error(source + ": not valid JSON");
  }
  if (document.value("format", "") != kFormat) {
    return Status::error(source + ": format: expected \"" + kFormat + "\"");
  }
  if (!document.contains("version") || !document["version"].is_number_integer() ||
      document["version"].get<int>() > kVersion) {
    return Status::error(source + ": version: expected " + std::to_string(kVersion) + " or older");
  }
  TargetMotion target;
  target.name = document.value("name", "target");
  if (Status s = number(document, "omega0_rad_s", source, target.omega0); !s.ok()) return s;
  const json& joints = document.value("joints", json::array());
  if (!joints.is_array() || static_cast<int>(joints.size()) != skeleton.jointCount()) {
    return Status::error(source + ": joints: expected " + std::to_string(skeleton.jointCount()) +
                         " joints for this skeleton");
  }
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const std::string where = source + ": joints[" + std::to_string(j) + "]";
    if (joints[j].value("name", "") != skeleton.names[j]) {
      return Status::error(where + ".name: expected '" + skeleton.names[j] + "'");
    }
    double q[4];
    double t[3];
    if (Status s = vector(joints[j], "base_rotation_wxyz", where, 4, q); !s.ok()) return s;
    if (Status s = vector(joints[j], "base_translation_m", where, 3, t); !s.ok()) return s;
    target.base_rotations.push_back(glm::normalize(glm::dquat(q[0], q[1], q[2], q[3])));
    target.base_translations.emplace_back(t[0], t[1], t[2]);
    if (joints[j].contains("base_scale")) {
      double s3[3];
      if (Status s = vector(joints[j], "base_scale", where, 3, s3); !s.ok()) return s;
      target.base_scales.resize(skeleton.jointCount(), glm::dvec3(1.0));
      target.base_scales[j] = glm::dvec3(s3[0], s3[1], s3[2]);
    }
  }
  const json& channels = document.value("channels", json::array());
  for (size_t c = 0; c < channels.size(); ++c) {
    const std::string where = source + ": channels[" + std::to_string(c) + "]";
    const json& item = channels[c];
    ChannelModel channel;
    channel.joint = skeleton.findJoint(item.value("joint", ""));
    if (channel.joint < 0) return Status::error(where + ".joint: no such joint in the skeleton");
    const std::string kind = item.value("kind", "");
    if (kind != "rotation" && kind != "translation") {
      return Status::error(where + ".kind: expected \"rotation\" or \"translation\"");
    }
    channel.kind = kind == "rotation" ? SignalKind::kRotation : SignalKind::kTranslation;
    const std::string axis = item.value("axis", "");
    if (axis != "x" && axis != "y" && axis != "z") {
      return Status::error(where + ".axis: expected \"x\", \"y\" or \"z\"");
    }
    channel.axis = axis[0] - 'x';
    if (Status s = number(item, "mean", where, channel.mean); !s.ok()) return s;
    if (Status s = number(item, "trend_per_s", where, channel.trend); !s.ok()) return s;
    const json& harmonics = item.value("harmonics", json::array());
    for (size_t h = 0; h < harmonics.size(); ++h) {
      const std::string at = where + ".harmonics[" + std::to_string(h) + "]";
      Harmonic harmonic;
      double n = 0.0;
      if (Status s = number(harmonics[h], "n", at, n); !s.ok()) return s;
      if (Status s = number(harmonics[h], "amplitude", at, harmonic.amplitude); !s.ok()) return s;
      if (Status s = number(harmonics[h], "phase_rad", at, harmonic.phase); !s.ok()) return s;
      harmonic.n = static_cast<int>(n);
      channel.terms.push_back(harmonic);
    }
    target.channels.push_back(std::move(channel));
  }
  const json& secondary = document.value("secondary", json::array());
  for (size_t n = 0; n < secondary.size(); ++n) {
    const std::string where = source + ": secondary[" + std::to_string(n) + "]";
    SecondaryTerm term;
    term.joint = skeleton.findJoint(secondary[n].value("joint", ""));
    if (term.joint < 0) return Status::error(where + ".joint: no such joint in the skeleton");
    const std::string axis = secondary[n].value("axis", "");
    if (axis != "x" && axis != "y" && axis != "z") {
      return Status::error(where + ".axis: expected \"x\", \"y\" or \"z\"");
    }
    term.axis = axis[0] - 'x';
    if (Status s = number(secondary[n], "omega_rad_s", where, term.omega); !s.ok()) return s;
    if (Status s = number(secondary[n], "amplitude_rad", where, term.amplitude); !s.ok()) return s;
    if (Status s = number(secondary[n], "phase_rad", where, term.phase); !s.ok()) return s;
    target.secondary.push_back(term);
  }
  if (Status s = target.validate(skeleton); !s.ok()) return Status::error(source + ": " + s.message());
  return target;
}

Status saveTarget(const std::filesystem::path& path, const TargetMotion& target,
                  const motion::Skeleton& skeleton) {
  return writeFileAtomically(path, targetToJson(target, skeleton));
}

Result<TargetMotion> loadTarget(const std::filesystem::path& path, const motion::Skeleton& skeleton) {
  Result<std::string> text = readFile(path);
  if (!text.ok()) return text.status();
  return targetFromJson(text.value(), skeleton, path.string());
}

}  // namespace sinew::spectral
