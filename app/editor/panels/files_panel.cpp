// Files: a path field with Open, the recent files, the animation chooser for files with several
// animations (glTF), and a hint that files can be dropped onto the window.
#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/panels/panels.h"

namespace sinew::editor {

void drawFilesPanel(EditorState& state, FilesPanelState& panel) {
  if (!ImGui::Begin("Files", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  ImGui::TextDisabled("BVH, glTF (.glb/.gltf): type a path or drop a file on the window");
  ImGui::SetNextItemWidth(-70.0f);
  const bool enter = ImGui::InputTextWithHint("##path", "path/to/clip.bvh", &panel.path,
                                              ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  if ((ImGui::Button("Open", ImVec2(-1.0f, 0.0f)) || enter) && !panel.path.empty()) {
    openFile(state, panel.path, panel.animation);
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
          if (ImGui::Selectable(clips[static_cast<size_t>(i)].name.c_str(), i == state.clip_index)) {
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
    openFile(state, chosen, panel.animation);
  }
  ImGui::End();
}

}  // namespace sinew::editor
