// sinew style: measure a style from a neutral and a styled clip and apply it (to the neutral or
// another clip of the skeleton) at a weight, or measure which style a clip is closest to.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "sinew/core/file_io.h"
#include "sinew/core/text.h"
#include "sinew/spectral/style.h"
#include "sinew/spectral/target_io.h"

namespace sinew::app {
namespace {

// Harmonics kept per joint when targets are built for style work: enough for a style's detail.
constexpr int kStyleHarmonics = 10;

struct StyleArgs {
  std::string neutral;
  std::string styled;
  std::string apply_to;
  std::string label;
  double weight = 1.0;
  std::string output;
  double fps = 0.0;
  int strides = 4;
  std::string measure;
  std::vector<std::string> library;
  std::string json_path;
  ImportFlags import;
};

// A label or clip name from a file name: paths are bytes, labels are text (shown, written in JSON).
std::string stemLabel(const std::filesystem::path& path) {
  return toUtf8(path.stem().string());
}

struct Loaded {
  motion::MotionAsset asset;
  spectral::TargetMotion target;
};

Result<Loaded> loadTarget(const std::string& path, const ImportFlags& flags) {
  Result<motion::ImportOptions> options = flags.options();
  if (!options.ok()) return options.status();
  Result<motion::MotionAsset> asset = motion::importMotion(path, options.value());
  if (!asset.ok()) return asset.status();
  Result<int> clip = selectClip(asset.value(), "");
  if (!clip.ok()) return clip.status();
  spectral::AnalysisSettings settings;
  settings.harmonics = kStyleHarmonics;
  Result<spectral::MotionSpectrum> spectrum =
      spectral::analyze(asset.value().skeleton, asset.value().clips[clip.value()], settings);
  if (!spectrum.ok()) return Status::error(path + ": " + spectrum.message());
  Loaded loaded{std::move(asset).value(), {}};
  loaded.target = spectral::targetFromSpectrum(spectrum.value(), {}, stemLabel(path));
  return loaded;
}

// `path`'s skeleton must be `reference`'s (from `reference_path`) by joint names and hierarchy.
Status matchJoints(const motion::Skeleton& reference, const std::string& reference_path,
                   const motion::Skeleton& skeleton, const std::string& path) {
  Status status = spectral::sameJoints(reference, skeleton);
  if (status.ok()) return status;
  return Status::error(path + ": not the skeleton of " + reference_path + ": " + status.message());
}

int runTransfer(const StyleArgs& args) {
  if (args.styled.empty() || args.output.empty()) {
    return fail("style: --neutral needs --styled and -o (or use --measure CLIP --library ...)");
  }
  Result<Loaded> neutral = loadTarget(args.neutral, args.import);
  if (!neutral.ok()) return fail(neutral.message());
  Result<Loaded> styled = loadTarget(args.styled, args.import);
  if (!styled.ok()) return fail(styled.message());
  if (Status status = matchJoints(neutral.value().asset.skeleton, args.neutral,
                                  styled.value().asset.skeleton, args.styled);
      !status.ok()) {
    return fail(status.message());
  }
  const std::string label = args.label.empty() ? stemLabel(args.styled) : toUtf8(args.label);
  Result<spectral::StyleVector> style =
      spectral::measureStyle(neutral.value().target, styled.value().target, label);
  if (!style.ok()) return fail(style.message());
  Result<Loaded> applied_to = args.apply_to.empty() ? std::move(neutral)
                                                     : loadTarget(args.apply_to, args.import);
  if (!applied_to.ok()) return fail(applied_to.message());
  if (Status status = matchJoints(styled.value().asset.skeleton, args.styled,
                                  applied_to.value().asset.skeleton,
                                  args.apply_to.empty() ? args.neutral : args.apply_to);
      !status.ok()) {
    return fail(status.message());
  }
  const motion::MotionAsset& asset = applied_to.value().asset;
  Result<spectral::TargetMotion> result =
      spectral::applyStyles(applied_to.value().target, {{&style.value(), args.weight}});
  if (!result.ok()) return fail(result.message());
  spectral::TargetMotion target = std::move(result).value();
  target.name = applied_to.value().target.name + "_" + label;
  std::printf("style '%s' (weight %.2f): stride %.3f s -> %.3f s; pose change %.2f deg RMS\n",
              label.c_str(), args.weight, applied_to.value().target.period(), target.period(),
              spectral::poseDistanceDeg(applied_to.value().target, target));
  Status status;
  if (std::filesystem::path(args.output).extension() == ".json") {
    status = spectral::saveTarget(args.output, target, asset.skeleton);
  } else {
    const double fps = args.fps > 0.0 ? args.fps : asset.clips.front().fps();
    status = motion::exportMotion(args.output, asset, target.sample(fps, args.strides));
  }
  if (!status.ok()) return fail(status.message());
  std::printf("wrote %s\n", args.output.c_str());
  return 0;
}

// One library entry as given: a styled file, and the neutral of its actor when the entry is a
// pair (label=NEUTRAL,STYLED) or comes from a folder with a neutral.
struct EntrySpec {
  std::string label;
  std::string neutral;  // empty: no neutral
  std::string styled;
};

bool isMotionFile(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".bvh" || ext == ".glb" || ext == ".gltf";
}

// A folder's label for a file: its stem without a trailing take number ("happy_02" -> "happy").
std::string labelOf(const std::filesystem::path& path) {
  const std::string stem = stemLabel(path);
  size_t end = stem.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(stem[end - 1]))) --end;
  while (end > 0 && (stem[end - 1] == '_' || stem[end - 1] == '-')) --end;
  return end > 0 ? stem.substr(0, end) : stem;
}

// --library arguments as entries: label=NEUTRAL,STYLED, label=FILE, FILE, or FOLDER (whose
// neutral.* file, if any, is every other file's neutral; labels from the file names).
Result<std::vector<EntrySpec>> parseLibrary(const std::vector<std::string>& arguments) {
  std::vector<EntrySpec> entries;
  for (const std::string& argument : arguments) {
    const size_t equals = argument.find('=');
    const std::string value = equals == std::string::npos ? argument : argument.substr(equals + 1);
    const std::string label = equals == std::string::npos ? "" : toUtf8(argument.substr(0, equals));
    if (equals != std::string::npos && label.empty()) {
      return Status::error("--library '" + argument + "': the label before '=' is empty");
    }
    if (const size_t comma = value.find(','); comma != std::string::npos) {
      if (label.empty()) return Status::error("--library '" + argument + "': a pair needs a label (label=NEUTRAL,STYLED)");
      const std::string neutral = value.substr(0, comma);
      const std::string styled = value.substr(comma + 1);
      if (neutral.empty() || styled.empty() || styled.find(',') != std::string::npos) {
        return Status::error("--library '" + argument + "': expected label=NEUTRAL,STYLED");
      }
      entries.push_back({label, neutral, styled});
      continue;
    }
    std::error_code error;
    if (std::filesystem::is_directory(value, error)) {
      std::vector<std::filesystem::path> files;
      for (const auto& item : std::filesystem::directory_iterator(value, error)) {
        if (item.is_regular_file() && isMotionFile(item.path())) files.push_back(item.path());
      }
      std::sort(files.begin(), files.end());
      std::string neutral;
      for (const auto& file : files) {
        if (file.stem() == "neutral") neutral = file.string();
      }
      size_t before = entries.size();
      for (const auto& file : files) {
        if (file.string() == neutral) continue;
        entries.push_back({label.empty() ? labelOf(file) : label, neutral, file.string()});
      }
      if (entries.size() == before) return Status::error(value + ": no styled motion files in the folder");
      continue;
    }
    entries.push_back({label.empty() ? stemLabel(value) : label, "", value});
  }
  return entries;
}

// Loads each file once: neutrals are shared by many pairs.
class TargetCache {
 public:
  explicit TargetCache(const ImportFlags& flags) : flags_(flags) {}
  Result<const Loaded*> get(const std::string& path) {
    for (const auto& [known, loaded] : loaded_) {
      if (known == path) return loaded.get();
    }
    Result<Loaded> loaded = loadTarget(path, flags_);
    if (!loaded.ok()) return loaded.status();
    loaded_.emplace_back(path, std::make_unique<Loaded>(std::move(loaded).value()));
    return loaded_.back().second.get();
  }

 private:
  const ImportFlags& flags_;
  std::vector<std::pair<std::string, std::unique_ptr<Loaded>>> loaded_;
};

int runMeasure(const StyleArgs& args) {
  if (args.library.empty()) {
    return fail("style --measure needs --library ENTRY... (label=NEUTRAL,STYLED, label=FILE, FILE or FOLDER)");
  }
  Result<std::vector<EntrySpec>> specs = parseLibrary(args.library);
  if (!specs.ok()) return fail(specs.message());
  TargetCache cache(args.import);
  Result<const Loaded*> clip = cache.get(args.measure);
  if (!clip.ok()) return fail(clip.message());
  const motion::Skeleton& skeleton = clip.value()->asset.skeleton;
  const auto load = [&](const std::string& path) -> Result<const Loaded*> {
    Result<const Loaded*> loaded = cache.get(path);
    if (!loaded.ok()) return loaded;
    if (Status status = matchJoints(skeleton, args.measure, loaded.value()->asset.skeleton, path);
        !status.ok()) {
      return status;
    }
    return loaded;
  };
  Result<spectral::StyleScores> scores = Status::error("no library");
  const bool relative = !args.neutral.empty();
  if (relative) {
    Result<const Loaded*> neutral = load(args.neutral);
    if (!neutral.ok()) return fail(neutral.message());
    std::vector<spectral::StyleExample> library;
    for (const EntrySpec& spec : specs.value()) {
      if (spec.neutral.empty()) {
        return fail("--library '" + spec.styled + "' has no neutral; with --neutral every entry is "
                    "a pair label=NEUTRAL,STYLED or a folder with a neutral.* file");
      }
      Result<const Loaded*> n = load(spec.neutral);
      if (!n.ok()) return fail(n.message());
      Result<const Loaded*> st = load(spec.styled);
      if (!st.ok()) return fail(st.message());
      library.push_back({spec.label, n.value()->target, st.value()->target});
    }
    scores = spectral::scoreStyleRelative(skeleton, clip.value()->target, neutral.value()->target, library);
  } else {
    std::vector<std::pair<std::string, spectral::TargetMotion>> library;
    for (const EntrySpec& spec : specs.value()) {
      Result<const Loaded*> st = load(spec.styled);
      if (!st.ok()) return fail(st.message());
      library.emplace_back(spec.label, st.value()->target);
    }
    scores = spectral::scoreStyle(skeleton, clip.value()->target, library);
  }
  if (!scores.ok()) return fail(scores.message());
  const spectral::StyleScores& result = scores.value();
  std::printf("style of %s, %s\n", args.measure.c_str(),
              relative ? ("relative to " + args.neutral).c_str() : "absolute (no --neutral)");
  nlohmann::json json_scores = nlohmann::json::object();
  nlohmann::json json_labels = nlohmann::json::array();
  for (size_t n = 0; n < result.scores.size(); ++n) {
    const auto& [label, score] = result.scores[n];
    std::printf("%-20s %.3f  (distance %.2f, %d example%s)\n", label.c_str(), score,
                result.distances[n], result.examples[n], result.examples[n] == 1 ? "" : "s");
    json_scores[label] = score;
    json_labels.push_back({{"label", label}, {"score", score}, {"distance", result.distances[n]},
                           {"examples", result.examples[n]}});
  }
  std::printf("closest: %s\n", result.closest.c_str());
  if (!args.json_path.empty()) {
    nlohmann::json json = {{"clip", args.measure},
                           {"relative", relative},
                           {"closest", result.closest},
                           {"scores", json_scores},
                           {"labels", json_labels}};
    if (relative) json["neutral"] = args.neutral;
    Status status = writeFileAtomically(args.json_path, json.dump(2) + "\n");
    if (!status.ok()) return fail(status.message());
  }
  return 0;
}

}  // namespace

void addStyleCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<StyleArgs>();
  CLI::App* command = app.add_subcommand(
      "style", "Transfer a style (--neutral A --styled B [--apply-to C] -o OUT) or measure one "
               "(--measure CLIP --library [label=]FILE...)");
  command->add_option("--neutral", args->neutral,
                      "The neutral clip the style is measured from; with --measure, the measured "
                      "clip's own actor's neutral (the style is then its difference from it)");
  command->add_option("--styled", args->styled, "The styled clip (same action and skeleton)");
  command->add_option("--apply-to", args->apply_to, "Apply the style to this clip (default: the neutral)");
  command->add_option("--label", args->label, "The style's name (default: the styled file's stem)");
  command->add_option("--weight", args->weight, "0 = unchanged, 1 = the style, 2 = exaggerated, -1 = removed")
      ->check(CLI::Range(-1.0, 2.0));
  command->add_option("-o,--output", args->output, "Result: .bvh/.glb/.gltf (sampled) or .json (coefficients)");
  command->add_option("--fps", args->fps, "Frame rate of a sampled result (default: the clip's)")
      ->check(CLI::Range(1.0, 1000.0));
  command->add_option("--strides", args->strides, "Strides in a sampled result")->check(CLI::Range(1, 1000));
  command->add_option("--measure", args->measure, "The clip whose style to measure");
  command->add_option("--library", args->library,
                      "Styles to measure against: label=NEUTRAL,STYLED (a pair of one actor), "
                      "label=FILE, FILE, or a FOLDER (its neutral.* is the others' neutral; labels "
                      "from the file names, take numbers dropped); a label may have several examples");
  command->add_option("--json", args->json_path, "With --measure: also write closest and scores as JSON");
  command->callback([args, &exit_code]() {
    if (!args->measure.empty()) {
      exit_code = runMeasure(*args);
    } else if (!args->neutral.empty()) {
      exit_code = runTransfer(*args);
    } else {
      exit_code = fail("style: give --neutral A --styled B -o OUT, or --measure CLIP --library FILES");
    }
  });
}

}  // namespace sinew::app
