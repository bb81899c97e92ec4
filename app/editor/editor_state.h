// The editor's model: what is loaded, what is analysed, where playback is, what is shown, and
// the message log. Plain data plus free functions; no ImGui or OpenGL here, so the model can be
// driven and tested without a window. The UI thread owns the one EditorState.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "editor/evolution.h"
#include "sinew/motion/asset.h"
#include "sinew/spectral/analysis.h"
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
  spectral::TargetMotion target;          // the model with joint_k, continuous in time
  std::vector<spectral::JointError> errors;  // (joints) error of the model with joint_k
  spectral::JointError total;
};

inline constexpr int kMaxK = 16;           // the K sliders' range
inline constexpr int kMaxRecentFiles = 10;

struct EditorState {
  std::optional<motion::MotionAsset> asset;
  int clip_index = -1;                    // into asset->clips, -1 when nothing is loaded
  std::optional<AnalysisState> analysis;  // empty when the clip could not be analysed
  std::string file_name;                  // the loaded file's name, for titles
  std::filesystem::path file_path;        // the loaded file
  Playback playback;
  ViewToggles view;
  int selected_joint = 0;                 // the joint the spectrum panel shows
  std::vector<std::string> recent_files;  // most recent first, at most kMaxRecentFiles
  bool frame_requested = false;           // the camera should frame the character next frame
  EvolutionState evolution;               // the search over the loaded rig, if one ran
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

// Sets K per joint (clamped to 0..kMaxK) and rebuilds the model and its error.
void setJointK(EditorState& state, std::vector<int> joint_k);

// Advances playback by dt seconds of wall time (times speed), wrapping or stopping at the end.
void advancePlayback(EditorState& state, double dt_s);

}  // namespace sinew::editor
