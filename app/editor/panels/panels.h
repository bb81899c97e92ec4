// The editor's panels: one file each, one Draw function each. A panel reads and edits the
// EditorState through the model's functions (openFile, setJointK, ...) and keeps only its own
// widget state (text fields) in its small struct here. The caller places the window first.
#pragma once

#include <string>
#include <vector>

#include "editor/editor_state.h"

namespace sinew::editor {

struct FilesPanelState {
  std::string path;       // the path field
  std::string animation;  // the animation wanted when opening a glTF
  std::string save_path;  // the "save as" field; filled with a suggestion when empty
  std::vector<std::string> matches;  // the path field's completions after Tab, when several
};

// Saves the open project, or an untitled one to the save-as field's path (Ctrl+S).
void saveOpenProject(EditorState& state, FilesPanelState& panel);

struct SpectrumPanelState {
  int global_k = 5;        // the "all joints" slider
  bool joints_moving_only = true;  // hide joints that do not move in the list
  float tolerance_cm = 1.0f;       // for "auto"
  bool show_curves = false;        // the chosen joint's curves instead of its harmonic bars
  bool show_ranking = false;       // the joints ranked by importance instead of the joint list
};

struct StylePanelState {
  std::string neutral, styled, label;  // the "add a style" fields
  std::string measured;                // the last style measurement, as shown
};

// The top-right region holds Spectrum or Style: a row of two tabs at the top of each.
void drawRightTabs(int& tab);

void drawFilesPanel(EditorState& state, FilesPanelState& panel);
void drawTimelinePanel(EditorState& state);
void drawSpectrumPanel(EditorState& state, SpectrumPanelState& panel, int& tab);
void drawStylePanel(EditorState& state, StylePanelState& panel, int& tab);
void drawLogPanel(EditorState& state);
void drawEvolvePanel(EditorState& state);
void drawBodyPanel(EditorState& state);
void drawExportPanel(EditorState& state);

}  // namespace sinew::editor
