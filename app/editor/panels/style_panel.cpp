// Style: edits of the harmonic model, previewed live on the translucent model in the viewport and
// used by the search and the export: gains per band of harmonics (gait 1-2, style 3-5, detail 6+)
// and joint group; styles measured from neutral/styled clip pairs, mixed with weights; secondary
// motion (breathing, sway) on chosen joints; and the measured style of the open clip.
#include <algorithm>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/panels/panels.h"

namespace sinew::editor {
namespace {

constexpr const char* kBands[app::kBandCount] = {"gait 1-2", "style 3-5", "detail 6+"};
constexpr const char* kGroups[app::kGroupCount] = {"legs", "arms", "spine", "head"};
constexpr const char* kAxes[3] = {"X", "Y", "Z"};

void drawBandGains(EditorState& state) {
  if (!ImGui::BeginTable("bands", app::kGroupCount + 1, ImGuiTableFlags_SizingStretchSame)) return;
  ImGui::TableSetupColumn("gain");
  for (const char* group : kGroups) ImGui::TableSetupColumn(group);
  ImGui::TableHeadersRow();
  for (int b = 0; b < app::kBandCount; ++b) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(kBands[b]);
    for (int g = 0; g < app::kGroupCount; ++g) {
      ImGui::TableNextColumn();
      ImGui::PushID(b * 8 + g);
      float gain = static_cast<float>(
          state.edits.band_gains[static_cast<size_t>(b)][static_cast<size_t>(g)]);
      ImGui::SetNextItemWidth(-1.0f);
      if (ImGui::DragFloat("##gain", &gain, 0.01f, 0.0f, 3.0f, "%.2f")) {
        state.edits.band_gains[static_cast<size_t>(b)][static_cast<size_t>(g)] =
            std::clamp(gain, 0.0f, 3.0f);
      }
      ImGui::PopID();
    }
  }
  ImGui::EndTable();
}

void drawStyles(EditorState& state, StylePanelState& panel) {
  std::vector<app::StylePair>& styles = state.edits.styles;
  for (size_t i = 0; i < styles.size(); ++i) {
    ImGui::PushID(static_cast<int>(i));
    const Result<spectral::StyleVector>& style = styleOf(state, styles[i]);
    ImGui::SetNextItemWidth(150.0f);
    float weight = static_cast<float>(styles[i].weight);
    if (ImGui::SliderFloat(styles[i].label.c_str(), &weight, -1.0f, 2.0f, "%.2f"))
      styles[i].weight = weight;
    if (ImGui::IsItemHovered()) {
      ImGui::SetTooltip("%s -> %s\n0 unchanged, 1 the style, 2 exaggerated, -1 removed%s",
                        styles[i].neutral.c_str(), styles[i].styled.c_str(),
                        style.ok() ? "" : ("\n" + style.message()).c_str());
    }
    ImGui::SameLine();
    const bool remove = ImGui::SmallButton("remove");
    ImGui::PopID();
    if (remove) {
      styles.erase(styles.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    }
  }
  ImGui::SetNextItemWidth(-70.0f);
  ImGui::InputTextWithHint("neutral", "neutral clip (.bvh)", &panel.neutral);
  ImGui::SetNextItemWidth(-70.0f);
  ImGui::InputTextWithHint("styled", "styled clip, same skeleton", &panel.styled);
  ImGui::SetNextItemWidth(120.0f);
  ImGui::InputTextWithHint("##label", "label (optional)", &panel.label);
  ImGui::SameLine();
  if (ImGui::Button("Add style") && !panel.neutral.empty() && !panel.styled.empty()) {
    if (addStyle(state, panel.neutral, panel.styled, panel.label)) panel.label.clear();
  }
  ImGui::SameLine();
  ImGui::BeginDisabled(styles.empty());
  if (ImGui::Button("Measure the clip")) {
    Result<spectral::StyleScores> scores = measureClipStyle(state);
    if (!scores.ok()) {
      panel.measured = scores.message();
      state.log.error("style measurement: " + scores.message());
    } else {
      panel.measured = "closest: " + scores.value().closest + "  (";
      for (const auto& [label, score] : scores.value().scores) {
        char item[96];
        std::snprintf(item, sizeof item, "%s %.2f ", label.c_str(), score);
        panel.measured += item;
      }
      panel.measured.back() = ')';
      state.log.info("style of '" + state.clip()->name + "': " + panel.measured);
    }
  }
  ImGui::EndDisabled();
  if (!panel.measured.empty()) ImGui::TextWrapped("%s", panel.measured.c_str());
}

void drawSecondary(EditorState& state) {
  std::vector<app::SecondaryMotion>& sources = state.edits.secondary;
  const motion::Skeleton& skeleton = state.asset->skeleton;
  for (size_t i = 0; i < sources.size(); ++i) {
    app::SecondaryMotion& m = sources[i];
    ImGui::PushID(static_cast<int>(i) + 100);
    ImGui::SetNextItemWidth(100.0f);
    if (ImGui::BeginCombo("##joint", m.joint.c_str())) {
      for (const std::string& name : skeleton.names) {
        if (ImGui::Selectable(name.c_str(), name == m.joint)) m.joint = name;
      }
      ImGui::EndCombo();
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(40.0f);
    ImGui::Combo("##axis", &m.axis, kAxes, 3);
    ImGui::SameLine();
    ImGui::Checkbox("noise", &m.noise);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(56.0f);
    float hz = static_cast<float>(m.frequency_hz);
    if (ImGui::DragFloat("Hz", &hz, 0.01f, 0.02f, 10.0f, "%.2f"))
      m.frequency_hz = std::clamp(hz, 0.02f, 10.0f);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(50.0f);
    float deg = static_cast<float>(m.amplitude_deg);
    if (ImGui::DragFloat("deg", &deg, 0.05f, 0.0f, 30.0f, "%.1f"))
      m.amplitude_deg = std::clamp(deg, 0.0f, 30.0f);
    ImGui::SameLine();
    const bool remove = ImGui::SmallButton("x");
    ImGui::PopID();
    if (remove) {
      sources.erase(sources.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    }
  }
  if (ImGui::SmallButton("add breathing")) {
    // A slow sway of the chest (or the first spine joint), the usual start.
    app::SecondaryMotion m;
    m.joint = skeleton.names.front();
    for (const std::string& name : skeleton.names) {
      if (name.find("Chest") != std::string::npos || name.find("chest") != std::string::npos) {
        m.joint = name;
        break;
      }
    }
    m.frequency_hz = 0.25;
    m.amplitude_deg = 1.5;
    sources.push_back(m);
  }
}

}  // namespace

void drawStylePanel(EditorState& state, StylePanelState& panel, int& tab) {
  if (!ImGui::Begin("Style", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  drawRightTabs(tab);
  if (!state.analysis || state.clip() == nullptr) {
    ImGui::TextDisabled("Open a clip that analyses to edit its style.");
    ImGui::End();
    return;
  }
  const bool edited = !state.edits.empty();
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextDisabled(
      "%s", edited ? "The translucent model shows the edits; the search and the export use them."
                   : "No edits: the model is the clip's harmonics.");
  ImGui::PopTextWrapPos();
  if (edited) {
    ImGui::SameLine();
    if (ImGui::SmallButton("reset")) state.edits = {};
  }
  if (ImGui::CollapsingHeader("Band gains", ImGuiTreeNodeFlags_DefaultOpen)) drawBandGains(state);
  if (ImGui::CollapsingHeader("Styles", ImGuiTreeNodeFlags_DefaultOpen)) drawStyles(state, panel);
  if (ImGui::CollapsingHeader("Secondary motion", ImGuiTreeNodeFlags_DefaultOpen))
    drawSecondary(state);
  applyEdits(state);  // the preview follows every change at once
  ImGui::End();
}

void drawRightTabs(int& tab) {
  const char* names[2] = {"Spectrum", "Style"};
  for (int i = 0; i < 2; ++i) {
    if (i > 0) ImGui::SameLine();
    if (ImGui::Selectable(names[i], tab == i, 0,
                          ImVec2(ImGui::CalcTextSize(names[i]).x + 8.0f, 0.0f)))
      tab = i;
  }
  ImGui::Separator();
}

}  // namespace sinew::editor
