// A console reporter that remembers each benchmark's fastest time, so that a benchmark's main can
// print ratios against a baseline measured in the same process.
#pragma once

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace sinew::bench {

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  explicit RatioReporter(OutputOptions options) : ConsoleReporter(options) {}

  void ReportRuns(const std::vector<Run>& runs) override {
    // The fastest repetition (--benchmark_repetitions=N): on a shared machine, the others
    // measure the neighbours.
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Aggregate) continue;
      const double time = run.GetAdjustedRealTime();
      auto [it, inserted] = times.emplace(run.benchmark_name(), time);
      if (!inserted) it->second = std::min(it->second, time);
    }
    ConsoleReporter::ReportRuns(runs);
  }

  std::map<std::string, double> times;  // fastest run, in each benchmark's time unit
};

// A reporter of our own does not see --benchmark_color: colour only on a terminal that did not
// turn it off, so that CI logs stay plain text. Call before benchmark::Initialize.
inline benchmark::ConsoleReporter::OutputOptions consoleOptions(int argc, char** argv) {
  bool colour = isatty(fileno(stdout)) != 0;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    if (flag == "--benchmark_color=false" || flag == "--benchmark_color=no" ||
        flag == "--benchmark_color=0") {
      colour = false;
    }
  }
  return colour ? benchmark::ConsoleReporter::OO_Defaults : benchmark::ConsoleReporter::OO_None;
}

}  // namespace sinew::bench
