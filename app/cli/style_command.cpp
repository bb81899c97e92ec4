// sinew style: measure a style from a neutral and a styled clip and apply it (to the neutral or
// another clip of the skeleton) at a weight, or measure which style a clip is closest to.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "sinew/core/file_io.h"
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
  loaded.target = spectral::targetFromSpectrum(spectrum.value(), {},
                                               std::filesystem::path(path).stem().string());
  return loaded;
}

int runTransfer(const StyleArgs& args) {
  if (args.styled.empty() || args.output.empty()) {
    return fail("style: --neutral needs --styled and -o (or use --measure CLIP --library ...)");
  }
  Result<Loaded> neutral = loadTarget(args.neutral, args.import);
  if (!neutral.ok()) return fail(neutral.message());
  Result<Loaded> styled = loadTarget(args.styled, args.import);
  if (!styled.ok()) return fail(styled.message());
  const std::string label =
      args.label.empty() ? std::filesystem::path(args.styled).stem().string() : args.label;
  Result<spectral::StyleVector> style =
      spectral::measureStyle(neutral.value().target, styled.value().target, label);
  if (!style.ok()) return fail(style.message());
  Result<Loaded> applied_to = args.apply_to.empty() ? std::move(neutral)
                                                     : loadTarget(args.apply_to, args.import);
  if (!applied_to.ok()) return fail(applied_to.message());
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

int runMeasure(const StyleArgs& args) {
  if (args.library.empty()) return fail("style --measure needs --library FILE... (label=path)");
  Result<Loaded> clip = loadTarget(args.measure, args.import);
  if (!clip.ok()) return fail(clip.message());
  std::vector<std::pair<std::string, spectral::TargetMotion>> library;
  for (const std::string& entry : args.library) {
    const size_t equals = entry.find('=');
    const std::string path = equals == std::string::npos ? entry : entry.substr(equals + 1);
    const std::string label = equals == std::string::npos
                                  ? std::filesystem::path(entry).stem().string()
                                  : entry.substr(0, equals);
    Result<Loaded> loaded = loadTarget(path, args.import);
    if (!loaded.ok()) return fail(loaded.message());
    library.emplace_back(label, std::move(loaded.value().target));
  }
  Result<spectral::StyleScores> scores =
      spectral::scoreStyle(clip.value().asset.skeleton, clip.value().target, library);
  if (!scores.ok()) return fail(scores.message());
  nlohmann::json json_scores = nlohmann::json::object();
  for (const auto& [label, score] : scores.value().scores) {
    std::printf("%-20s %.3f\n", label.c_str(), score);
    json_scores[label] = score;
  }
  std::printf("closest: %s\n", scores.value().closest.c_str());
  if (!args.json_path.empty()) {
    const nlohmann::json json = {{"clip", args.measure},
                                 {"closest", scores.value().closest},
                                 {"scores", json_scores}};
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
  command->add_option("--neutral", args->neutral, "The neutral clip the style is measured from");
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
  command->add_option("--library", args->library, "Labelled clips to measure against: label=path or path");
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
