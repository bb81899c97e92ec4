#include "editor/preferences.h"

#include <cstdlib>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sinew/core/file_io.h"
#include "sinew/core/text.h"

namespace sinew::editor {

std::filesystem::path configDir() {
  if (const char* dir = std::getenv("SINEW_CONFIG_DIR"); dir != nullptr && *dir != '\0') return dir;
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg != nullptr && *xdg != '\0')
    return std::filesystem::path(xdg) / "sinew";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".config" / "sinew";
  return {};
}

Result<Preferences> loadPreferences(const std::filesystem::path& path) {
  Preferences preferences;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return preferences;
  Result<std::string> text = readFile(path);
  if (!text.ok()) return text.status();
  const std::string name = path.string();
  try {
    const nlohmann::json json = nlohmann::json::parse(text.value());
    preferences.recent_files = json.value("recent_files", std::vector<std::string>{});
    preferences.window_width = json.value("window_width", preferences.window_width);
    preferences.window_height = json.value("window_height", preferences.window_height);
    if (json.contains("layout")) {
      const nlohmann::json& l = json.at("layout");
      PanelLayout& layout = preferences.layout;
      layout.left_width = l.value("left_width", 0.0f);
      layout.right_width = l.value("right_width", 0.0f);
      layout.timeline_height = l.value("timeline_height", 0.0f);
      layout.files_fraction = l.value("files_fraction", 0.0f);
      layout.body_fraction = l.value("body_fraction", 0.0f);
      layout.evolve_fraction = l.value("evolve_fraction", 0.0f);
      layout.spectrum_fraction = l.value("spectrum_fraction", 0.0f);
    }
  } catch (const nlohmann::json::exception& e) {
    return Status::error(name + ": " + e.what());
  }
  if (preferences.window_width < 320 || preferences.window_height < 240 ||
      preferences.window_width > 16384 || preferences.window_height > 16384)
    return Status::error(name + ": window_width/window_height: out of range");
  return preferences;
}

Status savePreferences(const Preferences& preferences, const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  if (ec) return Status::error(path.parent_path().string() + ": cannot create: " + ec.message());
  const PanelLayout& l = preferences.layout;
  // JSON text is UTF-8, and a path is bytes: one that is not UTF-8 (a Latin-1 file name) cannot
  // be stored so that it opens again, so it is left out of the list rather than altered.
  std::vector<std::string> recent;
  for (const std::string& file : preferences.recent_files)
    if (isValidUtf8(file)) recent.push_back(file);
  const nlohmann::json json = {{"recent_files", recent},
                               {"window_width", preferences.window_width},
                               {"window_height", preferences.window_height},
                               {"layout",
                                {{"left_width", l.left_width},
                                 {"right_width", l.right_width},
                                 {"timeline_height", l.timeline_height},
                                 {"files_fraction", l.files_fraction},
                                 {"body_fraction", l.body_fraction},
                                 {"evolve_fraction", l.evolve_fraction},
                                 {"spectrum_fraction", l.spectrum_fraction}}}};
  return writeFileAtomically(
      path, json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace sinew::editor
