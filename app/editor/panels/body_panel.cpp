// Body: the physical character the search simulates, as built from the clip with the project's
// overrides: total mass and degrees of freedom, and per link its joint type, mass and range. A
// link's mass can be set (or reset to the rule's), a joint welded or freed; the terrain and the
// pushes every evaluation takes. Every change is a project setting (undo, save).
#include <algorithm>
#include <string>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/panels/panels.h"

namespace sinew::editor {
namespace {

constexpr double kDeg = 57.29577951308232;

bool hasMassOverride(const app::BodyOverrides& body, const std::string& link) {
  return std::any_of(body.masses.begin(), body.masses.end(),
                     [&](const app::MassOverride& m) { return m.link == link; });
}

bool isWelded(const app::BodyOverrides& body, const std::string& link) {
  return std::find(body.fixed.begin(), body.fixed.end(), link) != body.fixed.end();
}

void drawLinks(EditorState& state, const physics::BodyPlan& plan) {
  const app::BodyOverrides& body = state.evolution.settings.physics.body;
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
    if (hasMassOverride(body, link.name)) {
      ImGui::SameLine();
      if (ImGui::SmallButton("x")) reset = link.name;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Back to the rule's mass");
    }
    ImGui::TableNextColumn();
    if (link.type == physics::JointType::kBase) {
      ImGui::TextDisabled("base");
    } else {
      bool welded = link.type == physics::JointType::kFixed;
      const bool overridden = isWelded(body, link.name);
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

// The terrain and the pushes are typed settings shown as their text; an edit is read (and
// applied) when Enter is pressed, and a line that does not read is named in the log.
void drawTerrainAndPushes(EditorState& state) {
  app::PhysicsSettings& physics = state.evolution.settings.physics;
  constexpr ImGuiInputTextFlags kOnEnter = ImGuiInputTextFlags_EnterReturnsTrue;
  ImGui::SetNextItemWidth(160.0f);
  std::string terrain = app::terrainText(physics.terrain);
  if (ImGui::InputText("terrain", &terrain, kOnEnter)) {
    Result<physics::TerrainSettings> read = app::parseTerrain(terrain, "terrain");
    if (read.ok()) {
      physics.terrain = read.value();
    } else {
      state.log.error(read.message());
    }
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "flat | slope:DEG | steps:HEIGHT,DEPTH | rough:AMPLITUDE,SEED (Enter applies)");
  ImGui::SameLine();
  if (ImGui::SmallButton("add a push")) {
    physics::Push push;
    push.time_s = 1.0;
    push.impulse_ns = glm::dvec3(-40.0, 0.0, 0.0);
    physics.pushes.push_back(push);
  }
  std::vector<physics::Push>& pushes = physics.pushes;
  for (size_t i = 0; i < pushes.size(); ++i) {
    ImGui::PushID(static_cast<int>(i) + 1000);
    ImGui::SetNextItemWidth(160.0f);
    std::string text = app::pushText(pushes[i]);
    if (ImGui::InputText("push", &text, kOnEnter)) {
      Result<physics::Push> read = app::parsePush(text, "push");
      if (read.ok()) {
        pushes[i] = read.value();
      } else {
        state.log.error(read.message());
      }
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "TIME,X,Y,Z[,LINK]: seconds, N s (Y up); the base when no link (Enter applies)");
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
  // A running search keeps its body.
  ImGui::BeginDisabled(state.evolution.snapshot &&
                       search::underWay(state.evolution.snapshot->state));
  if (plan == nullptr) {
    ImGui::TextWrapped("No body: %s", state.body_cache.error.c_str());
    if (!state.evolution.settings.physics.body.empty()) {
      if (ImGui::Button("Clear the overrides")) state.evolution.settings.physics.body = {};
    }
  } else {
    ImGui::Text("%.1f kg, %zu links, %d degrees of freedom", plan->total_mass_kg,
                plan->links.size(), plan->dofCount());
    // What the total comes from (the plan's "mass: " note, motion::estimateBody), and how the
    // links share it.
    std::string basis = "mass";
    for (const std::string& note : plan->notes)
      if (note.rfind("mass: ", 0) == 0) basis = note;
    basis += plan->human ? "; shared by de Leva's human fractions" : "; shared by shape volume";
    ImGui::TextWrapped("%s", basis.c_str());
    drawLinks(state, *plan);
  }
  drawTerrainAndPushes(state);
  ImGui::EndDisabled();
  ImGui::End();
}

}  // namespace sinew::editor
