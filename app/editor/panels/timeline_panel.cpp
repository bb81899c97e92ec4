// Timeline: play/pause, frame stepping, scrubbing in frames (seconds shown), speed, loop, and what
// the viewport shows (original, reconstructed model (the target), the search's simulated runs and
// the target's ghost over the chosen one, beside or overlaid, camera follow, shadows, a glTF
// character's skinned mesh and its skeleton over it).
#include <algorithm>
#include <cmath>
#include <cstring>

#include <imgui.h>

#include "editor/ghost.h"
#include "editor/panels/panels.h"

namespace sinew::editor {

void drawTimelinePanel(EditorState& state) {
  if (!ImGui::Begin("Timeline", nullptr, ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  const motion::Clip* clip = state.clip();
  if (clip == nullptr) {
    ImGui::TextDisabled("Open a clip to play it.");
    ImGui::End();
    return;
  }
  Playback& playback = state.playback;
  const int last = clip->frame_count - 1;
  int frame =
      std::clamp(static_cast<int>(std::lround(playback.time_s / clip->frame_time)), 0, last);

  if (ImGui::Button(playback.playing ? "Pause" : "Play", ImVec2(64.0f, 0.0f))) {
    playback.playing = !playback.playing;
  }
  ImGui::SameLine();
  if (ImGui::ArrowButton("##back", ImGuiDir_Left)) {
    playback.playing = false;
    playback.time_s = std::max(frame - 1, 0) * clip->frame_time;
  }
  ImGui::SameLine();
  if (ImGui::ArrowButton("##forward", ImGuiDir_Right)) {
    playback.playing = false;
    playback.time_s = std::min(frame + 1, last) * clip->frame_time;
  }
  ImGui::SameLine();
  ImGui::Checkbox("Loop", &playback.loop);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(110.0f);
  float speed = static_cast<float>(playback.speed);
  if (ImGui::SliderFloat("Speed", &speed, 0.1f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic)) {
    playback.speed = speed;
  }
  ImGui::SameLine();
  ImGui::Text(" %6.3f s / %.3f s", playback.time_s, clip->duration());
  // How the character is drawn, on this row: the view toggles' row below is full.
  ViewToggles& look = state.view;
  ImGui::SameLine();
  ImGui::TextDisabled("|");
  ImGui::SameLine();
  ImGui::Checkbox("Shadows", &look.shadows);
  ImGui::SameLine();
  const bool has_mesh = state.asset && !state.asset->meshes.empty();
  ImGui::BeginDisabled(!has_mesh);
  ImGui::Checkbox("Mesh", &look.show_mesh);
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip(has_mesh ? "The glTF character's skinned mesh (off: capsules)"
                               : "This file has no skinned mesh");
  }
  ImGui::SameLine();
  ImGui::BeginDisabled(!look.show_mesh);
  ImGui::Checkbox("Skeleton", &look.show_skeleton);
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip("The skeleton's capsules over the mesh, translucent");
  }
  ImGui::EndDisabled();
  ImGui::EndDisabled();

  ImGui::SetNextItemWidth(-1.0f);
  char label[160];
  std::snprintf(label, sizeof label, "frame %d / %d  (%.2f s)", frame, last,
                frame * clip->frame_time);
  // The simulated run every panel shows (issue 16), and where in its own loop it is replayed.
  const EvolutionState& evolution = state.evolution;
  const int chosen = evolution.show_population ? chosenIndividual(evolution) : -1;
  if (chosen >= 0) {
    const motion::Clip& run = evolution.snapshot->population_motions[static_cast<size_t>(chosen)];
    const std::string which = chosenRunLabel(evolution);
    const size_t used = std::strlen(label);
    std::snprintf(label + used, sizeof label - used, "   run %s at %.2f s", which.c_str(),
                  replayedFrame(run, playback.time_s) * run.frame_time);
  }
  if (ImGui::SliderInt("##scrub", &frame, 0, last, label)) {
    playback.time_s = frame * clip->frame_time;
  }
  if (ImGui::IsItemActive()) playback.playing = false;

  ViewToggles& view = state.view;
  ImGui::Checkbox("Original", &view.show_original);
  ImGui::SameLine();
  ImGui::BeginDisabled(!state.analysis);
  ImGui::Checkbox("Reconstructed (model)", &view.show_model);
  ImGui::SameLine();
  ImGui::Checkbox("Beside", &view.model_beside);
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Off: the model is overlaid on the original");
  ImGui::SameLine();
  const bool has_runs =
      state.evolution.snapshot && !state.evolution.snapshot->population_motions.empty();
  ImGui::BeginDisabled(!has_runs);
  ImGui::Checkbox("Simulated", &state.evolution.show_population);
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip(has_runs ? "The search's last generation, replayed beside the clip"
                               : "No search has finished a generation yet");
  ImGui::SameLine();
  ImGui::BeginDisabled(!has_runs || !state.evolution.show_population);
  ImGui::Checkbox("Ghost", &state.evolution.show_ghost);
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip(
        "The search's target drawn over the chosen run (the best, or the one\n"
        "clicked), each bone grey where the run follows it, to red at %.0f deg\n"
        "or more off; the Evolve panel gives the degrees per joint",
        kGhostRedDeg);
  ImGui::SameLine();
  ImGui::TextDisabled("|");
  ImGui::SameLine();
  ImGui::Checkbox("Follow", &view.follow);
  ImGui::SameLine();
  ImGui::Checkbox("Grid", &view.show_grid);
  ImGui::SameLine();
  ImGui::Checkbox("End sites", &view.show_end_sites);
  ImGui::SameLine();
  if (ImGui::Button("Frame (F)")) state.frame_requested = true;
  ImGui::End();
}

}  // namespace sinew::editor
