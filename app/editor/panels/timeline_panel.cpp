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
namespace {

// Keeps the next item on this row when `width` of it still fits, else lets it start a new row:
// the toggles wrap in a narrow panel instead of running off its edge. Returns whether it stayed.
bool sameLineIfFits(float width) {
  const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
  const bool fits = ImGui::GetItemRectMax().x + ImGui::GetStyle().ItemSpacing.x + width <= right;
  if (fits) ImGui::SameLine();
  return fits;
}

float checkboxWidth(const char* label) {
  return ImGui::GetFrameHeight() + ImGui::GetStyle().ItemInnerSpacing.x +
         ImGui::CalcTextSize(label, nullptr, true).x;
}

// A checkbox after the last item, on its row if it fits.
bool toggle(const char* label, bool* value) {
  sameLineIfFits(checkboxWidth(label));
  return ImGui::Checkbox(label, value);
}

// A faint bar between groups of toggles, where the next one (`next` wide) still fits after it;
// none at the start of a wrapped row.
void groupBar(float next) {
  const float bar = ImGui::CalcTextSize("|").x + ImGui::GetStyle().ItemSpacing.x;
  if (!sameLineIfFits(bar + next)) return;
  ImGui::TextDisabled("|");
}

// Row 1: play, step, loop, speed, the time; then how the character is drawn (the view toggles'
// row below is full).
void drawTransportRow(EditorState& state, const motion::Clip& clip, int frame, int last) {
  Playback& playback = state.playback;
  if (ImGui::Button(playback.playing ? "Pause" : "Play", ImVec2(64.0f, 0.0f))) {
    playback.playing = !playback.playing;
  }
  ImGui::SameLine();
  if (ImGui::ArrowButton("##back", ImGuiDir_Left)) {
    playback.playing = false;
    playback.time_s = std::max(frame - 1, 0) * clip.frame_time;
  }
  ImGui::SameLine();
  if (ImGui::ArrowButton("##forward", ImGuiDir_Right)) {
    playback.playing = false;
    playback.time_s = std::min(frame + 1, last) * clip.frame_time;
  }
  ImGui::SameLine();
  ImGui::Checkbox("Loop", &playback.loop);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(84.0f);
  float speed = static_cast<float>(playback.speed);
  if (ImGui::SliderFloat("Speed", &speed, 0.1f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic)) {
    playback.speed = speed;
  }
  ImGui::SameLine();
  ImGui::Text("%.2f / %.2f s", playback.time_s, clip.duration());
  ViewToggles& look = state.view;
  groupBar(checkboxWidth("Shadows"));
  toggle("Shadows", &look.shadows);
  const bool has_mesh = state.asset && !state.asset->meshes.empty();
  ImGui::BeginDisabled(!has_mesh);
  toggle("Mesh", &look.show_mesh);
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip(has_mesh ? "The glTF character's skinned mesh (off: capsules)"
                               : "This file has no skinned mesh");
  }
  ImGui::BeginDisabled(!look.show_mesh);
  toggle("Skeleton", &look.show_skeleton);
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) {
    ImGui::SetTooltip("The skeleton's capsules over the mesh, translucent");
  }
  ImGui::EndDisabled();
  ImGui::EndDisabled();
}

// Row 2: the scrubber, in frames, with the chosen run's own time.
void drawScrubber(EditorState& state, const motion::Clip& clip, int frame, int last) {
  Playback& playback = state.playback;
  ImGui::SetNextItemWidth(-1.0f);
  char label[160];
  std::snprintf(label, sizeof label, "frame %d / %d  (%.2f s)", frame, last,
                frame * clip.frame_time);
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
    playback.time_s = frame * clip.frame_time;
  }
  if (ImGui::IsItemActive()) playback.playing = false;
}

// Row 3: what the viewport shows.
void drawViewToggles(EditorState& state) {
  ViewToggles& view = state.view;
  ImGui::Checkbox("Original", &view.show_original);
  ImGui::BeginDisabled(!state.analysis);
  toggle("Model", &view.show_model);
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("The reconstructed model: the harmonic series the search tracks");
  toggle("Beside", &view.model_beside);
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Off: the model is overlaid on the original");
  const bool has_runs =
      state.evolution.snapshot && !state.evolution.snapshot->population_motions.empty();
  ImGui::BeginDisabled(!has_runs);
  toggle("Runs", &state.evolution.show_population);
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip(has_runs ? "The search's last generation, replayed beside the clip"
                               : "No search has finished a generation yet");
  ImGui::BeginDisabled(!has_runs || !state.evolution.show_population);
  toggle("Ghost", &state.evolution.show_ghost);
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip(
        "The search's target drawn over the chosen run (the best, or the one\n"
        "clicked), each bone grey where the run follows it, to red at %.0f deg\n"
        "or more off; the Evolve panel gives the degrees per joint",
        kGhostRedDeg);
  groupBar(checkboxWidth("Follow"));
  toggle("Follow", &view.follow);
  toggle("Grid", &view.show_grid);
  toggle("End sites", &view.show_end_sites);
  sameLineIfFits(ImGui::CalcTextSize("Frame").x + 2.0f * ImGui::GetStyle().FramePadding.x);
  if (ImGui::Button("Frame")) state.frame_requested = true;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Frame the character in the viewport (F)");
}

}  // namespace

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
  const int last = clip->frame_count - 1;
  const int frame =
      std::clamp(static_cast<int>(std::lround(state.playback.time_s / clip->frame_time)), 0, last);
  drawTransportRow(state, *clip, frame, last);
  drawScrubber(state, *clip, frame, last);
  drawViewToggles(state);
  ImGui::End();
}

}  // namespace sinew::editor
