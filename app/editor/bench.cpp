#include "editor/bench.h"

#include <algorithm>
#include <cstdio>

#include "editor/evolution.h"

namespace sinew::editor {
namespace {

size_t generationsDone(const EditorState& state) {
  return state.evolution.snapshot ? state.evolution.snapshot->history.size() : 0;
}

// Evaluations per second over the generations finished after the first one that ended inside
// the phase: those ran wholly inside it. 0 when there are fewer than two.
double evaluationRate(const EditorState& state, size_t history_at_start, int& whole) {
  whole = 0;
  if (!state.evolution.snapshot) return 0.0;
  const std::vector<search::GenerationRecord>& history = state.evolution.snapshot->history;
  if (history.size() < history_at_start + 2) return 0.0;
  const search::GenerationRecord& first = history[history_at_start];
  const search::GenerationRecord& last = history.back();
  whole = static_cast<int>(history.size() - history_at_start - 1);
  const double seconds = last.wall_s - first.wall_s;
  return seconds > 0.0 ? static_cast<double>(last.evaluations - first.evaluations) / seconds : 0.0;
}

void printPhase(std::string& out, const char* name, const BenchFigures& f) {
  char line[256];
  std::snprintf(line, sizeof line,
                "  %-36s median %6.1f ms (%3.0f fps), 95th percentile %6.1f ms, longest %6.1f "
                "ms, %4d frames in %5.1f s\n",
                name, f.median_ms, f.median_ms > 0 ? 1000.0 / f.median_ms : 0.0, f.p95_ms,
                f.longest_ms, f.frames, f.seconds);
  out += line;
}

void printStages(std::string& out, const char* name, const BenchFigures& f) {
  char line[96];
  std::snprintf(line, sizeof line, "  %-18s", name);
  out += line;
  for (int k = 0; k < kFrameStageCount; ++k) {
    std::snprintf(line, sizeof line, " %s %.1f", frameStageName(static_cast<FrameStage>(k)),
                  f.stage_ms[static_cast<size_t>(k)]);
    out += line;
  }
  out += " (ms per frame)\n";
}

}  // namespace

void EditorBench::beginPhase(BenchPhase phase, const EditorState& state, double now_s,
                             StageProfile& profile) {
  phase_ = phase;
  phase_start_s_ = now_s;
  history_at_start_ = generationsDone(state);
  times_.clear();
  waited_s_ = 0.0;
  profile.clear();
}

void EditorBench::endPhase(const EditorState& state, double now_s, const StageProfile& profile) {
  BenchFigures* f = phase_ == BenchPhase::kAlone       ? &alone_
                    : phase_ == BenchPhase::kSearching ? &searching_
                    : phase_ == BenchPhase::kPaused    ? &paused_
                                                       : nullptr;
  if (f == nullptr) return;
  f->frames = static_cast<int>(times_.size());
  f->seconds = now_s - phase_start_s_;
  f->median_ms = 1000.0 * times_.percentile(0.5);
  f->p95_ms = 1000.0 * times_.percentile(0.95);
  f->longest_ms = 1000.0 * times_.longest();
  for (int k = 0; k < kFrameStageCount; ++k)
    f->stage_ms[static_cast<size_t>(k)] = profile.meanMs(static_cast<FrameStage>(k));
  f->evaluations_per_s = evaluationRate(state, history_at_start_, f->whole_generations);
  f->waited_on_search_ms = 1000.0 * waited_s_;
}

bool EditorBench::phaseComplete(const EditorState& state, double now_s) const {
  const double spent = now_s - phase_start_s_;
  if (phase_ == BenchPhase::kAlone) return static_cast<int>(times_.size()) >= frames_;
  if (spent > limit_s_) return true;
  const bool search_over = !search::underWay(evolutionState(state));
  // The paused scene draws only on change: its phase counts generations, not frames.
  const bool enough_frames =
      phase_ == BenchPhase::kPaused || static_cast<int>(times_.size()) >= frames_;
  return enough_frames && (search_over || generationsDone(state) >= history_at_start_ + 2);
}

void EditorBench::frameDrawn(EditorState& state, double interval_s, double work_s, double now_s,
                             double waited_on_search_s, StageProfile& profile) {
  if (done()) return;
  if (phase_ == BenchPhase::kWaiting) {
    // The population exists once the first generation is in.
    if (generationsDone(state) >= 1) {
      beginPhase(BenchPhase::kSearching, state, now_s, profile);
    } else if (now_s - phase_start_s_ > limit_s_ || !search::underWay(evolutionState(state))) {
      std::fprintf(stderr, "sinew edit: --bench: the search finished no generation in %.0f s\n",
                   limit_s_);
      failed_ = true;
      phase_ = BenchPhase::kDone;
    }
    return;
  }
  times_.add(phase_ == BenchPhase::kPaused ? work_s : interval_s);
  waited_s_ = std::max(waited_s_, waited_on_search_s);
  profile.endFrame();
  if (!phaseComplete(state, now_s)) return;
  endPhase(state, now_s, profile);
  switch (phase_) {
    case BenchPhase::kAlone:
      search_threads_ =
          state.evolution.threads > 0 ? state.evolution.threads : search::hardwareThreads();
      if (!startEvolution(state)) {
        failed_ = true;
        phase_ = BenchPhase::kDone;
        return;
      }
      beginPhase(BenchPhase::kWaiting, state, now_s, profile);
      break;
    case BenchPhase::kSearching:
      state.playback.playing = false;  // the same scene, still: the editor draws only on change
      beginPhase(BenchPhase::kPaused, state, now_s, profile);
      break;
    default:
      phase_ = BenchPhase::kDone;
      break;
  }
}

std::string EditorBench::report(const std::string& renderer, int width, int height,
                                int shown) const {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "editor frame time, %dx%d, %s, search on %d of %d threads:\n",
                width, height, renderer.c_str(), search_threads_, search::hardwareThreads());
  out += line;
  char searching[64];
  std::snprintf(searching, sizeof searching, "%d characters while the search runs:", shown);
  printPhase(out, "the clip alone:", alone_);
  printPhase(out, searching, searching_);
  printPhase(out, "paused, while the search runs:", paused_);
  std::snprintf(line, sizeof line,
                "  ratio (search / alone): median %.2fx, 95th percentile %.2fx\n",
                alone_.median_ms > 0 ? searching_.median_ms / alone_.median_ms : 0.0,
                alone_.p95_ms > 0 ? searching_.p95_ms / alone_.p95_ms : 0.0);
  out += line;
  out += "where a frame goes:\n";
  printStages(out, "the clip alone:", alone_);
  printStages(out, "while searching:", searching_);
  std::snprintf(line, sizeof line, "  paused: %.1f frames drawn per second\n",
                paused_.seconds > 0 ? paused_.frames / paused_.seconds : 0.0);
  out += line;
  auto rate = [](const BenchFigures& f, char* text, size_t size) {
    if (f.whole_generations < 1)
      std::snprintf(text, size, "n/a (no whole generation in the phase)");
    else
      std::snprintf(text, size, "%.2f evaluations/s over %d generations", f.evaluations_per_s,
                    f.whole_generations);
  };
  char drawing[96], idle[96];
  rate(searching_, drawing, sizeof drawing);
  rate(paused_, idle, sizeof idle);
  std::snprintf(line, sizeof line, "the search: %s with the editor drawing, %s paused\n", drawing,
                idle);
  out += line;
  std::snprintf(line, sizeof line,
                "the UI thread's longest wait for the search's snapshot: %.2f ms while searching, "
                "%.2f ms paused\n",
                searching_.waited_on_search_ms, paused_.waited_on_search_ms);
  out += line;
  return out;
}

}  // namespace sinew::editor
