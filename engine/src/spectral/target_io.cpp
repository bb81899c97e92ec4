#include "sinew/spectral/target_io.h"

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/core/json_keys.h"
#include "sinew/core/text.h"
#include "sinew/spectral/limits.h"

namespace sinew::spectral {
namespace {

using nlohmann::json;

constexpr const char* kFormat = "sinew.target";
constexpr int kVersion = 1;

const char* axisName(int axis) {
  return axis == 0 ? "x" : axis == 1 ? "y" : "z";
}

// "walk.json: joints" at the top level, "walk.json: joints[2].name" below it.
std::string field(const std::string& where, const char* key) {
  return where + (!where.empty() && where.back() == ']' ? "." : ": ") + key;
}

// Reads a number at `where`, or says which field is missing or wrong.
Status number(const json& object, const char* key, const std::string& where, double& out) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) {
    return Status::error(field(where, key) + ": expected a number");
  }
  out = it->get<double>();
  return {};
}

// A whole number in [low, high] at `where`: 1.5 and 1e9 are refused, not truncated.
Status wholeNumber(const json& object, const char* key, const std::string& where, int low, int high,
                   int& out) {
  const auto it = object.find(key);
  const double value = it != object.end() && it->is_number() ? it->get<double>() : 0.5;
  if (!(value == std::floor(value) && value >= low && value <= high)) {
    return Status::error(field(where, key) + ": expected a whole number from " +
                         std::to_string(low) + " to " + std::to_string(high));
  }
  out = static_cast<int>(value);
  return {};
}

// An array at `key` (empty when absent) of at most `limit` entries.
Status arrayOf(const json& object, const char* key, const std::string& where, size_t limit,
               const json*& out) {
  static const json kEmpty = json::array();
  const auto it = object.find(key);
  out = it == object.end() ? &kEmpty : &*it;
  if (!out->is_array()) return Status::error(field(where, key) + ": expected an array");
  if (out->size() > limit) {
    return Status::error(field(where, key) + ": more than " + std::to_string(limit) + " entries");
  }
  return {};
}

// A string at `key`, or `fallback` when absent.
Status text(const json& object, const char* key, const std::string& where, std::string fallback,
            std::string& out) {
  const auto it = object.find(key);
  if (it == object.end()) {
    out = std::move(fallback);
    return {};
  }
  if (!it->is_string()) return Status::error(field(where, key) + ": expected a string");
  out = it->get<std::string>();
  return {};
}

Status vector(const json& object, const char* key, const std::string& where, int size,
              double* out) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_array() || static_cast<int>(it->size()) != size) {
    return Status::error(field(where, key) + ": expected an array of " + std::to_string(size) +
                         " numbers");
  }
  for (int n = 0; n < size; ++n) {
    if (!(*it)[n].is_number()) return Status::error(field(where, key) + ": expected numbers");
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
    const int parent = skeleton.parents[j];
    json joint = {{"name", skeleton.names[j]},
                  {"parent", parent == motion::kNoParent ? "" : skeleton.names[parent]},
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
    channels.push_back(
        {{"joint", skeleton.names[channel.joint]},
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
  const json document = {
      {"format", kFormat},
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

namespace {

Status readJoints(const json& document, const motion::Skeleton& skeleton, const std::string& source,
                  TargetMotion& target, std::vector<std::string>* warnings) {
  const json* joints = nullptr;
  // No limit here: the count must equal the skeleton's, which the message below says.
  if (Status s = arrayOf(document, "joints", source, SIZE_MAX, joints); !s.ok()) return s;
  if (static_cast<int>(joints->size()) != skeleton.jointCount()) {
    return Status::error(source + ": joints: expected " + std::to_string(skeleton.jointCount()) +
                         " joints for this skeleton, found " + std::to_string(joints->size()));
  }
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const std::string where = source + ": joints[" + std::to_string(j) + "]";
    const json& joint = (*joints)[j];
    if (!joint.is_object()) return Status::error(where + ": expected an object");
    unknownKeys(joint, {"name", "parent", "base_rotation_wxyz", "base_translation_m", "base_scale"},
                where, warnings);
    std::string name;
    if (Status s = text(joint, "name", where, "", name); !s.ok()) return s;
    if (name != skeleton.names[j]) {
      return Status::error(where + ".name: expected '" + skeleton.names[j] + "', found '" + name +
                           "' (the coefficients are for another rig)");
    }
    // Written since the hierarchy is checked; older files have no parent and match by name.
    const int parent = skeleton.parents[j];
    const std::string expected = parent == motion::kNoParent ? "" : skeleton.names[parent];
    std::string parent_name;
    if (Status s = text(joint, "parent", where, expected, parent_name); !s.ok()) return s;
    if (parent_name != expected) {
      return Status::error(where + ".parent: expected '" + expected + "', found '" + parent_name +
                           "' (the coefficients are for a rig with another hierarchy)");
    }
    double q[4];
    double t[3];
    if (Status s = vector(joint, "base_rotation_wxyz", where, 4, q); !s.ok()) return s;
    if (Status s = vector(joint, "base_translation_m", where, 3, t); !s.ok()) return s;
    const glm::dquat rotation(q[0], q[1], q[2], q[3]);
    const double norm = glm::length(rotation);
    if (!(norm > 1e-9 && norm < 1e9)) {
      return Status::error(where + ".base_rotation_wxyz: expected a non-zero quaternion");
    }
    // A unit quaternion is kept bit for bit: normalising it again moves its last bits, and a
    // replayed controller must be the one that was scored (a marginal gait falls otherwise).
    target.base_rotations.push_back(std::abs(norm - 1.0) < 1e-12 ? rotation : rotation / norm);
    target.base_translations.emplace_back(t[0], t[1], t[2]);
    if (joint.contains("base_scale")) {
      double s3[3];
      if (Status s = vector(joint, "base_scale", where, 3, s3); !s.ok()) return s;
      target.base_scales.resize(skeleton.jointCount(), glm::dvec3(1.0));
      target.base_scales[j] = glm::dvec3(s3[0], s3[1], s3[2]);
    }
  }
  return {};
}

Status readAxis(const json& item, const std::string& where, int& axis) {
  std::string name;
  if (Status s = text(item, "axis", where, "", name); !s.ok()) return s;
  if (name != "x" && name != "y" && name != "z") {
    return Status::error(where + ".axis: expected \"x\", \"y\" or \"z\"");
  }
  axis = name[0] - 'x';
  return {};
}

Status readJoint(const json& item, const motion::Skeleton& skeleton, const std::string& where,
                 int& joint) {
  std::string name;
  if (Status s = text(item, "joint", where, "", name); !s.ok()) return s;
  joint = skeleton.findJoint(name);
  if (joint < 0)
    return Status::error(where + ".joint: no such joint in the skeleton: '" + name + "'");
  return {};
}

Result<ChannelModel> readChannel(const json& item, const motion::Skeleton& skeleton,
                                 const std::string& where, std::vector<std::string>* warnings) {
  if (!item.is_object()) return Status::error(where + ": expected an object");
  unknownKeys(item, {"joint", "kind", "axis", "unit", "mean", "trend_per_s", "harmonics"}, where,
              warnings);
  ChannelModel channel;
  if (Status s = readJoint(item, skeleton, where, channel.joint); !s.ok()) return s;
  std::string kind;
  if (Status s = text(item, "kind", where, "", kind); !s.ok()) return s;
  if (kind != "rotation" && kind != "translation") {
    return Status::error(where + ".kind: expected \"rotation\" or \"translation\"");
  }
  channel.kind = kind == "rotation" ? SignalKind::kRotation : SignalKind::kTranslation;
  if (Status s = readAxis(item, where, channel.axis); !s.ok()) return s;
  if (Status s = number(item, "mean", where, channel.mean); !s.ok()) return s;
  if (Status s = number(item, "trend_per_s", where, channel.trend); !s.ok()) return s;
  const json* harmonics = nullptr;
  if (Status s = arrayOf(item, "harmonics", where, kMaxHarmonicsPerChannel, harmonics); !s.ok())
    return s;
  std::vector<bool> seen(static_cast<size_t>(kMaxHarmonicIndex) + 1, false);
  for (size_t h = 0; h < harmonics->size(); ++h) {
    const std::string at = where + ".harmonics[" + std::to_string(h) + "]";
    const json& term = (*harmonics)[h];
    if (!term.is_object()) return Status::error(at + ": expected an object");
    unknownKeys(term, {"n", "amplitude", "phase_rad"}, at, warnings);
    Harmonic harmonic;
    if (Status s = wholeNumber(term, "n", at, 1, kMaxHarmonicIndex, harmonic.n); !s.ok()) return s;
    if (Status s = number(term, "amplitude", at, harmonic.amplitude); !s.ok()) return s;
    if (Status s = number(term, "phase_rad", at, harmonic.phase); !s.ok()) return s;
    if (seen[static_cast<size_t>(harmonic.n)])  // one coefficient pair per index, as a genome
      return Status::error(at + ".n: harmonic " + std::to_string(harmonic.n) +
                           " appears twice in this channel");
    seen[static_cast<size_t>(harmonic.n)] = true;
    channel.terms.push_back(harmonic);
  }
  return channel;
}

Result<SecondaryTerm> readSecondary(const json& item, const motion::Skeleton& skeleton,
                                    const std::string& where, std::vector<std::string>* warnings) {
  if (!item.is_object()) return Status::error(where + ": expected an object");
  unknownKeys(item, {"joint", "axis", "omega_rad_s", "amplitude_rad", "phase_rad"}, where,
              warnings);
  SecondaryTerm term;
  if (Status s = readJoint(item, skeleton, where, term.joint); !s.ok()) return s;
  if (Status s = readAxis(item, where, term.axis); !s.ok()) return s;
  if (Status s = number(item, "omega_rad_s", where, term.omega); !s.ok()) return s;
  if (Status s = number(item, "amplitude_rad", where, term.amplitude); !s.ok()) return s;
  if (Status s = number(item, "phase_rad", where, term.phase); !s.ok()) return s;
  return term;
}

}  // namespace

Result<TargetMotion> targetFromJson(std::string_view text_in, const motion::Skeleton& skeleton,
                                    std::string_view source_name,
                                    std::vector<std::string>* warnings) {
  const std::string source(source_name);
  const json document = json::parse(withoutBom(text_in), nullptr, false);
  if (document.is_discarded() || !document.is_object()) {
    return Status::error(source + ": not valid JSON");
  }
  unknownKeys(document,
              {"format", "version", "name", "omega0_rad_s", "period_s", "model", "joints",
               "channels", "secondary"},
              source, warnings);
  std::string format;
  if (Status s = text(document, "format", source, "", format); !s.ok()) return s;
  if (format != kFormat) return Status::error(source + ": format: expected \"" + kFormat + "\"");
  int version = 0;
  if (Status s = wholeNumber(document, "version", source, 1, kVersion, version); !s.ok()) return s;
  TargetMotion target;
  if (Status s = text(document, "name", source, "target", target.name); !s.ok()) return s;
  target.name = toUtf8(target.name);
  if (Status s = number(document, "omega0_rad_s", source, target.omega0); !s.ok()) return s;
  if (Status s = readJoints(document, skeleton, source, target, warnings); !s.ok()) return s;
  const json* channels = nullptr;
  const size_t most_channels = static_cast<size_t>(skeleton.jointCount()) * 6;
  if (Status s = arrayOf(document, "channels", source, most_channels, channels); !s.ok()) return s;
  for (size_t c = 0; c < channels->size(); ++c) {
    Result<ChannelModel> channel = readChannel(
        (*channels)[c], skeleton, source + ": channels[" + std::to_string(c) + "]", warnings);
    if (!channel.ok()) return channel.status();
    target.channels.push_back(std::move(channel).value());
  }
  const json* secondary = nullptr;
  if (Status s = arrayOf(document, "secondary", source, most_channels, secondary); !s.ok())
    return s;
  for (size_t n = 0; n < secondary->size(); ++n) {
    Result<SecondaryTerm> term = readSecondary(
        (*secondary)[n], skeleton, source + ": secondary[" + std::to_string(n) + "]", warnings);
    if (!term.ok()) return term.status();
    target.secondary.push_back(term.value());
  }
  if (Status s = target.validate(skeleton); !s.ok())
    return Status::error(source + ": " + s.message());
  return target;
}

Status saveTarget(const std::filesystem::path& path, const TargetMotion& target,
                  const motion::Skeleton& skeleton) {
  return writeFileAtomically(path, targetToJson(target, skeleton));
}

Result<TargetMotion> loadTarget(const std::filesystem::path& path, const motion::Skeleton& skeleton,
                                std::vector<std::string>* warnings) {
  Result<std::string> file_text = readFile(path);
  if (!file_text.ok()) return file_text.status();
  return targetFromJson(file_text.value(), skeleton, path.string(), warnings);
}

}  // namespace sinew::spectral
