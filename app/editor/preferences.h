// What the editor remembers between runs, apart from projects: recent files, the panels' sizes
// and the window's size. A JSON file in the user's configuration folder; a missing or broken file
// means defaults (and a message), never a failure to start.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sinew/core/status.h"

namespace sinew::editor {

struct PanelLayout {
  // 0: the default for the window's size. Pixels or fractions of the window's height.
  float left_width = 0.0f;         // Files and Log
  float right_width = 0.0f;        // Spectrum and Evolve
  float timeline_height = 0.0f;    // under the viewport
  float files_fraction = 0.0f;     // of the height: Files at the top of the left column
  float body_fraction = 0.0f;      // of the height: Body under Files, above Log
  float spectrum_fraction = 0.0f;  // of the height: Spectrum at the top of the right column
  float evolve_fraction = 0.0f;    // of the height: Evolve under Spectrum, above Export
  bool operator==(const PanelLayout&) const = default;
};

struct Preferences {
  std::vector<std::string> recent_files;  // most recent first
  PanelLayout layout;
  int window_width = 1600;
  int window_height = 900;
  bool operator==(const Preferences&) const = default;
};

// $SINEW_CONFIG_DIR, else $XDG_CONFIG_HOME/sinew, else $HOME/.config/sinew; empty when none is set.
std::filesystem::path configDir();
inline constexpr const char* kPreferencesFile = "editor.json";
inline constexpr const char* kRecoveryFile = "recovery.sinew.json";

// A missing file gives the defaults; a broken one an error naming the file and field.
Result<Preferences> loadPreferences(const std::filesystem::path& path);
Status savePreferences(const Preferences& preferences, const std::filesystem::path& path);

}  // namespace sinew::editor
