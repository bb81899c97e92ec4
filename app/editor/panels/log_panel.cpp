// Log: the editor's messages, newest at the bottom; errors red, warnings amber.
#include <imgui.h>

#include "editor/panels/panels.h"

namespace sinew::editor {

void drawLogPanel(EditorState& state) {
  if (!ImGui::Begin("Log", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  if (ImGui::SmallButton("Clear")) state.log.clear();
  ImGui::Separator();
  ImGui::BeginChild("##lines", ImVec2(0, 0), false);  // lines wrap: no horizontal scrolling
  for (const LogLine& line : state.log.lines()) {
    const ImVec4 color = line.level == LogLevel::kError     ? ImVec4(1.0f, 0.45f, 0.40f, 1.0f)
                         : line.level == LogLevel::kWarning ? ImVec4(1.0f, 0.78f, 0.35f, 1.0f)
                                                            : ImVec4(0.80f, 0.82f, 0.85f, 1.0f);
    ImGui::TextDisabled("%6.1f", line.time_s);
    ImGui::SameLine();
    ImGui::PushStyleColor(ImGuiCol_Text, color);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(line.text.c_str());
    ImGui::PopTextWrapPos();
    ImGui::PopStyleColor();
  }
  if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY() - 1.0f) ImGui::SetScrollHereY(1.0f);
  ImGui::EndChild();
  ImGui::End();
}

}  // namespace sinew::editor
