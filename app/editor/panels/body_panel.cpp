// Body: the physical character the search simulates, as built from the clip with the project's
// overrides: total mass and degrees of freedom, and per link its joint type, mass and range. A
// link's mass can be set (or reset to the rule's), a joint welded or freed; the terrain and the
// pushes every evaluation takes. Every change is a project setting (undo, save).
#include <algorithm>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/panels/panels.h"

namespace sinew::editor {
namespace {

constexpr double kDeg = 57.29577951308232;

bool hasOverride(const std::vector<std::string>& list, const std::string& link) {
  return std::any_of(list.begin(), list.end(), [&](const std::string& entry) {
    return entry == link || entry.rfind(link + "=", 0) == 0;
  });
}

void drawLinks(EditorState& state, const physics::BodyPlan& plan) {
  const app::BodyOverrides& body = state.evolution.settings.body;
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY |
                                ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingFixedFit;
  const float height = std::max(ImGui::GetContentRegionAvail().y - 70.0f, 80.0f);
  if (!ImGui::BeginTable("links", 4, flags, ImVec2(0.0f, height))) return;
  ImGui::TableSetupScrollFreeze(0, 1);
  ImGui::TableSetupColumn("link", ImGuiTableColumnFlags_WidthStretch);
  ImGui::TableSetupColumn("kg");
  ImGui::TableSetupColumn("joint");
  ImGui::TableSetupColumn("range, deg");
  ImGui::TableHeadersRow();
  std::string weld, free, reset;
  std::pair<std::string, double> mass;
  for (size_t i = 0; i < plan.links.size(); ++i) {
    const physics::Link& link = plan.links[i];
    ImGui::PushID(static_cast<int>(i));
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::Text("%s", link.name.c_str());
    ImGui::TableNextColumn();
    float kg = static_cast<float>(link.mass_kg);
    ImGui::SetNextItemWidth(58.0f);
    if (ImGui::DragFloat("##kg", &kg, 0.05f, 0.05f, 500.0f, "%.2f"))
      mass = {link.name, std::max(kg, 0.05f)};
    if (hasOverride(body.masses, link.name)) {
      ImGui::SameLine();
      if (ImGui::SmallButton("x")) reset = link.name;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Back to the rule's mass");
    }
    ImGui::TableNextColumn();
    if (link.type == physics::JointType::kBase) {
      ImGui::TextDisabled("base");
    } else {
      bool welded = link.type == physics::JointType::kFixed;
      const bool overridden = hasOverride(body.fixed, link.name);
      ImGui::BeginDisabled(welded && !overridden);  // fixed by the rules: it does not move
      if (ImGui::Checkbox("##weld", &welded)) (welded ? weld : free) = link.name;
      ImGui::EndDisabled();
      if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
        ImGui::SetTooltip(welded ? "Welded (no motion); untick to free it"
                                 : "Tick to weld this joint");
      }
      ImGui::SameLine();
      ImGui::Text("%s", physics::jointTypeName(link.type));
    }
    ImGui::TableNextColumn();
    if (link.type == physics::JointType::kHinge) {
      ImGui::Text("%.0f .. %.0f", link.hinge_lower * kDeg, link.hinge_upper * kDeg);
    } else if (link.type == physics::JointType::kBall) {
      ImGui::Text("%.0f/%.0f/%.0f", (link.ball_upper.x - link.ball_lower.x) * kDeg,
                  (link.ball_upper.y - link.ball_lower.y) * kDeg,
                  (link.ball_upper.z - link.ball_lower.z) * kDeg);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Span of the observed range per axis (X/Y/Z)");
    }
    ImGui::PopID();
  }
  ImGui::EndTable();
  if (!mass.first.empty()) setBodyMass(state, mass.first, mass.second);
  if (!reset.empty()) clearBodyMass(state, reset);
  if (!weld.empty()) setBodyWelded(state, weld, true);
  if (!free.empty()) setBodyWelded(state, free, false);
}

void drawTerrainAndPushes(EditorState& state) {
  EvolutionSettings& settings = state.evolution.settings;
  ImGui::SetNextItemWidth(160.0f);
  ImGui::InputText("terrain", &settings.terrain);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("flat | slope:DEG | steps:HEIGHT,DEPTH | rough:AMPLITUDE,SEED");
  ImGui::SameLine();
  if (ImGui::SmallButton("add a push")) settings.pushes.emplace_back("1.0,-40,0,0");
  std::vector<std::string>& pushes = settings.pushes;
  for (size_t i = 0; i < pushes.size(); ++i) {
    ImGui::PushID(static_cast<int>(i) + 1000);
    ImGui::SetNextItemWidth(160.0f);
    ImGui::InputText("push", &pushes[i]);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("TIME,X,Y,Z[,LINK]: seconds, N s (Y up); the base when no link");
    ImGui::SameLine();
    const bool remove = ImGui::SmallButton("remove");
    ImGui::PopID();
    if (remove) {
      pushes.erase(pushes.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    }
  }
}

}  // namespace

void drawBodyPanel(EditorState& state) {
  if (!ImGui::Begin("Body", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  const physics::BodyPlan* plan = bodyPlan(state);
  const std::string run = state.evolution.snapshot ? state.evolution.snapshot->state : "";
  ImGui::BeginDisabled(run == "running" || run == "paused");  // a running search keeps its body
  if (plan == nullptr) {
    ImGui::TextWrapped("No body: %s", state.body_cache.error.c_str());
    if (!state.evolution.settings.body.masses.empty() ||
        !state.evolution.settings.body.fixed.empty()) {
      if (ImGui::Button("Clear the overrides")) state.evolution.settings.body = {};
    }
  } else {
    ImGui::Text("%.1f kg, %zu links, %d degrees of freedom", plan->total_mass_kg,
                plan->links.size(), plan->dofCount());
    ImGui::TextDisabled(
        "%s", plan->human ? "masses: de Leva's human fractions" : "masses: by shape volume");
    drawLinks(state, *plan);
  }
  drawTerrainAndPushes(state);
  ImGui::EndDisabled();
  ImGui::End();
}

}  // namespace sinew::editor
