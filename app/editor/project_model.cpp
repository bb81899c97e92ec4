#include "editor/project_model.h"

#include <algorithm>
#include <map>

#include "sinew/core/file_io.h"
#include "sinew/pipeline/pipeline.h"

namespace sinew::editor {
namespace {

// The K most joints have: the project's "harmonics", so that only exceptions are listed.
int commonK(const std::vector<int>& joint_k, int fallback) {
  std::map<int, int> counts;
  for (int k : joint_k) ++counts[k];
  int best = fallback, best_count = 0;
  for (const auto& [k, count] : counts) {
    if (count > best_count) {
      best = k;
      best_count = count;
    }
  }
  return std::clamp(best, 1, 64);
}

std::string wantedFile(const app::Project& project) {
  return project.clip.empty() ? project.rig : project.clip;
}

}  // namespace

app::Project captureProject(const EditorState& state) {
  app::Project project;
  project.harmonics = state.saved.harmonics;
  if (state.asset) {
    if (state.rig_path.empty()) {
      project.rig = state.file_path.string();
    } else {
      project.rig = state.rig_path;
      project.clip = state.file_path.string();
    }
    const motion::Clip* clip = state.clip();
    if (clip != nullptr && state.asset->clips.size() > 1) project.animation = clip->name;
  }
  project.target = state.target_path;
  if (state.analysis && state.asset) {
    const std::vector<int>& joint_k = state.analysis->joint_k;
    project.harmonics = commonK(joint_k, project.harmonics);
    for (size_t j = 0; j < joint_k.size(); ++j) {
      if (joint_k[j] != project.harmonics) {
        project.joint_k[state.asset->skeleton.names[j]] = joint_k[j];
      }
    }
  }
  project.edits = state.edits;
  project.physics = state.evolution.settings.physics;
  project.search = state.evolution.settings.search;
  app::ViewSettings& v = project.view;
  v.speed = state.playback.speed;
  v.loop = state.playback.loop;
  v.show_original = state.view.show_original;
  v.show_model = state.view.show_model;
  v.model_beside = state.view.model_beside;
  v.follow = state.view.follow;
  v.show_grid = state.view.show_grid;
  v.show_end_sites = state.view.show_end_sites;
  v.show_population = state.evolution.show_population;
  v.show_ghost = state.evolution.show_ghost;
  return project;
}

bool applyProject(EditorState& state, const app::Project& project) {
  const std::string file = wantedFile(project);
  if (!file.empty() && (!state.asset || std::filesystem::path(file) != state.file_path)) {
    if (!openFile(state, file, project.animation)) return false;
  } else if (state.asset && !project.animation.empty()) {
    const int index = state.asset->findClip(project.animation);
    if (index < 0) {
      state.log.warning(file + ": no animation called '" + project.animation + "'; keeping '" +
                        (state.clip() ? state.clip()->name : std::string()) + "'");
    } else if (index != state.clip_index) {
      chooseClip(state, index);
    }
  }
  state.rig_path = project.clip.empty() ? std::string() : project.rig;
  state.target_path = project.target;

  if (state.analysis && state.asset) {
    // As `sinew evolve` resolves them: a joint the rig does not have is an error naming it.
    Result<std::vector<int>> joint_k = pipeline::resolveJointK(
        state.asset->skeleton, project.harmonics, project.joint_k, state.file_name);
    if (!joint_k.ok()) {
      state.log.error(joint_k.message() + " (K per joint not applied)");
    } else if (joint_k.value() != state.analysis->joint_k) {
      setJointK(state, std::move(joint_k).value());
    }
  }

  state.edits = project.edits;
  applyEdits(state);
  EvolutionSettings& e = state.evolution.settings;
  const bool weights_changed = !(e.search.weights == project.search.weights);
  e.physics = project.physics;
  e.search = project.search;
  if (weights_changed && state.evolution.session && !state.evolution.session->finished()) {
    setEvolutionWeights(state);
  }
  const app::ViewSettings& v = project.view;
  state.playback.speed = v.speed;
  state.playback.loop = v.loop;
  state.view.show_original = v.show_original;
  state.view.show_model = v.show_model;
  state.view.model_beside = v.model_beside;
  state.view.follow = v.follow;
  state.view.show_grid = v.show_grid;
  state.view.show_end_sites = v.show_end_sites;
  state.evolution.show_population = v.show_population;
  state.evolution.show_ghost = v.show_ghost;
  return true;
}

bool openProject(EditorState& state, const std::filesystem::path& path) {
  std::vector<std::string> warnings;
  Result<app::Project> project = app::loadProject(path, &warnings);
  if (!project.ok()) {
    state.log.error(project.message());
    return false;
  }
  for (std::string& warning : warnings) state.log.warning(std::move(warning));
  if (!applyProject(state, project.value())) {
    state.log.error(path.string() +
                    ": the project's files did not open (see above); nothing changed");
    return false;
  }
  state.project_path = path;
  state.saved = captureProject(state);
  state.history.reset(state.saved);
  rememberRecent(state, path.string());
  state.log.info("opened project " + path.string());
  return true;
}

bool saveProjectAs(EditorState& state, const std::filesystem::path& path) {
  const app::Project project = captureProject(state);
  if (project.rig.empty()) {
    state.log.error("save: open a rig first (a project names its rig)");
    return false;
  }
  if (Status saved = app::saveProject(project, path); !saved.ok()) {
    state.log.error("save: " + saved.message());
    return false;
  }
  state.project_path = path;
  state.saved = project;
  rememberRecent(state, path.string());
  state.log.info("saved project " + path.string());
  return true;
}

bool openAny(EditorState& state, const std::filesystem::path& path, const std::string& animation) {
  if (path.extension() == ".json") return openProject(state, path);
  if (!openFile(state, path, animation)) return false;
  startUntitled(state);
  return true;
}

void startUntitled(EditorState& state) {
  state.project_path.clear();
  state.saved = captureProject(state);
  state.history.reset(state.saved);
}

void newProject(EditorState& state) {
  app::Project defaults;
  const app::Project current = captureProject(state);
  defaults.rig = current.rig;
  defaults.clip = current.clip;
  defaults.animation = current.animation;
  if (!defaults.rig.empty()) applyProject(state, defaults);
  startUntitled(state);
  state.log.info("new project on " +
                 (state.file_name.empty() ? std::string("nothing") : state.file_name));
}

bool hasUnsavedChanges(const EditorState& state) {
  return !(captureProject(state) == state.saved);
}

void recordHistory(EditorState& state) {
  state.history.record(captureProject(state));
}

namespace {

// One step back (undo) or forward (redo) through the history, applied and logged.
bool step(EditorState& state, bool forward) {
  const char* verb = forward ? "redo" : "undo";
  std::optional<History::Step> taken = forward ? state.history.redo() : state.history.undo();
  if (!taken) {
    state.log.info(std::string(verb) + ": nothing to " + verb);
    return false;
  }
  applyProject(state, taken->value);
  state.log.info(std::string(verb) + ": " + taken->what);
  return true;
}

}  // namespace

bool undo(EditorState& state) {
  return step(state, false);
}

bool redo(EditorState& state) {
  return step(state, true);
}

Status writeRecovery(const EditorState& state, const std::filesystem::path& path) {
  const app::Project project = captureProject(state);
  if (project.rig.empty()) return Status();
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  return writeFileAtomically(path, app::projectJson(project, {}));
}

}  // namespace sinew::editor
