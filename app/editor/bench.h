// The editor's frame-time benchmark (`sinew edit --bench`, bench/editor_bench): in one window and
// one process, the clip alone, then `shown` characters of the population replaying while the
// search runs, then the same scene paused (the editor draws only when something changes), each
// with its frame times, where they went (StageProfile), and the search's evaluations per second
// measured over whole generations inside the phase. Plain code: the main loop feeds it frames.
#pragma once

#include <array>
#include <string>

#include "editor/editor_state.h"
#include "editor/frame_stats.h"

namespace sinew::editor {

enum class BenchPhase { kAlone, kWaiting, kSearching, kPaused, kDone };

struct BenchFigures {
  int frames = 0;
  double seconds = 0.0;    // of wall time in the phase
  double median_ms = 0.0;  // frame time: between frames (active phases), or the work of a
  double p95_ms = 0.0;     // drawn frame (the paused phase, which waits between frames)
  double longest_ms = 0.0;
  std::array<double, kFrameStageCount> stage_ms{};  // mean per frame
  double evaluations_per_s = 0.0;    // over the whole generations finished inside the phase; 0:
  int whole_generations = 0;         // fewer than one
  double waited_on_search_ms = 0.0;  // the longest time a frame waited for the session's lock
};

class EditorBench {
 public:
  // `frames` per phase at least; the search phases also last until two generations have finished
  // in them (at most `phase_limit_s`).
  EditorBench(int frames, double phase_limit_s = 120.0)
      : frames_(frames), limit_s_(phase_limit_s) {}

  BenchPhase phase() const { return phase_; }
  bool done() const { return phase_ == BenchPhase::kDone; }
  bool failed() const { return failed_; }

  // One frame was drawn: `interval_s` since the last one, `work_s` of it spent working (not
  // waiting for events), `now_s` the run's clock. Moves through the phases: starts the search
  // (startEvolution) after the clip alone, pauses playback for the paused phase.
  void frameDrawn(EditorState& state, double interval_s, double work_s, double now_s,
                  double waited_on_search_s, StageProfile& profile);

  // The table: one line per phase, then where the frames went and the search's rates.
  std::string report(const std::string& renderer, int width, int height, int shown) const;

 private:
  void beginPhase(BenchPhase phase, const EditorState& state, double now_s, StageProfile& profile);
  void endPhase(const EditorState& state, double now_s, const StageProfile& profile);
  bool phaseComplete(const EditorState& state, double now_s) const;

  int frames_;
  double limit_s_;
  BenchPhase phase_ = BenchPhase::kAlone;
  bool failed_ = false;
  int search_threads_ = 0;
  double phase_start_s_ = 0.0;
  size_t history_at_start_ = 0;  // generations finished when the phase began
  FrameTimes times_{100000};
  double waited_s_ = 0.0;
  BenchFigures alone_, searching_, paused_;
};

}  // namespace sinew::editor
