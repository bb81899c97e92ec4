// Evolve: runs the search on the loaded rig from the model being edited and shows it live: the
// budget and window, start/pause/resume/stop, the generation, the best individual's terms, the
// best cost per generation (the Export panel writes the best). The
// viewport replays the population's runs beside the clip while it is shown.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <imgui.h>

#include "editor/panels/panels.h"

namespace sinew::editor {
namespace {

void plotHistory(const search::Snapshot& snap) {
  // The best so far after each generation (a generation's own best can be worse than an earlier
  // one: CMA-ES samples afresh every generation).
  std::vector<float> best;
  for (const search::GenerationRecord& r : snap.history) {
    const float cost = static_cast<float>(r.total.best);
    best.push_back(best.empty() ? cost : std::min(best.back(), cost));
  }
  if (best.empty()) return;
  const float top = best.front();
  char label[64];
  std::snprintf(label, sizeof label, "best cost so far (%.1f -> %.2f)", best.front(), best.back());
  ImGui::TextDisabled("%s", label);
  ImGui::PlotLines("##best", best.data(), static_cast<int>(best.size()), 0, nullptr, 0.0f,
                   top * 1.05f, ImVec2(ImGui::GetContentRegionAvail().x, 56.0f));
}

}  // namespace

void drawEvolvePanel(EditorState& state) {
  ImGui::Begin("Evolve", nullptr, ImGuiWindowFlags_NoCollapse);
  EvolutionState& evolution = state.evolution;
  const std::string run_state = evolution.snapshot ? evolution.snapshot->state : "";
  const bool running = run_state == "running" || run_state == "paused";
  if (!state.analysis) {
    ImGui::TextDisabled("Open a clip that analyses to evolve its physical motion.");
    ImGui::End();
    return;
  }

  ImGui::BeginDisabled(running);
  ImGui::SetNextItemWidth(120.0f);
  float minutes = static_cast<float>(evolution.settings.minutes);
  if (ImGui::SliderFloat("minutes", &minutes, 0.5f, 30.0f, "%.1f"))
    evolution.settings.minutes = minutes;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(100.0f);
  float window = static_cast<float>(evolution.settings.window_s);
  if (ImGui::SliderFloat("window s", &window, 2.0f, 20.0f, "%.0f"))
    evolution.settings.window_s = window;
  ImGui::Checkbox("no prior (baseline)", &evolution.settings.no_prior);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0f);
  const bool ga = evolution.settings.optimizer == "ga";
  if (ImGui::BeginCombo("optimiser", ga ? "GA" : "CMA-ES")) {
    if (ImGui::Selectable("CMA-ES", !ga)) evolution.settings.optimizer = "cmaes";
    if (ImGui::Selectable("GA (baseline)", ga)) evolution.settings.optimizer = "ga";
    ImGui::EndCombo();
  }
  ImGui::SetNextItemWidth(90.0f);
  ImGui::InputInt("population", &evolution.settings.population, 1, 4);
  evolution.settings.population = std::clamp(evolution.settings.population, 0, 1000);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("0: the optimiser's default (CMA-ES 4 + 3 ln n)");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90.0f);
  int seed = static_cast<int>(evolution.settings.seed);
  if (ImGui::InputInt("seed", &seed))
    evolution.settings.seed = static_cast<std::uint64_t>(std::max(seed, 0));
  ImGui::EndDisabled();
  if (ImGui::TreeNode("fitness weights")) {
    // Live: a running search takes them from its next generation.
    bool changed = false;
    for (int k = 0; k < search::kFitnessTermCount; ++k) {
      float w = static_cast<float>(search::fitnessWeight(evolution.settings.weights, k));
      ImGui::SetNextItemWidth(120.0f);
      if (ImGui::DragFloat(search::fitnessTermName(k), &w, 0.01f, 0.0f, 100.0f, "%.3f")) {
        search::fitnessWeight(evolution.settings.weights, k) = std::max(w, 0.0f);
        changed = true;
      }
      if (k % 2 == 0 && k + 1 < search::kFitnessTermCount) ImGui::SameLine();
    }
    if (changed) setEvolutionWeights(state);
    ImGui::TreePop();
  }

  if (!running) {
    if (ImGui::Button(evolution.snapshot ? "Start again" : "Start")) startEvolution(state);
  } else {
    if (run_state == "paused") {
      if (ImGui::Button("Resume")) resumeEvolution(state);
    } else if (ImGui::Button("Pause")) {
      pauseEvolution(state);
    }
    ImGui::SameLine();
    if (ImGui::Button("Stop")) stopEvolution(state);
  }
  ImGui::SameLine();
  ImGui::Checkbox("show population", &evolution.show_population);

  if (evolution.snapshot) {
    const search::Snapshot& snap = *evolution.snapshot;
    const double wall = snap.history.empty() ? 0.0 : snap.history.back().wall_s;
    ImGui::Text("%s: generation %d, %lld evaluations, %.0f s (%.1f eval/s)", run_state.c_str(),
                snap.generation, snap.evaluations, wall,
                wall > 0.0 ? static_cast<double>(snap.evaluations) / wall : 0.0);
    if (!snap.best_point.empty()) {
      // The individual clicked in the viewport, or the best so far.
      const int picked = evolution.selected;
      const bool show_picked =
          picked >= 0 && picked < static_cast<int>(snap.population_terms.size());
      const search::FitnessTerms& t =
          show_picked ? snap.population_terms[static_cast<size_t>(picked)] : snap.best_terms;
      if (show_picked) {
        int rank = 1;
        for (const search::FitnessTerms& other : snap.population_terms)
          rank += other.total < t.total;
        ImGui::TextColored(ImVec4(1.0f, 0.95f, 0.8f, 1.0f), "clicked: #%d of %zu in generation %d",
                           rank, snap.population_terms.size(), snap.generation);
        ImGui::SameLine();
        if (ImGui::SmallButton("show the best")) evolution.selected = -1;
      }
      ImGui::Text("%s: %s %.1f s, %.2f m (%.2f m/s), cost %.2f", show_picked ? "it" : "best",
                  t.fell ? "fell after" : "walked", t.survived_s, t.distance_m, t.speed_m_s,
                  t.total);
      if (ImGui::BeginTable("terms", search::kFitnessTermCount,
                            ImGuiTableFlags_SizingStretchSame)) {
        for (int k = 0; k < search::kFitnessTermCount; ++k)
          ImGui::TableSetupColumn(search::fitnessTermName(k));
        ImGui::TableHeadersRow();
        ImGui::TableNextRow();
        for (int k = 0; k < search::kFitnessTermCount; ++k) {
          ImGui::TableNextColumn();
          ImGui::Text("%.2f", search::fitnessTerm(t, k));
        }
        ImGui::EndTable();
      }
      plotHistory(snap);
    }
  } else {
    ImGui::TextWrapped(
        "Evolves the clip's Fourier controller (seeded from the model above) until "
        "the simulated character keeps the style without falling.");
  }
  ImGui::End();
}

}  // namespace sinew::editor
