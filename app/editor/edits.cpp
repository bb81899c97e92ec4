// The Style panel's model: band gains, styles and secondary motion applied to the harmonic model
// (pipeline::applyMotionEdits, shared with `sinew evolve PROJECT`), with the measured styles
// cached.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "editor/editor_state.h"
#include "sinew/pipeline/pipeline.h"

namespace sinew::editor {

const Result<spectral::StyleVector>& styleOf(EditorState& state, const app::StylePair& pair) {
  const std::string key = pair.neutral + "|" + pair.styled;
  auto found = state.style_cache.find(key);
  if (found == state.style_cache.end()) {
    Result<spectral::StyleVector> measured =
        state.asset ? pipeline::measureStylePair(pair, state.asset->skeleton)
                    : Result<spectral::StyleVector>(Status::error("open a clip first"));
    found = state.style_cache
                .emplace(key,
                         std::make_shared<const Result<spectral::StyleVector>>(std::move(measured)))
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
  std::snprintf(line, sizeof line, "style '%s': stride x%.3f; applied at weight 1",
                pair.label.c_str(), std::exp(-style.value().log_tempo));
  state.log.info(line);
  applyEdits(state);
  return true;
}

bool applyEdits(EditorState& state) {
  if (!state.analysis || !state.asset) return false;
  AnalysisState& analysis = *state.analysis;
  if (analysis.applied == state.edits) return false;  // rebuildModel resets `applied`
  std::vector<const spectral::StyleVector*> styles;
  for (const app::StylePair& pair : state.edits.styles) {
    const Result<spectral::StyleVector>& style = styleOf(state, pair);
    if (!style.ok())
      state.log.error("style '" + pair.label + "': " + style.message() + " (left out)");
    styles.push_back(style.ok() ? &style.value() : nullptr);
  }
  Result<spectral::TargetMotion> edited =
      pipeline::applyMotionEdits(analysis.model, state.asset->skeleton, state.edits, styles);
  if (edited.ok()) {
    analysis.target = std::move(edited).value();
  } else {
    state.log.error("edits: " + edited.message() + " (the model is shown without them)");
    analysis.target = analysis.model;
  }
  analysis.applied = state.edits;
  return true;
}

Result<spectral::StyleScores> measureClipStyle(EditorState& state) {
  const motion::Clip* clip = state.clip();
  if (clip == nullptr) return Status::error("open a clip first");
  if (state.edits.styles.empty()) return Status::error("add a style pair first: it is the library");
  const motion::Skeleton& skeleton = state.asset->skeleton;
  Result<spectral::TargetMotion> current = pipeline::styleTarget(skeleton, *clip, state.file_name);
  if (!current.ok()) return current.status();
  std::vector<std::pair<std::string, spectral::TargetMotion>> library;
  for (const app::StylePair& pair : state.edits.styles) {
    if (library.empty()) {
      Result<spectral::TargetMotion> neutral = pipeline::styleClipTarget(pair.neutral, skeleton);
      if (!neutral.ok()) return neutral.status();
      library.emplace_back("neutral", std::move(neutral).value());
    }
    Result<spectral::TargetMotion> styled = pipeline::styleClipTarget(pair.styled, skeleton);
    if (!styled.ok()) return styled.status();
    library.emplace_back(pair.label, std::move(styled).value());
  }
  return spectral::scoreStyle(skeleton, current.value(), library);
}

}  // namespace sinew::editor
