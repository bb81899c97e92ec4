#include "editor/editor_state.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "sinew/pipeline/pipeline.h"
#include "sinew/spectral/target_io.h"

namespace sinew::editor {

void Log::add(LogLevel level, std::string text) {
  const char* prefix = level == LogLevel::kError     ? "error: "
                       : level == LogLevel::kWarning ? "warning: "
                                                     : "";
  std::cout << "sinew edit: " << prefix << text << '\n' << std::flush;
  lines_.push_back({level, clock_s, std::move(text)});
}

const motion::Clip* EditorState::clip() const {
  if (!asset || clip_index < 0 || clip_index >= static_cast<int>(asset->clips.size())) {
    return nullptr;
  }
  return &asset->clips[static_cast<size_t>(clip_index)];
}

std::vector<std::string> completePath(const std::string& partial, size_t limit) {
  const size_t slash = partial.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "." : partial.substr(0, slash + 1);
  const std::string start = slash == std::string::npos ? partial : partial.substr(slash + 1);
  const std::string shown = slash == std::string::npos ? "" : partial.substr(0, slash + 1);
  std::vector<std::string> out;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(folder.empty() ? "/" : folder, ec), end;
       !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(start, 0) != 0 || (name[0] == '.' && (start.empty() || start[0] != '.')))
      continue;
    std::error_code type_ec;
    if (it->is_directory(type_ec)) {
      out.push_back(shown + name + "/");
    } else {
      std::string extension = it->path().extension().string();
      std::transform(extension.begin(), extension.end(), extension.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (extension == ".bvh" || extension == ".glb" || extension == ".gltf" ||
          extension == ".json")
        out.push_back(shown + name);
    }
  }
  std::sort(out.begin(), out.end());
  if (out.size() > limit) out.resize(limit);
  return out;
}

std::string commonStart(const std::vector<std::string>& candidates) {
  if (candidates.empty()) return "";
  std::string common = candidates.front();
  for (const std::string& c : candidates) {
    size_t n = 0;
    while (n < common.size() && n < c.size() && common[n] == c[n]) ++n;
    common.resize(n);
  }
  return common;
}

void rememberRecent(EditorState& state, const std::string& path) {
  auto& recent = state.recent_files;
  recent.erase(std::remove(recent.begin(), recent.end(), path), recent.end());
  recent.insert(recent.begin(), path);
  if (static_cast<int>(recent.size()) > kMaxRecentFiles) recent.resize(kMaxRecentFiles);
}

namespace {

void rebuildModel(const motion::Skeleton& skeleton, const motion::Clip& clip,
                  AnalysisState& analysis) {
  const spectral::MotionSpectrum& spectrum = analysis.spectrum;
  analysis.model = spectral::targetFromSpectrum(spectrum, analysis.joint_k, clip.name);
  analysis.target = analysis.model;  // the edits go on top (applyEdits)
  analysis.applied = {};
  const motion::Clip original = spectral::windowFrames(clip, spectrum);
  const motion::Clip model = spectral::reconstruct(skeleton, spectrum, analysis.joint_k);
  analysis.errors =
      spectral::measureError(skeleton, original, model, spectrum.signals, &analysis.total);
}

// The joint whose rotation carries the most harmonic energy: the spectrum worth showing first.
int mostActiveJoint(const spectral::MotionSpectrum& spectrum) {
  int best = 0;
  double best_energy = -1.0;
  std::vector<double> energy;
  for (size_t c = 0; c < spectrum.signals.channels.size(); ++c) {
    const spectral::SignalChannel& channel = spectrum.signals.channels[c];
    if (channel.kind != spectral::SignalKind::kRotation) continue;
    if (energy.size() <= static_cast<size_t>(channel.joint)) energy.resize(channel.joint + 1, 0.0);
    for (const spectral::Harmonic& h : spectrum.series[c].harmonics) {
      energy[static_cast<size_t>(channel.joint)] += h.amplitude * h.amplitude;
    }
  }
  for (size_t j = 0; j < energy.size(); ++j) {
    if (energy[j] > best_energy) {
      best_energy = energy[j];
      best = static_cast<int>(j);
    }
  }
  return best;
}

}  // namespace

bool openFile(EditorState& state, const std::filesystem::path& path, const std::string& animation) {
  Result<motion::MotionAsset> imported = motion::importMotion(path);
  if (!imported.ok()) {
    state.log.error(imported.message());
    return false;
  }
  motion::MotionAsset& asset = imported.value();
  if (asset.clips.empty()) {
    state.log.error(path.string() + ": the file has no animation to play");
    return false;
  }
  int clip_index = 0;
  if (!animation.empty()) {
    clip_index = asset.findClip(animation);
    if (clip_index < 0) {
      std::string names;
      for (const motion::Clip& clip : asset.clips) names += (names.empty() ? "" : ", ") + clip.name;
      state.log.error(path.string() + ": no animation called '" + animation +
                      "' (there are: " + names + ")");
      return false;
    }
  }
  for (const std::string& warning : asset.warnings) state.log.warning(warning);
  stopEvolution(state);  // its session belongs to the file being replaced
  state.evolution.session.reset();
  state.evolution.snapshot.reset();
  state.evolution.reported_generation = 0;
  state.asset = std::move(asset);
  state.file_path = path;
  // Edits and body overrides name joints of the old rig; a project opened next brings its own.
  state.edits = {};
  state.style_cache.clear();
  state.evolution.settings.physics.body = {};
  state.rig_path.clear();
  state.target_path.clear();
  state.evolution.export_dir = (path.parent_path() / (path.stem().string() + "_evolved")).string();
  state.selected_joint = 0;
  state.frame_requested = true;
  state.file_name = path.filename().string();
  rememberRecent(state, path.string());
  state.log.info("opened " + path.string() + ": " +
                 std::to_string(state.asset->skeleton.jointCount()) + " joints, " +
                 std::to_string(state.asset->clips.size()) + " animation(s)");
  chooseClip(state, clip_index);
  return true;
}

void chooseClip(EditorState& state, int clip_index) {
  state.clip_index = clip_index;
  state.analysis.reset();
  state.playback.time_s = 0.0;
  const motion::Clip* clip = state.clip();
  if (clip == nullptr) return;
  const motion::Skeleton& skeleton = state.asset->skeleton;
  Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, *clip);
  if (!spectrum.ok()) {
    state.log.error("analysis of '" + clip->name + "': " + spectrum.message());
    return;
  }
  AnalysisState analysis;
  analysis.spectrum = std::move(spectrum.value());
  analysis.joint_k = analysis.spectrum.joint_k;
  for (const std::string& note : analysis.spectrum.notes) state.log.warning(note);
  rebuildModel(skeleton, *clip, analysis);
  state.selected_joint = mostActiveJoint(analysis.spectrum);
  state.analysis = std::move(analysis);
  applyEdits(state);
  char line[160];
  std::snprintf(line, sizeof line,
                "'%s': %d frames at %.0f fps, stride %.3f s, model error %.2f deg RMS",
                clip->name.c_str(), clip->frame_count, clip->fps(),
                state.analysis->spectrum.period_s, state.analysis->total.rot_err_deg_rms);
  state.log.info(line);
}

void setJointK(EditorState& state, std::vector<int> joint_k) {
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) return;
  for (int& k : joint_k) k = std::clamp(k, 0, kMaxK);
  joint_k.resize(static_cast<size_t>(state.asset->skeleton.jointCount()), 0);
  state.analysis->joint_k = std::move(joint_k);
  rebuildModel(state.asset->skeleton, *clip, *state.analysis);
  applyEdits(state);
}

const physics::BodyPlan* bodyPlan(EditorState& state) {
  EditorState::BodyPlanCache& cache = state.body_cache;
  const motion::Clip* clip = state.clip();
  const app::BodyOverrides& overrides = state.evolution.settings.physics.body;
  if (cache.file == state.file_path.string() && cache.clip_index == state.clip_index &&
      cache.overrides == overrides && (cache.plan || !cache.error.empty())) {
    return cache.plan ? &*cache.plan : nullptr;
  }
  cache.plan.reset();
  cache.error.clear();
  cache.file = state.file_path.string();
  cache.clip_index = state.clip_index;
  cache.overrides = overrides;
  if (clip == nullptr) {
    cache.error = "open a clip first";
    return nullptr;
  }
  Result<physics::BodyPlan> plan =
      pipeline::bodyPlan(state.asset->skeleton, *clip, overrides, state.file_name);
  if (!plan.ok()) {
    cache.error = plan.message();
    return nullptr;
  }
  cache.plan = std::move(plan).value();
  return &*cache.plan;
}

void setBodyMass(EditorState& state, const std::string& link, double kg) {
  std::vector<app::MassOverride>& masses = state.evolution.settings.physics.body.masses;
  clearBodyMass(state, link);
  masses.push_back({link, kg});
}

void clearBodyMass(EditorState& state, const std::string& link) {
  std::vector<app::MassOverride>& masses = state.evolution.settings.physics.body.masses;
  std::erase_if(masses, [&](const app::MassOverride& m) { return m.link == link; });
}

void setBodyWelded(EditorState& state, const std::string& link, bool welded) {
  std::vector<std::string>& fixed = state.evolution.settings.physics.body.fixed;
  std::erase(fixed, link);
  if (welded) fixed.push_back(link);
}

bool exportChosen(EditorState& state) {
  ExportSettings& e = state.exporting;
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) {
    state.log.error("export: open a clip that analyses first");
    return false;
  }
  if (e.folder.empty()) e.folder = state.file_path.parent_path().string();
  if (e.simulated) {
    state.evolution.export_dir = e.folder;
    if (e.loop) return exportEvolutionLoop(state, e.loop_strides, e.in_place);
    return exportEvolutionBest(state);
  }
  if (e.name.empty()) e.name = clip->name + "_model";
  if (!(e.fps >= 1.0 && e.fps <= 1000.0) || e.strides < 1 || e.strides > 1000) {
    state.log.error("export: fps must be 1..1000 and strides 1..1000");
    return false;
  }
  if (!e.bvh && !e.gltf && !e.coefficients) {
    state.log.error("export: choose at least one of BVH, glTF and coefficients");
    return false;
  }
  std::error_code ec;
  std::filesystem::create_directories(e.folder, ec);
  if (ec) {
    state.log.error("export: " + e.folder + ": cannot create the folder: " + ec.message());
    return false;
  }
  const std::filesystem::path base = std::filesystem::path(e.folder) / e.name;
  const spectral::TargetMotion& target = state.analysis->target;
  const motion::Clip sampled = target.sample(e.fps, e.strides);
  std::vector<std::string> written;
  auto write = [&](const std::string& extension, const Status& status) {
    if (!status.ok()) {
      state.log.error("export: " + status.message());
      return false;
    }
    written.push_back(base.string() + extension);
    return true;
  };
  bool ok = true;
  if (e.bvh)
    ok &= write(".bvh", motion::exportMotion(base.string() + ".bvh", *state.asset, sampled));
  if (e.gltf)
    ok &= write(".glb", motion::exportMotion(base.string() + ".glb", *state.asset, sampled));
  if (e.coefficients)
    ok &= write(".json",
                spectral::saveTarget(base.string() + ".json", target, state.asset->skeleton));
  for (const std::string& path : written) {
    state.log.info("export: wrote " + path);
  }
  char line[160];
  std::snprintf(line, sizeof line,
                "export: the model, %d strides of %.3f s at %.0f fps (%d frames)", e.strides,
                target.period(), e.fps, sampled.frame_count);
  if (!written.empty()) state.log.info(line);
  return ok;
}

bool setAutoK(EditorState& state, double tolerance_cm) {
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) return false;
  spectral::AnalysisSettings settings;
  settings.auto_harmonics = true;
  settings.tolerance_cm = tolerance_cm;
  Result<spectral::MotionSpectrum> spectrum =
      spectral::analyze(state.asset->skeleton, *clip, settings);
  if (!spectrum.ok()) {
    state.log.error("auto K: " + spectrum.message());
    return false;
  }
  setJointK(state, spectrum.value().joint_k);
  int coefficients = 0;
  for (const spectral::SignalChannel& channel : state.analysis->spectrum.signals.channels) {
    coefficients += 1 + 2 * state.analysis->joint_k[static_cast<size_t>(channel.joint)];
  }
  char line[160];
  std::snprintf(line, sizeof line,
                "auto K (worst position under %.2f cm): %d coefficients, %.2f cm max, %.2f deg RMS",
                tolerance_cm, coefficients, state.analysis->total.pos_err_cm_max,
                state.analysis->total.rot_err_deg_rms);
  state.log.info(line);
  return true;
}

const spectral::ImportanceReport* rankJoints(EditorState& state) {
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) return nullptr;
  AnalysisState& analysis = *state.analysis;
  if (!analysis.importance) {
    Result<spectral::ImportanceReport> report =
        spectral::jointImportance(state.asset->skeleton, *clip, analysis.spectrum);
    if (!report.ok()) {
      state.log.error("joint importance: " + report.message());
      return nullptr;
    }
    analysis.importance = std::move(report).value();
  }
  return &*analysis.importance;
}

void advancePlayback(EditorState& state, double dt_s) {
  const motion::Clip* clip = state.clip();
  Playback& playback = state.playback;
  if (clip == nullptr) return;
  const double duration = clip->duration();
  if (playback.playing) playback.time_s += dt_s * playback.speed;
  if (duration <= 0.0) {
    playback.time_s = 0.0;
  } else if (playback.time_s > duration) {
    if (playback.loop) {
      playback.time_s = std::fmod(playback.time_s, duration);
    } else {
      playback.time_s = duration;
      playback.playing = false;
    }
  } else if (playback.time_s < 0.0) {
    playback.time_s = 0.0;
  }
}

}  // namespace sinew::editor
