// The editor's model: what is loaded, what is analysed, where playback is, what is shown, and
// the message log. Plain data plus free functions; no ImGui or OpenGL here, so the model can be
// driven and tested without a window. The UI thread owns the one EditorState.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "editor/evolution.h"
#include "editor/history.h"
#include "sinew/motion/asset.h"
#include "sinew/physics/body_plan.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/importance.h"
#include "sinew/spectral/style.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::editor {

enum class LogLevel { kInfo, kWarning, kError };

struct LogLine {
  LogLevel level = LogLevel::kInfo;
  double time_s = 0.0;  // seconds since the editor started
  std::string text;
};

// Non-modal notifications and errors, newest last. Every line is echoed to stdout (errors and
// warnings prefixed) so that headless runs and tests can read them.
class Log {
 public:
  void info(std::string text) { add(LogLevel::kInfo, std::move(text)); }
  void warning(std::string text) { add(LogLevel::kWarning, std::move(text)); }
  void error(std::string text) { add(LogLevel::kError, std::move(text)); }
  void add(LogLevel level, std::string text);
  void clear() { lines_.clear(); }
  const std::vector<LogLine>& lines() const { return lines_; }
  double clock_s = 0.0;  // set by the main loop each frame; stamps new lines

 private:
  std::vector<LogLine> lines_;
};

struct Playback {
  double time_s = 0.0;  // seconds from the clip's first frame, in [0, duration]
  double speed = 1.0;   // playback rate, 0.1..4
  bool playing = true;
  bool loop = true;     // wrap at the end; otherwise stop there
};

struct ViewToggles {
  bool show_original = true;
  bool show_model = true;     // the reconstructed harmonic model, translucent
  bool model_beside = true;   // beside the original (offset to its left); else overlaid
  bool follow = true;         // the camera follows the character's root
  bool show_grid = true;
  bool show_end_sites = true;
  bool show_mesh = true;       // glTF characters as their skinned meshes (else as capsules)
  bool show_skeleton = false;  // with the mesh: the capsules drawn over it, translucent
  bool shadows = true;         // the key light's shadow map
};

// The spectrum of the chosen clip and the model the user is editing (K per joint).
struct AnalysisState {
  spectral::MotionSpectrum spectrum;
  std::vector<int> joint_k;               // (joints) harmonics kept, 0..kMaxK
  spectral::TargetMotion model;           // the model with joint_k, continuous in time
  spectral::TargetMotion target;          // the model with the edits (band gains, styles,
                                          // secondary motion): what is drawn, searched, exported
  app::MotionEdits applied;               // the edits `target` has
  std::vector<spectral::JointError> errors;  // (joints) error of the model with joint_k
  spectral::JointError total;
  // Joint importance (the Spectrum panel's ranking), computed when first asked for; cleared
  // with the analysis. Depends on the clip only, not on K.
  std::optional<spectral::ImportanceReport> importance;
};

inline constexpr int kMaxK = 16;           // the K sliders' range

// The Export panel's choices. The kinematic target (the model with its K) is sampled at `fps` for
// `strides` whole strides (the loop closes exactly); the fittest simulated run is written as the
// search recorded it (best.bvh, best.glb, best.json).
struct ExportSettings {
  std::string folder;  // default: beside the opened file
  std::string name;    // file name without extension; default: the clip's name + "_model"
  double fps = 30.0;
  int strides = 4;
  bool bvh = true, gltf = true, coefficients = true;
  bool simulated = false;  // the fittest simulated run instead of the kinematic target
  bool loop = false;       // with `simulated`: the run as a seamless loop, feet planted
  int loop_strides = 2;    // whole strides in the loop, 1..16
  bool in_place = false;   // the loop's root without its travel
};
inline constexpr int kMaxRecentFiles = 10;

struct EditorState {
  std::optional<motion::MotionAsset> asset;
  int clip_index = -1;                    // into asset->clips, -1 when nothing is loaded
  std::optional<AnalysisState> analysis;  // empty when the clip could not be analysed
  std::string file_name;                  // the loaded file's name, for titles
  std::filesystem::path file_path;        // the loaded file
  std::string rig_path;     // the rig, when the clip came from another file (a project's "clip")
  std::string target_path;  // a project's coefficient file: kept so that saving loses nothing
  std::filesystem::path project_path;     // the open project; empty: untitled
  app::Project saved;       // the project as last opened or saved: "unsaved changes" compare to it
  History history;          // undo / redo of every setting (see project_model.h)
  Playback playback;
  ViewToggles view;
  int selected_joint = 0;                 // the joint the spectrum panel shows
  std::vector<std::string> recent_files;  // files and projects, most recent first (kMaxRecentFiles)
  bool frame_requested = false;           // the camera should frame the character next frame
  EvolutionState evolution;               // the search over the loaded rig, if one ran
  ExportSettings exporting;
  app::MotionEdits edits;  // the Style panel's edits of the model (a project setting)
  // Styles measured from their clip pairs, by "neutral|styled": measuring analyses two clips.
  std::map<std::string, std::shared_ptr<const Result<spectral::StyleVector>>> style_cache;
  // The body plan of the loaded clip with the project's body overrides (the Body panel); built
  // on demand by bodyPlan() and rebuilt when the file, clip or overrides change.
  struct BodyPlanCache {
    std::optional<physics::BodyPlan> plan;
    std::string error;            // why there is no plan
    std::string file;             // what it was built for
    int clip_index = -1;
    app::BodyOverrides overrides;
  } body_cache;
  Log log;

  // The chosen clip, or nullptr.
  const motion::Clip* clip() const;
};

// Loads a .bvh/.glb/.gltf file and chooses the animation called `animation` (the first when
// empty). On failure the state keeps what it had and the log says why (the engine's message,
// naming the file and line). Returns whether the file was loaded.
bool openFile(EditorState& state, const std::filesystem::path& path,
              const std::string& animation = "");

// Chooses another clip of the loaded asset: rewinds playback and analyses it.
void chooseClip(EditorState& state, int clip_index);

// The body plan of the chosen clip with evolution.settings.body's overrides, or nullptr (then
// body_cache.error says why).
const physics::BodyPlan* bodyPlan(EditorState& state);

// Body overrides by link name (replacing an earlier one for the same link): a mass in kg, or
// welding the joint (fixed) or freeing it again.
void setBodyMass(EditorState& state, const std::string& link, double kg);
void clearBodyMass(EditorState& state, const std::string& link);
void setBodyWelded(EditorState& state, const std::string& link, bool welded);

// Makes analysis->target the model with state.edits applied, when the edits or the model changed
// since (a cheap check; call it each frame). A style or source that cannot be applied is logged
// and left out. Returns whether it re-derived the target.
bool applyEdits(EditorState& state);
// The style of a pair, measured on first use (two clips analysed) and then cached.
const Result<spectral::StyleVector>& styleOf(EditorState& state, const app::StylePair& pair);
// Adds a style pair at weight 1 after measuring it; the log says why not when it cannot.
bool addStyle(EditorState& state, const std::string& neutral, const std::string& styled,
              const std::string& label = "");
// How close the open clip is to each style pair's styled clip (and to the first pair's neutral,
// labelled "neutral"): spectral::scoreStyle.
Result<spectral::StyleScores> measureClipStyle(EditorState& state);

// Writes what the Export panel chose; the log names every file written (or why not).
bool exportChosen(EditorState& state);

// Path completion for the Files panel: the entries of `partial`'s folder whose names start with
// its last part, folders (with a trailing '/') and the files the editor opens (.bvh, .glb, .gltf,
// .json), sorted; hidden entries only when the last part starts with '.'. At most `limit`.
std::vector<std::string> completePath(const std::string& partial, size_t limit = 50);
// The longest common start of the candidates ("" for none).
std::string commonStart(const std::vector<std::string>& candidates);

// Puts `path` first in the recent files.
void rememberRecent(EditorState& state, const std::string& path);

// K per joint chosen by the analysis's `auto`: the fewest harmonics per joint keeping the worst
// joint position error under `tolerance_cm`. Logs the coefficients and the error it reached.
bool setAutoK(EditorState& state, double tolerance_cm);

// The joints ranked by how much the motion loses when each is frozen at its mean (computed once
// per clip, then cached); nullptr when there is no analysis or it failed (logged).
const spectral::ImportanceReport* rankJoints(EditorState& state);

// Sets K per joint (clamped to 0..kMaxK) and rebuilds the model and its error.
void setJointK(EditorState& state, std::vector<int> joint_k);

// Advances playback by dt seconds of wall time (times speed), wrapping or stopping at the end.
void advancePlayback(EditorState& state, double dt_s);

}  // namespace sinew::editor
