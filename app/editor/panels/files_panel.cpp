// Files: the project (new, save, save as; its name and whether it has unsaved changes), a path
// field with Open for motion files and projects, the recent files, the animation chooser for
// files with several animations (glTF), and a hint that files can be dropped onto the window.
#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/panels/panels.h"
#include "editor/project_model.h"

namespace sinew::editor {
namespace {

// The save-as field's suggestion: the project beside its clip, named after it.
std::string suggestedProjectPath(const EditorState& state) {
  if (!state.project_path.empty()) return state.project_path.string();
  if (state.file_path.empty()) return "";
  return (state.file_path.parent_path() / (state.file_path.stem().string() + ".sinew.json"))
      .string();
}

void drawProject(EditorState& state, FilesPanelState& panel) {
  const bool unsaved = hasUnsavedChanges(state);
  const std::string name =
      state.project_path.empty() ? "untitled project" : state.project_path.filename().string();
  ImGui::Text("%s%s", name.c_str(), unsaved ? "  (unsaved changes)" : "");
  if (!state.project_path.empty() && ImGui::IsItemHovered()) {
    ImGui::SetTooltip("%s", state.project_path.string().c_str());
  }
  if (ImGui::Button("New")) newProject(state);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Default settings on the open file (Ctrl+N)");
  ImGui::SameLine();
  ImGui::BeginDisabled(!state.asset);
  if (ImGui::Button("Save")) saveOpenProject(state, panel);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Ctrl+S; an untitled project goes to the path below");
  ImGui::SameLine();
  ImGui::BeginDisabled(!state.history.canUndo());
  if (ImGui::Button("Undo")) undo(state);
  if (state.history.canUndo() && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip("Undo %s (Ctrl+Z)", state.history.undoLabel().c_str());
  }
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(!state.history.canRedo());
  if (ImGui::Button("Redo")) redo(state);
  if (state.history.canRedo() && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip("Redo %s (Ctrl+Shift+Z)", state.history.redoLabel().c_str());
  }
  ImGui::EndDisabled();
  if (panel.save_path.empty()) panel.save_path = suggestedProjectPath(state);
  ImGui::SetNextItemWidth(-70.0f);
  ImGui::InputTextWithHint("##saveas", "path/to/project.sinew.json", &panel.save_path);
  ImGui::SameLine();
  if (ImGui::Button("Save as", ImVec2(-1.0f, 0.0f)) && !panel.save_path.empty()) {
    saveProjectAs(state, panel.save_path);
  }
  ImGui::EndDisabled();
}

}  // namespace

void saveOpenProject(EditorState& state, FilesPanelState& panel) {
  if (!state.project_path.empty()) {
    saveProjectAs(state, state.project_path);
    return;
  }
  if (panel.save_path.empty()) panel.save_path = suggestedProjectPath(state);
  if (!panel.save_path.empty()) saveProjectAs(state, panel.save_path);
}

void drawFilesPanel(EditorState& state, FilesPanelState& panel) {
  if (!ImGui::Begin("Files", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  drawProject(state, panel);
  ImGui::Separator();
  ImGui::TextDisabled("BVH, glTF (.glb/.gltf) or a project (.json): type a path or drop a file");
  ImGui::SetNextItemWidth(-70.0f);
  // Tab completes the path from the folder it names (the matches are listed under the field).
  auto complete = [](ImGuiInputTextCallbackData* data) -> int {
    auto* matches = static_cast<std::vector<std::string>*>(data->UserData);
    *matches = completePath(std::string(data->Buf, static_cast<size_t>(data->BufTextLen)));
    const std::string common = commonStart(*matches);
    if (common.size() > static_cast<size_t>(data->BufTextLen)) {
      data->DeleteChars(0, data->BufTextLen);
      data->InsertChars(0, common.c_str());
    }
    if (matches->size() == 1) matches->clear();  // completed: nothing to choose from
    return 0;
  };
  const bool tab = ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Tab));
  const bool enter = ImGui::InputTextWithHint(
      "##path", "path/to/clip.bvh (Tab completes)", &panel.path,
      ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_CallbackCompletion, complete,
      &panel.matches);
  if (ImGui::IsItemEdited() && !tab) panel.matches.clear();  // typing: the list is stale
  ImGui::SameLine();
  if ((ImGui::Button("Open", ImVec2(-1.0f, 0.0f)) || enter) && !panel.path.empty()) {
    if (openAny(state, panel.path, panel.animation)) panel.save_path.clear();
  }
  for (const std::string& match : panel.matches) {
    // Clicking a match takes it (a folder: to complete further).
    const size_t slash = match.find_last_of('/', match.size() - 2);
    const std::string label = "  " + (slash == std::string::npos ? match : match.substr(slash + 1));
    if (ImGui::Selectable(label.c_str())) {
      panel.path = match;
      panel.matches.clear();
      break;
    }
  }
  ImGui::SetNextItemWidth(-70.0f);
  ImGui::InputTextWithHint("##animation", "animation name (glTF, optional)", &panel.animation);

  if (state.asset) {
    ImGui::Separator();
    ImGui::Text("%s", state.file_name.c_str());
    if (const motion::Clip* clip = state.clip()) {
      ImGui::TextDisabled("%d joints, %d frames, %.0f fps, %.2f s",
                          state.asset->skeleton.jointCount(), clip->frame_count, clip->fps(),
                          clip->duration());
    }
    const auto& clips = state.asset->clips;
    if (clips.size() > 1) {
      const char* current = state.clip() != nullptr ? state.clip()->name.c_str() : "";
      ImGui::SetNextItemWidth(-1.0f);
      if (ImGui::BeginCombo("##clip", current)) {
        for (int i = 0; i < static_cast<int>(clips.size()); ++i) {
          if (ImGui::Selectable(clips[static_cast<size_t>(i)].name.c_str(),
                                i == state.clip_index)) {
            chooseClip(state, i);
          }
        }
        ImGui::EndCombo();
      }
    } else if (const motion::Clip* clip = state.clip()) {
      ImGui::TextDisabled("animation: %s", clip->name.c_str());
    }
  }

  ImGui::Separator();
  ImGui::TextDisabled("Recent");
  std::string chosen;
  for (const std::string& path : state.recent_files) {
    if (ImGui::Selectable(path.c_str(), false)) chosen = path;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", path.c_str());
  }
  if (!chosen.empty()) {
    panel.path = chosen;
    if (openAny(state, chosen, panel.animation)) panel.save_path.clear();
  }
  ImGui::End();
}

}  // namespace sinew::editor
