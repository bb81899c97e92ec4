// Projects, undo and redo in the editor. Everything a user sets is captured as one app::Project
// (the files, K per joint by joint name, the search's settings and weights, physics, view);
// undo/redo restore such values, a save writes one, "unsaved changes" compares the current one
// with the one last saved. Plain model code: tests drive it without a window.
#pragma once

#include <filesystem>

#include "editor/editor_state.h"
#include "project/project.h"

namespace sinew::editor {

// The project as the editor has it now (files absolute).
app::Project captureProject(const EditorState& state);
// Makes the editor match `project`: opens its file when it is not the one loaded (the current
// state stays when that fails, and the log says why; returns false), then applies every setting.
bool applyProject(EditorState& state, const app::Project& project);

// Opens a project file: its files and settings; the history starts over. A bad project is named
// in the log with its field and nothing changes.
bool openProject(EditorState& state, const std::filesystem::path& path);
// Saves the current project to `path` (atomically) and makes it the open project.
bool saveProjectAs(EditorState& state, const std::filesystem::path& path);
// Opens a motion file (.bvh/.glb/.gltf) or a project (.json) by its extension.
bool openAny(EditorState& state, const std::filesystem::path& path,
             const std::string& animation = "");
// After opening a motion file as such: an untitled project on it with default settings, saved
// state set so that it counts as unchanged.
void startUntitled(EditorState& state);

// Default settings on the open file, untitled (the files stay).
void newProject(EditorState& state);

bool hasUnsavedChanges(const EditorState& state);
// Call once per frame while no widget is being dragged: a change since the last call becomes
// one undo step.
void recordHistory(EditorState& state);
bool undo(EditorState& state);  // logs what it undid; false when there is nothing to undo
bool redo(EditorState& state);

// The recovery file (autosave): the current project with absolute paths, written atomically.
Status writeRecovery(const EditorState& state, const std::filesystem::path& path);

}  // namespace sinew::editor
