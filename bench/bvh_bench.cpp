// BVH reading and writing speed, against a baseline in the same process: scanning the same text
// for numbers with std::from_chars and nothing else (the cost no BVH reader can avoid).
// Prints, per file, MB/s and the ratio reader time / baseline time.
#include <benchmark/benchmark.h>

#include "ratio_reporter.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sinew/core/file_io.h"
#include "sinew/motion/bvh.h"

namespace {

struct Input {
  std::string name;
  std::string text;
};

std::vector<Input>& inputs() {
  static std::vector<Input> all;
  return all;
}

double scanNumbers(const std::string& text) {
  double sum = 0.0;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    double value = 0.0;
    const auto [next, error] = std::from_chars(p, end, value);
    if (error == std::errc()) {
      sum += value;
      p = next;
    } else {
      ++p;
    }
  }
  return sum;
}

void baselineScan(benchmark::State& state, const Input* input) {
  for (auto _ : state) benchmark::DoNotOptimize(scanNumbers(input->text));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * input->text.size()));
}

void readBvh(benchmark::State& state, const Input* input) {
  for (auto _ : state) {
    auto asset = sinew::motion::readBvh(input->text, input->name);
    if (!asset.ok()) state.SkipWithError(asset.message().c_str());
    benchmark::DoNotOptimize(asset);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * input->text.size()));
}

void writeBvh(benchmark::State& state, const Input* input) {
  auto asset = sinew::motion::readBvh(input->text, input->name);
  if (!asset.ok()) {
    state.SkipWithError(asset.message().c_str());
    return;
  }
  const auto& read = asset.value();
  for (auto _ : state) {
    benchmark::DoNotOptimize(sinew::motion::writeBvh(read.skeleton, read.clips[0], read.skeleton.source));
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * input->text.size()));
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::filesystem::path> files = {std::filesystem::path(SINEW_SOURCE_DIR) / "assets" /
                                              "biped_walk.bvh"};
  const std::filesystem::path shared = std::filesystem::path(SINEW_SHARED_DATA) / "bvh";
  for (const char* name : {"bandai_dataset-1_walk_normal_001.bvh", "cmu_131_01.bvh",
                           "cmu-iclone_002_03.bvh"}) {
    if (std::filesystem::exists(shared / name)) files.push_back(shared / name);
  }
  if (files.size() == 1) std::printf("note: %s not found; benchmarking the bundled walk only\n",
                                     shared.c_str());
  for (const auto& path : files) {
    auto text = sinew::readFile(path);
    if (!text.ok()) {
      std::fprintf(stderr, "%s\n", text.message().c_str());
      return 1;
    }
    inputs().push_back({path.filename().string(), std::move(text).value()});
  }
  for (const Input& input : inputs()) {
    benchmark::RegisterBenchmark(("baseline_scan/" + input.name).c_str(), baselineScan, &input);
    benchmark::RegisterBenchmark(("read_bvh/" + input.name).c_str(), readBvh, &input);
    benchmark::RegisterBenchmark(("write_bvh/" + input.name).c_str(), writeBvh, &input);
  }
  const auto options = sinew::bench::consoleOptions(argc, argv);
  benchmark::Initialize(&argc, argv);
  sinew::bench::RatioReporter reporter(options);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\n%-40s %12s %12s\n", "file", "read/scan", "write/scan");
  for (const Input& input : inputs()) {
    const double scan = reporter.times["baseline_scan/" + input.name];
    if (scan <= 0.0) continue;
    std::printf("%-40s %11.2fx %11.2fx\n", input.name.c_str(),
                reporter.times["read_bvh/" + input.name] / scan,
                reporter.times["write_bvh/" + input.name] / scan);
  }
  benchmark::Shutdown();
  return 0;
}
