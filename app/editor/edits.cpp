// The Style panel's model: band gains, styles and secondary motion applied to the harmonic model.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "editor/editor_state.h"
#include "sinew/spectral/bands.h"
#include "sinew/spectral/secondary.h"

namespace sinew::editor {
namespace {

// Harmonics kept per joint when clips are analysed for style work (as `sinew style` does).
constexpr int kStyleHarmonics = 10;

Result<spectral::TargetMotion> styleTarget(const std::string& path,
                                           const motion::Skeleton& skeleton) {
  Result<motion::MotionAsset> asset = motion::importMotion(path);
  if (!asset.ok()) return asset.status();
  if (asset.value().clips.empty()) return Status::error(path + ": no animation");
  if (asset.value().skeleton.names != skeleton.names)
    return Status::error(path + ": its skeleton is not the open clip's (the joints differ)");
  spectral::AnalysisSettings settings;
  settings.harmonics = kStyleHarmonics;
  Result<spectral::MotionSpectrum> spectrum =
      spectral::analyze(asset.value().skeleton, asset.value().clips.front(), settings);
  if (!spectrum.ok()) return Status::error(path + ": " + spectrum.message());
  return spectral::targetFromSpectrum(spectrum.value(), {},
                                      std::filesystem::path(path).stem().string());
}

}  // namespace

const Result<spectral::StyleVector>& styleOf(EditorState& state, const app::StylePair& pair) {
  const std::string key = pair.neutral + "|" + pair.styled;
  auto found = state.style_cache.find(key);
  if (found == state.style_cache.end()) {
    auto measure = [&]() -> Result<spectral::StyleVector> {
      if (!state.asset) return Status::error("open a clip first");
      Result<spectral::TargetMotion> neutral = styleTarget(pair.neutral, state.asset->skeleton);
      if (!neutral.ok()) return neutral.status();
      Result<spectral::TargetMotion> styled = styleTarget(pair.styled, state.asset->skeleton);
      if (!styled.ok()) return styled.status();
      return spectral::measureStyle(neutral.value(), styled.value(), pair.label);
    };
    found = state.style_cache
                .emplace(key, std::make_shared<const Result<spectral::StyleVector>>(measure()))
                .first;
  }
  return *found->second;
}

bool addStyle(EditorState& state, const std::string& neutral, const std::string& styled,
              const std::string& label) {
  app::StylePair pair;
  pair.neutral = neutral;
  pair.styled = styled;
  pair.label = label.empty() ? std::filesystem::path(styled).stem().string() : label;
  pair.weight = 1.0;
  const Result<spectral::StyleVector>& style = styleOf(state, pair);
  if (!style.ok()) {
    state.log.error("style '" + pair.label + "': " + style.message());
    state.style_cache.erase(neutral + "|" + styled);  // a fixed file can be tried again
    return false;
  }
  state.edits.styles.push_back(pair);
  char line[200];
  std::snprintf(line, sizeof line, "style '%s': tempo x%.3f; applied at weight 1",
                pair.label.c_str(), std::exp(style.value().log_tempo));
  state.log.info(line);
  applyEdits(state);
  return true;
}

bool applyEdits(EditorState& state) {
  if (!state.analysis || !state.asset) return false;
  AnalysisState& analysis = *state.analysis;
  if (analysis.applied == state.edits) return false;  // rebuildModel resets `applied`
  const motion::Skeleton& skeleton = state.asset->skeleton;
  spectral::TargetMotion target = analysis.model;
  const app::MotionEdits& edits = state.edits;
  if (edits.band_gains != app::MotionEdits().band_gains) {
    spectral::BandGains gains;
    for (size_t b = 0; b < gains.gains.size() && b < edits.band_gains.size(); ++b) {
      for (size_t g = 0; g < gains.gains[b].size(); ++g) gains.gains[b][g] = edits.band_gains[b][g];
    }
    if (Status valid = gains.validate(); valid.ok()) {
      target = spectral::applyBandGains(target, skeleton, gains);
    } else {
      state.log.error("band gains: " + valid.message());
    }
  }
  std::vector<std::pair<const spectral::StyleVector*, double>> styles;
  for (const app::StylePair& pair : edits.styles) {
    const Result<spectral::StyleVector>& style = styleOf(state, pair);
    if (!style.ok()) {
      if (!(analysis.applied == edits))
        state.log.error("style '" + pair.label + "': " + style.message());
      continue;
    }
    if (pair.weight != 0.0) styles.emplace_back(&style.value(), pair.weight);
  }
  if (!styles.empty()) {
    Result<spectral::TargetMotion> styled = spectral::applyStyles(target, styles);
    if (styled.ok()) {
      target = std::move(styled).value();
    } else {
      state.log.error("styles: " + styled.message());
    }
  }
  if (!edits.secondary.empty()) {
    spectral::SecondarySettings settings;
    for (const app::SecondaryMotion& m : edits.secondary) {
      spectral::SecondarySource source;
      source.kind = m.noise ? spectral::SecondarySource::Kind::kNoise
                            : spectral::SecondarySource::Kind::kPeriodic;
      source.joint = m.joint;
      source.axis = m.axis;
      source.frequency_hz = m.frequency_hz;
      source.amplitude_deg = m.amplitude_deg;
      source.seed = m.seed;
      settings.sources.push_back(source);
    }
    Result<spectral::TargetMotion> moved = spectral::addSecondaryMotion(target, skeleton, settings);
    if (moved.ok()) {
      target = std::move(moved).value();
    } else {
      state.log.error("secondary motion: " + moved.message());
    }
  }
  analysis.target = std::move(target);
  analysis.applied = edits;
  return true;
}

Result<spectral::StyleScores> measureClipStyle(EditorState& state) {
  const motion::Clip* clip = state.clip();
  if (clip == nullptr) return Status::error("open a clip first");
  if (state.edits.styles.empty()) return Status::error("add a style pair first: it is the library");
  spectral::AnalysisSettings settings;
  settings.harmonics = kStyleHarmonics;
  Result<spectral::MotionSpectrum> spectrum =
      spectral::analyze(state.asset->skeleton, *clip, settings);
  if (!spectrum.ok()) return spectrum.status();
  const spectral::TargetMotion current =
      spectral::targetFromSpectrum(spectrum.value(), {}, clip->name);
  std::vector<std::pair<std::string, spectral::TargetMotion>> library;
  for (const app::StylePair& pair : state.edits.styles) {
    if (library.empty()) {
      Result<spectral::TargetMotion> neutral = styleTarget(pair.neutral, state.asset->skeleton);
      if (!neutral.ok()) return neutral.status();
      library.emplace_back("neutral", std::move(neutral).value());
    }
    Result<spectral::TargetMotion> styled = styleTarget(pair.styled, state.asset->skeleton);
    if (!styled.ok()) return styled.status();
    library.emplace_back(pair.label, std::move(styled).value());
  }
  return spectral::scoreStyle(state.asset->skeleton, current, library);
}

}  // namespace sinew::editor
