// Export: the kinematic target (the model with its K per joint, sampled at a chosen rate for whole
// strides, as BVH, glTF and coefficients JSON) or the fittest simulated run of the search (BVH,
// glTF and its controller file), raw or as a seamless loop with planted feet. Every file written, or why not, goes to the Log.
#include <algorithm>
#include <optional>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "editor/panels/panels.h"

namespace sinew::editor {

void drawExportPanel(EditorState& state) {
  if (!ImGui::Begin("Export", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  ExportSettings& e = state.exporting;
  const motion::Clip* clip = state.clip();
  if (clip == nullptr || !state.analysis) {
    ImGui::TextDisabled("Open a clip to export its model.");
    ImGui::End();
    return;
  }
  if (e.folder.empty()) e.folder = state.file_path.parent_path().string();
  if (e.name.empty()) e.name = clip->name + "_model";
  const bool have_best = state.evolution.snapshot && !state.evolution.snapshot->best_point.empty();
  if (ImGui::RadioButton("the model", !e.simulated)) e.simulated = false;
  ImGui::SameLine();
  ImGui::BeginDisabled(!have_best);
  // The one selection (issue 16): a run clicked in the viewport or the Evolve panel is the one
  // written; none clicked, the fittest so far.
  const std::optional<ExportedRun> run = exportedRun(state.evolution);
  const bool clicked = run && state.evolution.selected >= 0;
  std::string simulated = "the fittest simulated run###simulated";
  if (clicked) {
    const std::string which = chosenRunLabel(state.evolution);  // "#3 of 23 (clicked)"
    simulated = "the clicked run, " + which.substr(0, which.find(" (")) + "###simulated";
  }
  if (ImGui::RadioButton(simulated.c_str(), e.simulated)) e.simulated = true;
  ImGui::EndDisabled();
  if (clicked && ImGui::IsItemHovered())
    ImGui::SetTooltip("%s, into %s", run->what.c_str(), run->dir.string().c_str());
  if (!have_best && e.simulated) e.simulated = false;
  ImGui::SetNextItemWidth(-60.0f);
  ImGui::InputText("folder", &e.folder);
  if (!e.simulated) {
    ImGui::SetNextItemWidth(160.0f);
    ImGui::InputText("name", &e.name);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(60.0f);
    float fps = static_cast<float>(e.fps);
    if (ImGui::DragFloat("fps", &fps, 1.0f, 1.0f, 240.0f, "%.0f"))
      e.fps = std::clamp(fps, 1.0f, 240.0f);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(60.0f);
    ImGui::DragInt("strides", &e.strides, 0.2f, 1, 100);
    ImGui::Checkbox("BVH", &e.bvh);
    ImGui::SameLine();
    ImGui::Checkbox("glTF (.glb)", &e.gltf);
    ImGui::SameLine();
    ImGui::Checkbox("coefficients (.json)", &e.coefficients);
  } else {
    if (ImGui::RadioButton("the raw run", !e.loop)) e.loop = false;
    ImGui::SameLine();
    if (ImGui::RadioButton("a loop of it", e.loop)) e.loop = true;
    if (e.loop) {
      ImGui::SameLine();
      ImGui::SetNextItemWidth(60.0f);
      ImGui::DragInt("strides", &e.loop_strides, 0.1f, 1, 16);
      e.loop_strides = std::clamp(e.loop_strides, 1, 16);
      ImGui::SameLine();
      ImGui::Checkbox("in place", &e.in_place);
      ImGui::TextDisabled("best_loop.bvh, best_loop.glb and loop.json (seam, foot slide, style)");
    } else {
      ImGui::TextDisabled("best.bvh, best.glb and best.json (replay: sinew simulate --controller)");
    }
  }
  if (ImGui::Button("Export", ImVec2(100.0f, 0.0f))) exportChosen(state);
  ImGui::End();
}

}  // namespace sinew::editor
