#include "project/project.h"

#include <charconv>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/core/json_keys.h"
#include "sinew/core/path_json.h"
#include "sinew/core/text.h"

namespace sinew::app {
namespace {

using nlohmann::json;

constexpr const char* kBandNames[kBandCount] = {"gait", "style", "detail"};
constexpr const char* kGroupNames[kGroupCount] = {"legs", "arms", "spine", "head"};

Result<double> parseNumber(const std::string& text, const std::string& context) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return value;
  } catch (const std::exception&) {
    return Status::error(context + ": '" + text + "' is not a number");
  }
}

std::vector<std::string> splitCommas(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) parts.push_back(item);
  return parts;
}

// A JSON value of the expected type, or a message naming the field.
template <class T>
Status read(const json& object, const char* key, T& out, const std::string& where) {
  if (!object.contains(key)) return Status();
  try {
    out = object.at(key).get<T>();
    return Status();
  } catch (const json::exception&) {
    return Status::error(where + key + ": expected " +
                         (std::is_same_v<T, std::string> ? "a string"
                          : std::is_same_v<T, bool>      ? "true or false"
                          : std::is_arithmetic_v<T>      ? "a number"
                                                         : "a list of strings") +
                         ", got " + object.at(key).dump());
  }
}

std::string relativeTo(const std::string& file, const std::filesystem::path& base) {
  if (file.empty() || base.empty()) return file;
  const std::filesystem::path path(file);
  if (!path.is_absolute()) return file;
  const std::filesystem::path relative = path.lexically_relative(base);
  return relative.empty() ? file : relative.generic_string();
}

json weightsJson(const search::FitnessWeights& weights) {
  json out = json::object();
  search::FitnessWeights copy = weights;
  for (int term = 0; term < search::kFitnessTermCount; ++term) {
    out[search::fitnessTermName(term)] = search::fitnessWeight(copy, term);
  }
  return out;
}

Status readWeights(const json& object, search::FitnessWeights& weights, const std::string& where) {
  if (!object.is_object()) return Status::error(where + "weights: expected an object");
  for (const auto& [key, value] : object.items()) {
    int term = -1;
    for (int t = 0; t < search::kFitnessTermCount; ++t) {
      if (key == search::fitnessTermName(t)) term = t;
    }
    if (term < 0) return Status::error(where + "weights: unknown term '" + key + "'");
    if (!value.is_number()) return Status::error(where + "weights." + key + ": expected a number");
    search::fitnessWeight(weights, term) = value.get<double>();
  }
  if (Status status = weights.validate(); !status.ok())
    return Status::error(where + "weights: " + status.message());
  return Status();
}

// The format and version of a project document.
Status checkHeader(const json& document, const std::string& where) {
  if (!document.is_object()) return Status::error(where + "expected a JSON object");
  if (document.value("format", json()) != "sinew.project")
    return Status::error(where + "format: expected \"sinew.project\"");
  const json version = document.value("version", json());
  if (!version.is_number_integer() || version.get<int>() < 1)
    return Status::error(where + "version: expected a whole number (1.." +
                         std::to_string(kProjectVersion) + ")");
  if (version.get<int>() > kProjectVersion)
    return Status::error(where + "version: " + version.dump() +
                         " is newer than this sinew reads (1.." + std::to_string(kProjectVersion) +
                         "); update sinew");
  return Status();
}

// "band_gains": {BAND: {GROUP: GAIN}}.
Status readBandGains(const json& document, const std::string& where, MotionEdits& edits) {
  if (document.contains("band_gains")) {
    const json& bands = document.at("band_gains");
    if (!bands.is_object()) return Status::error(where + "band_gains: expected an object");
    for (const auto& [band, groups] : bands.items()) {
      int b = -1;
      for (int i = 0; i < kBandCount; ++i)
        if (band == kBandNames[i]) b = i;
      if (b < 0)
        return Status::error(where + "band_gains: unknown band '" + band +
                             "' (gait, style, detail)");
      if (!groups.is_object())
        return Status::error(where + "band_gains." + band + ": expected an object");
      for (const auto& [group, gain] : groups.items()) {
        int g = -1;
        for (int i = 0; i < kGroupCount; ++i)
          if (group == kGroupNames[i]) g = i;
        if (g < 0)
          return Status::error(where + "band_gains." + band + ": unknown group '" + group +
                               "' (legs, arms, spine, head)");
        if (!gain.is_number() || gain.get<double>() < 0.0 || gain.get<double>() > 10.0)
          return Status::error(where + "band_gains." + band + "." + group +
                               ": expected a number 0..10");
        edits.band_gains[static_cast<size_t>(b)][static_cast<size_t>(g)] = gain.get<double>();
      }
    }
  }
  return Status();
}

// "search" and "view".
Status readSearchAndView(const json& document, const std::string& where, const std::string& name,
                         std::vector<std::string>* warnings, Project& project) {
  Status status;
  auto check = [&](Status s) {
    if (status.ok() && !s.ok()) status = std::move(s);
  };
  if (document.contains("search")) {
    const json& search = document.at("search");
    const std::string in = where + "search.";
    if (!search.is_object()) return Status::error(where + "search: expected an object");
    unknownKeys(search,
                {"minutes", "population", "no_prior", "optimizer", "seed", "weights", "trials",
                 "trial_push_m_s", "robust_push_m_s", "restart_after", "start_generations"},
                name, warnings, "search.");
    check(read(search, "minutes", project.search.minutes, in));
    check(read(search, "population", project.search.population, in));
    check(read(search, "no_prior", project.search.no_prior, in));
    check(read(search, "seed", project.search.seed, in));
    check(read(search, "trials", project.search.trials, in));
    check(read(search, "trial_push_m_s", project.search.trial_push_m_s, in));
    check(read(search, "robust_push_m_s", project.search.robust_push_m_s, in));
    check(read(search, "restart_after", project.search.restart_after, in));
    check(read(search, "start_generations", project.search.start_generations, in));
    std::string optimizer = search::optimizerName(project.search.optimizer);
    check(read(search, "optimizer", optimizer, in));
    if (status.ok()) {
      Result<search::OptimizerKind> kind = search::optimizerFromName(optimizer);
      if (!kind.ok()) return Status::error(in + "optimizer: " + kind.message());
      project.search.optimizer = kind.value();
    }
    if (search.contains("weights"))
      check(readWeights(search.at("weights"), project.search.weights, in));
  }
  if (document.contains("view")) {
    const json& view = document.at("view");
    const std::string in = where + "view.";
    if (!view.is_object()) return Status::error(where + "view: expected an object");
    unknownKeys(view,
                {"speed", "loop", "show_original", "show_model", "model_beside", "follow",
                 "show_grid", "show_end_sites", "show_population", "show_ghost"},
                name, warnings, "view.");
    ViewSettings& v = project.view;
    check(read(view, "speed", v.speed, in));
    check(read(view, "loop", v.loop, in));
    check(read(view, "show_original", v.show_original, in));
    check(read(view, "show_model", v.show_model, in));
    check(read(view, "model_beside", v.model_beside, in));
    check(read(view, "follow", v.follow, in));
    check(read(view, "show_grid", v.show_grid, in));
    check(read(view, "show_end_sites", v.show_end_sites, in));
    check(read(view, "show_population", v.show_population, in));
    check(read(view, "show_ghost", v.show_ghost, in));
  }
  return status;
}

}  // namespace

Result<Project> parseProject(const std::string& text, const std::filesystem::path& base,
                             const std::string& name, std::vector<std::string>* warnings) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number past double's range
    return Status::error(name + ": not JSON: " + e.what());
  }
  const std::string where = name + ": ";
  if (Status valid = checkHeader(document, where); !valid.ok()) return valid;
  unknownKeys(document, {"format",          "version",    "rig",    "rig_encoding",    "clip",
                         "clip_encoding",   "animation",  "target", "target_encoding", "harmonics",
                         "joint_harmonics", "band_gains", "styles", "secondary",       "terrain",
                         "window_s",        "pushes",     "body",   "search",          "view"},
              name, warnings);
  Project project;
  Status status;
  auto check = [&](Status s) {
    if (status.ok() && !s.ok()) status = std::move(s);
  };
  if (!document.contains("rig")) return Status::error(where + "rig: missing (the rig file)");
  check(readPathJson(document, "rig", project.rig, where));
  check(readPathJson(document, "clip", project.clip, where));
  check(read(document, "animation", project.animation, where));
  check(readPathJson(document, "target", project.target, where));
  check(read(document, "harmonics", project.harmonics, where));
  check(read(document, "window_s", project.physics.window_s, where));
  std::string terrain = "flat";
  std::vector<std::string> pushes;
  check(read(document, "terrain", terrain, where));
  check(read(document, "pushes", pushes, where));
  if (!status.ok()) return status;
  Result<physics::TerrainSettings> ground = parseTerrain(terrain, "terrain");
  if (!ground.ok()) return Status::error(where + ground.message());
  project.physics.terrain = ground.value();
  for (const std::string& item : pushes) {
    Result<physics::Push> push = parsePush(item, "pushes");
    if (!push.ok()) return Status::error(where + push.message());
    project.physics.pushes.push_back(push.value());
  }
  if (document.contains("joint_harmonics")) {
    const json& joints = document.at("joint_harmonics");
    if (!joints.is_object()) return Status::error(where + "joint_harmonics: expected an object");
    for (const auto& [joint, k] : joints.items()) {
      if (!k.is_number_integer() || k.get<int>() < 0 || k.get<int>() > 64)
        return Status::error(where + "joint_harmonics." + joint +
                             ": expected a whole number 0..64");
      project.joint_k[joint] = k.get<int>();
    }
  }
  if (Status gains = readBandGains(document, where, project.edits); !gains.ok()) return gains;
  // A list of objects under `key`: `each` reads one, given its index and the message prefix.
  auto objects = [&](const char* key, auto each) -> Status {
    if (!document.contains(key)) return Status();
    const json& list = document.at(key);
    if (!list.is_array()) return Status::error(where + key + ": expected a list");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string at = where + key + "[" + std::to_string(i) + "]";
      if (!list[i].is_object()) return Status::error(at + ": expected an object");
      if (Status s = each(list[i], at + "."); !s.ok()) return s;
    }
    return Status();
  };
  Status lists = objects("styles", [&](const json& item, const std::string& in) {
    unknownKeys(item,
                {"label", "neutral", "neutral_encoding", "styled", "styled_encoding", "weight"},
                name, warnings, in.substr(where.size()));
    StylePair pair;
    check(read(item, "label", pair.label, in));
    check(readPathJson(item, "neutral", pair.neutral, in));
    check(readPathJson(item, "styled", pair.styled, in));
    check(read(item, "weight", pair.weight, in));
    if (status.ok() && (pair.neutral.empty() || pair.styled.empty()))
      return Status::error(in + "neutral/styled: both clips are needed");
    project.edits.styles.push_back(pair);
    return Status();
  });
  if (!lists.ok()) return lists;
  lists = objects("secondary", [&](const json& item, const std::string& in) {
    unknownKeys(item, {"joint", "axis", "kind", "frequency_hz", "amplitude_deg", "seed"}, name,
                warnings, in.substr(where.size()));
    SecondaryMotion source;
    std::string kind = "periodic";
    check(read(item, "joint", source.joint, in));
    check(read(item, "axis", source.axis, in));
    check(read(item, "kind", kind, in));
    check(read(item, "frequency_hz", source.frequency_hz, in));
    check(read(item, "amplitude_deg", source.amplitude_deg, in));
    check(read(item, "seed", source.seed, in));
    if (kind != "periodic" && kind != "noise")
      return Status::error(in + "kind: expected \"periodic\" or \"noise\"");
    source.noise = kind == "noise";
    project.edits.secondary.push_back(source);
    return Status();
  });
  if (!lists.ok()) return lists;
  if (document.contains("body")) {
    const json& body = document.at("body");
    if (!body.is_object()) return Status::error(where + "body: expected an object");
    unknownKeys(body, {"masses", "fixed", "hinge_limits"}, name, warnings, "body.");
    std::vector<std::string> masses, fixed, hinge_limits;
    check(read(body, "masses", masses, where + "body."));
    check(read(body, "fixed", fixed, where + "body."));
    check(read(body, "hinge_limits", hinge_limits, where + "body."));
    if (!status.ok()) return status;
    Result<BodyOverrides> overrides = parseBodyOverrides(masses, fixed, hinge_limits);
    if (!overrides.ok()) return Status::error(where + "body: " + overrides.message());
    project.physics.body = std::move(overrides).value();
  }
  check(readSearchAndView(document, where, name, warnings, project));
  if (!status.ok()) return status;

  auto resolve = [&](std::string& file) {
    if (file.empty()) return;
    const std::filesystem::path path(file);
    file = (path.is_absolute() ? path : base / path).lexically_normal().string();
  };
  resolve(project.rig);
  resolve(project.clip);
  resolve(project.target);
  for (StylePair& pair : project.edits.styles) {
    resolve(pair.neutral);
    resolve(pair.styled);
  }
  if (project.rig.empty()) return Status::error(where + "rig: empty (the rig file)");
  if (Status valid = validateProject(project); !valid.ok())
    return Status::error(where + valid.message());
  return project;
}

Result<Project> loadProject(const std::filesystem::path& path, std::vector<std::string>* warnings) {
  Result<std::string> text = readFile(path);
  if (!text.ok()) return text.status();
  return parseProject(text.value(), path.parent_path(), path.string(), warnings);
}

Status validateProject(const Project& project) {
  if (Status valid = project.validate(); !valid.ok()) return valid;
  if (!(project.view.speed >= 0.1 && project.view.speed <= 4.0))
    return Status::error("view.speed: must be 0.1..4");
  return Status();
}

std::string projectJson(const Project& project, const std::filesystem::path& base) {
  json out = json::object();
  out["format"] = "sinew.project";
  out["version"] = kProjectVersion;
  writePathJson(out, "rig", relativeTo(project.rig, base));
  if (!project.clip.empty()) writePathJson(out, "clip", relativeTo(project.clip, base));
  if (!project.animation.empty()) out["animation"] = project.animation;
  if (!project.target.empty()) writePathJson(out, "target", relativeTo(project.target, base));
  out["harmonics"] = project.harmonics;
  if (!project.joint_k.empty()) out["joint_harmonics"] = project.joint_k;
  const MotionEdits& edits = project.edits;
  if (edits.band_gains != MotionEdits().band_gains) {
    json bands = json::object();
    for (int b = 0; b < kBandCount; ++b) {
      for (int g = 0; g < kGroupCount; ++g) {
        bands[kBandNames[b]][kGroupNames[g]] =
            edits.band_gains[static_cast<size_t>(b)][static_cast<size_t>(g)];
      }
    }
    out["band_gains"] = bands;
  }
  if (!edits.styles.empty()) {
    json styles = json::array();
    for (const StylePair& pair : edits.styles) {
      json item = {{"label", pair.label}, {"weight", pair.weight}};
      writePathJson(item, "neutral", relativeTo(pair.neutral, base));
      writePathJson(item, "styled", relativeTo(pair.styled, base));
      styles.push_back(std::move(item));
    }
    out["styles"] = styles;
  }
  if (!edits.secondary.empty()) {
    json secondary = json::array();
    for (const SecondaryMotion& m : edits.secondary) {
      secondary.push_back({{"joint", m.joint},
                           {"axis", m.axis},
                           {"kind", m.noise ? "noise" : "periodic"},
                           {"frequency_hz", m.frequency_hz},
                           {"amplitude_deg", m.amplitude_deg},
                           {"seed", m.seed}});
    }
    out["secondary"] = secondary;
  }
  const PhysicsSettings& physics = project.physics;
  out["terrain"] = terrainText(physics.terrain);
  out["window_s"] = physics.window_s;
  json pushes = json::array();
  for (const physics::Push& push : physics.pushes) pushes.push_back(pushText(push));
  out["pushes"] = pushes;
  json masses = json::array(), hinges = json::array();
  for (const MassOverride& m : physics.body.masses) masses.push_back(massText(m));
  for (const HingeLimitOverride& h : physics.body.hinge_limits) hinges.push_back(hingeLimitText(h));
  out["body"] = {{"masses", masses}, {"fixed", physics.body.fixed}, {"hinge_limits", hinges}};
  const SearchSettings& s = project.search;
  out["search"] = {{"minutes", s.minutes},   {"population", s.population},
                   {"no_prior", s.no_prior}, {"optimizer", search::optimizerName(s.optimizer)},
                   {"seed", s.seed},         {"weights", weightsJson(s.weights)},
                   {"trials", s.trials},     {"trial_push_m_s", s.trial_push_m_s},
                   {"robust_push_m_s", s.robust_push_m_s}, {"restart_after", s.restart_after},
                   {"start_generations", s.start_generations}};
  const ViewSettings& v = project.view;
  out["view"] = {{"speed", v.speed},
                 {"loop", v.loop},
                 {"show_original", v.show_original},
                 {"show_model", v.show_model},
                 {"model_beside", v.model_beside},
                 {"follow", v.follow},
                 {"show_grid", v.show_grid},
                 {"show_end_sites", v.show_end_sites},
                 {"show_population", v.show_population},
                 {"show_ghost", v.show_ghost}};
  // Paths are bytes; JSON is UTF-8: a non-UTF-8 byte is written as U+FFFD, never a crash.
  return out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

Status saveProject(const Project& project, const std::filesystem::path& path) {
  if (Status valid = validateProject(project); !valid.ok())
    return Status::error(path.string() + ": not saved: " + valid.message());
  const std::filesystem::path base = std::filesystem::absolute(path).parent_path();
  return writeFileAtomically(path, projectJson(project, base));
}

Result<physics::TerrainSettings> parseTerrain(const std::string& text, const std::string& field) {
  physics::TerrainSettings t;
  const size_t colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  std::vector<double> values;
  if (colon != std::string::npos) {
    for (const std::string& item : splitCommas(text.substr(colon + 1))) {
      Result<double> value = parseNumber(item, field + " '" + text + "'");
      if (!value.ok()) return value.status();
      values.push_back(value.value());
    }
  }
  auto want = [&](size_t most) -> Status {
    if (values.size() > most)
      return Status::error(field + " " + kind + ": at most " + std::to_string(most) +
                           " values, got " + std::to_string(values.size()));
    return Status();
  };
  using Kind = physics::TerrainSettings::Kind;
  if (kind == "flat") {
    if (Status s = want(0); !s.ok()) return s;
  } else if (kind == "slope") {
    if (Status s = want(1); !s.ok()) return s;
    t.kind = Kind::kSlope;
    if (!values.empty()) t.slope_deg = values[0];
  } else if (kind == "steps") {
    if (Status s = want(2); !s.ok()) return s;
    t.kind = Kind::kSteps;
    if (values.size() > 0) t.step_height_m = values[0];
    if (values.size() > 1) t.step_depth_m = values[1];
  } else if (kind == "rough") {
    if (Status s = want(2); !s.ok()) return s;
    t.kind = Kind::kRough;
    if (values.size() > 0) t.amplitude_m = values[0];
    if (values.size() > 1) {
      if (values[1] < 0.0 ||
          values[1] != static_cast<double>(static_cast<std::uint64_t>(values[1])))
        return Status::error(field + " rough: the seed must be a whole number >= 0");
      t.seed = static_cast<std::uint64_t>(values[1]);
    }
  } else {
    return Status::error(field + ": unknown kind '" + kind +
                         "' (flat, slope:DEG, steps:HEIGHT,DEPTH, rough:AMPLITUDE,SEED)");
  }
  if (Status s = t.validate(); !s.ok()) return Status::error(field + ": " + s.message());
  return t;
}

Result<physics::Push> parsePush(const std::string& text, const std::string& field) {
  const std::vector<std::string> parts = splitCommas(text);
  if (parts.size() != 4 && parts.size() != 5)
    return Status::error(field + " '" + text + "': expected TIME,X,Y,Z[,LINK] (seconds, N s)");
  double v[4];
  for (size_t i = 0; i < 4; ++i) {
    Result<double> value = parseNumber(parts[i], field + " '" + text + "'");
    if (!value.ok()) return value.status();
    v[i] = value.value();
  }
  physics::Push push;
  push.time_s = v[0];
  push.impulse_ns = glm::dvec3(v[1], v[2], v[3]);
  if (parts.size() == 5) push.link = parts[4];
  return push;
}

search::ControllerFile resultsMeta(const pipeline::ProjectSettings& settings,
                                   const search::EvolveSettings& used) {
  search::ControllerFile meta;
  meta.terrain = terrainText(settings.physics.terrain);
  meta.seed = used.seed;
  meta.optimizer = search::optimizerName(used.optimizer);
  meta.no_prior = settings.search.no_prior;
  meta.rig = settings.rig;
  meta.clip = settings.clip.empty() ? settings.rig : settings.clip;
  return meta;
}

std::string settingsJson(const pipeline::ProjectSettings& settings) {
  Project project;
  static_cast<pipeline::ProjectSettings&>(project) = settings;
  return projectJson(project, {});
}

std::string numberText(double value) {
  char text[64];
  const std::to_chars_result written = std::to_chars(text, text + sizeof text, value);
  return std::string(text, written.ptr);
}

std::string terrainText(const physics::TerrainSettings& t) {
  using Kind = physics::TerrainSettings::Kind;
  switch (t.kind) {
    case Kind::kFlat:
      return "flat";
    case Kind::kSlope:
      return "slope:" + numberText(t.slope_deg);
    case Kind::kSteps:
      return "steps:" + numberText(t.step_height_m) + "," + numberText(t.step_depth_m);
    case Kind::kRough:
      return "rough:" + numberText(t.amplitude_m) + "," + std::to_string(t.seed);
  }
  return "flat";
}

std::string pushText(const physics::Push& push) {
  std::string text = numberText(push.time_s) + "," + numberText(push.impulse_ns.x) + "," +
                     numberText(push.impulse_ns.y) + "," + numberText(push.impulse_ns.z);
  if (!push.link.empty()) text += "," + push.link;
  return text;
}

std::string massText(const MassOverride& mass) {
  return mass.link + "=" + numberText(mass.kg);
}

std::string hingeLimitText(const HingeLimitOverride& limit) {
  return limit.link + "=" + numberText(limit.lo_deg) + "," + numberText(limit.hi_deg);
}

Result<BodyOverrides> parseBodyOverrides(const std::vector<std::string>& masses,
                                         const std::vector<std::string>& fixed,
                                         const std::vector<std::string>& hinge_limits) {
  BodyOverrides body;
  auto split = [](const std::string& text,
                  const char* flag) -> Result<std::pair<std::string, std::string>> {
    const size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
      return Status::error(std::string(flag) + " '" + text + "': expected NAME=VALUE");
    return std::make_pair(text.substr(0, eq), text.substr(eq + 1));
  };
  for (const std::string& m : masses) {
    auto parts = split(m, "--mass");
    if (!parts.ok()) return parts.status();
    Result<double> kg = parseNumber(parts.value().second, "--mass '" + m + "'");
    if (!kg.ok()) return kg.status();
    body.masses.push_back({parts.value().first, kg.value()});
  }
  body.fixed = fixed;
  for (const std::string& h : hinge_limits) {
    auto parts = split(h, "--hinge-limits");
    if (!parts.ok()) return parts.status();
    const std::vector<std::string> range = splitCommas(parts.value().second);
    if (range.size() != 2) return Status::error("--hinge-limits '" + h + "': expected NAME=LO,HI");
    Result<double> lo = parseNumber(range[0], "--hinge-limits '" + h + "'");
    Result<double> hi = parseNumber(range[1], "--hinge-limits '" + h + "'");
    if (!lo.ok()) return lo.status();
    if (!hi.ok()) return hi.status();
    body.hinge_limits.push_back({parts.value().first, lo.value(), hi.value()});
  }
  if (Result<physics::BodyPlanSettings> valid = body.planSettings(); !valid.ok())
    return valid.status();
  return body;
}

}  // namespace sinew::app
