#include "editor/theme.h"

#include <filesystem>

#include <imgui.h>

namespace sinew::editor {

void applyTheme() {
  ImGuiIO& io = ImGui::GetIO();
  // DejaVu Sans when the system has it (Debian's fonts-dejavu-core); ImGui's built-in font else.
  const char* const fonts[] = {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                               "/usr/share/fonts/TTF/DejaVuSans.ttf"};
  for (const char* font : fonts) {
    std::error_code error;
    if (std::filesystem::is_regular_file(font, error)) {
      io.Fonts->AddFontFromFileTTF(font, 15.0f);
      break;
    }
  }

  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0.0f;
  style.FrameRounding = 3.0f;
  style.GrabRounding = 3.0f;
  style.ScrollbarRounding = 3.0f;
  style.WindowBorderSize = 1.0f;
  style.FrameBorderSize = 0.0f;
  style.WindowPadding = ImVec2(10.0f, 8.0f);
  style.FramePadding = ImVec2(7.0f, 4.0f);
  style.ItemSpacing = ImVec2(8.0f, 6.0f);
  style.WindowTitleAlign = ImVec2(0.0f, 0.5f);

  ImVec4* c = style.Colors;
  const ImVec4 bg(0.135f, 0.140f, 0.155f, 1.0f);
  const ImVec4 bg_dark(0.105f, 0.110f, 0.122f, 1.0f);
  const ImVec4 frame(0.200f, 0.210f, 0.232f, 1.0f);
  const ImVec4 accent(0.93f, 0.62f, 0.26f, 1.0f);
  c[ImGuiCol_WindowBg] = bg;
  c[ImGuiCol_ChildBg] = ImVec4(0, 0, 0, 0);
  c[ImGuiCol_PopupBg] = bg_dark;
  c[ImGuiCol_Border] = ImVec4(0.06f, 0.06f, 0.07f, 1.0f);
  c[ImGuiCol_TitleBg] = bg_dark;
  c[ImGuiCol_TitleBgActive] = ImVec4(0.16f, 0.17f, 0.19f, 1.0f);
  c[ImGuiCol_TitleBgCollapsed] = bg_dark;
  c[ImGuiCol_FrameBg] = frame;
  c[ImGuiCol_FrameBgHovered] = ImVec4(0.25f, 0.26f, 0.29f, 1.0f);
  c[ImGuiCol_FrameBgActive] = ImVec4(0.29f, 0.30f, 0.34f, 1.0f);
  c[ImGuiCol_Button] = ImVec4(0.23f, 0.24f, 0.27f, 1.0f);
  c[ImGuiCol_ButtonHovered] = ImVec4(0.30f, 0.31f, 0.35f, 1.0f);
  c[ImGuiCol_ButtonActive] = ImVec4(0.36f, 0.37f, 0.42f, 1.0f);
  c[ImGuiCol_Header] = ImVec4(0.93f, 0.62f, 0.26f, 0.22f);
  c[ImGuiCol_HeaderHovered] = ImVec4(0.93f, 0.62f, 0.26f, 0.32f);
  c[ImGuiCol_HeaderActive] = ImVec4(0.93f, 0.62f, 0.26f, 0.45f);
  c[ImGuiCol_SliderGrab] = accent;
  c[ImGuiCol_SliderGrabActive] = ImVec4(1.0f, 0.72f, 0.36f, 1.0f);
  c[ImGuiCol_CheckMark] = accent;
  c[ImGuiCol_Separator] = ImVec4(0.22f, 0.23f, 0.26f, 1.0f);
  c[ImGuiCol_Text] = ImVec4(0.86f, 0.87f, 0.89f, 1.0f);
  c[ImGuiCol_TextDisabled] = ImVec4(0.52f, 0.54f, 0.58f, 1.0f);
  c[ImGuiCol_ScrollbarBg] = ImVec4(0, 0, 0, 0);
}

}  // namespace sinew::editor
