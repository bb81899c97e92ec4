// sinew evolve --batch: a library of clips, one search each, into OUT/<clip name>/ with its usual
// files and evolve.log; OUT/summary.csv and OUT/summary.json list every clip done so far. On one
// process the clips go in turn; under mpirun rank 0 hands them out to the other ranks as they
// become free; as a scheduler's job array each task runs one (`--batch-index I`). Every clip
// leaves OUT/<name>/result.json, and the summary is rebuilt from all of them after each clip, so
// the tasks of a job array need no coordinator: the last to finish writes the whole table.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/evolve.h"
#include "sinew/core/file_io.h"
#include "sinew/core/path_json.h"
#include "sinew/search/session.h"

namespace sinew::app {
namespace {

namespace fs = std::filesystem;

bool isMotionFile(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".bvh" || ext == ".glb" || ext == ".gltf";
}

// The batch's clips: a folder's motion files (.bvh, .glb, .gltf; sorted by name), or a list
// file's lines (paths relative to the list's folder; blank lines and '#' comments skipped).
Result<std::vector<fs::path>> batchClips(const std::string& source) {
  std::error_code ec;
  std::vector<fs::path> clips;
  if (fs::is_directory(source, ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(source, ec))
      if (e.is_regular_file() && isMotionFile(e.path())) clips.push_back(e.path());
    std::sort(clips.begin(), clips.end());
    if (clips.empty())
      return Status::error(source + ": no .bvh, .glb or .gltf file in this folder");
    return clips;
  }
  std::ifstream list(source);
  if (!list)
    return Status::error(source + ": cannot read the batch list (a folder or a file of paths)");
  std::string line;
  for (int number = 1; std::getline(list, line); ++number) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const size_t last = line.find_last_not_of(" \t\r");
    fs::path clip = line.substr(first, last - first + 1);
    if (clip.is_relative()) clip = fs::path(source).parent_path() / clip;
    if (!fs::is_regular_file(clip, ec))
      return Status::error(source + ":" + std::to_string(number) + ": " + clip.string() +
                           ": no such file");
    clips.push_back(clip);
  }
  if (clips.empty()) return Status::error(source + ": the batch list names no clip");
  return clips;
}

// Output folders: each clip's file stem, with "_2", "_3", ... when two clips share one.
std::vector<std::string> folderNames(const std::vector<fs::path>& clips) {
  std::vector<std::string> names;
  std::map<std::string, int> seen;
  for (const fs::path& clip : clips) {
    const std::string stem = clip.stem().string();
    const int n = ++seen[stem];
    names.push_back(n == 1 ? stem : stem + "_" + std::to_string(n));
  }
  return names;
}

// stdout goes to `path` while this lives (a clip's per-generation lines go to its evolve.log).
class StdoutTo {
 public:
  explicit StdoutTo(const fs::path& path) {
    std::fflush(stdout);
    saved_ = dup(STDOUT_FILENO);
    const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      close(fd);
    }
  }
  ~StdoutTo() {
    std::fflush(stdout);
    if (saved_ >= 0) {
      dup2(saved_, STDOUT_FILENO);
      close(saved_);
    }
  }
  StdoutTo(const StdoutTo&) = delete;
  StdoutTo& operator=(const StdoutTo&) = delete;

 private:
  int saved_ = -1;
};

// What a clip's run left: its row of the summary, from best.json and checkpoint.json.
nlohmann::json resultRow(const fs::path& clip, const fs::path& dir, int exit_code, double wall_s,
                         int rank) {
  nlohmann::json row = {{"folder", dir.filename().string()},
                        {"exit_code", exit_code},
                        {"wall_s", wall_s},
                        {"rank", rank}};
  writePathJson(row, "clip", clip.string());
  try {
    std::ifstream best(dir / "best.json");
    const nlohmann::json fitness = nlohmann::json::parse(best).at("fitness");
    row["stood_up_s"] = fitness.at("survived_s");
    row["fell"] = fitness.at("fell");
    row["fell_because"] = fitness.value("fall_reason", "");
    row["distance_m"] = fitness.at("distance_m");
    row["speed_m_s"] = fitness.at("speed_m_s");
    row["tracking_deg"] = fitness.at("track_err_rad_rms").get<double>() * 180.0 / std::numbers::pi;
    row["cost"] = fitness.at("total");
    std::ifstream checkpoint(dir / "checkpoint.json");
    const nlohmann::json history = nlohmann::json::parse(checkpoint).at("history");
    row["generations"] = history.empty() ? 0 : history.back().at("generation").get<int>();
    row["evaluations"] = history.empty() ? 0 : history.back().at("evaluations").get<long long>();
    row["status"] = exit_code == 0 ? "ok" : (exit_code == 130 ? "interrupted" : "failed");
  } catch (const nlohmann::json::exception&) {
    row["status"] = "failed: no result (see " + (dir / "evolve.log").string() + " and stderr)";
  }
  return row;
}

// Evolves one clip into OUT/<folder>/ (the flags as given, the clip as its own rig, or as --clip
// of the one --rig) and writes its result.json. Returns the row.
nlohmann::json evolveClip(const EvolveArgs& args, const fs::path& clip, const std::string& folder,
                          const distributed::Ranks& ranks) {
  EvolveArgs one = args;
  one.batch.clear();
  one.batch_index = -1;
  if (ranks.size > 1 &&
      one.threads == 0)  // rank 0 only hands out clips: the others share the cores
    one.threads =
        std::max(1, search::hardwareThreads() / std::max(1, distributed::localRanks() - 1));
  (args.rig.empty() ? one.rig : one.clip) = clip.string();
  const fs::path dir = fs::path(args.out) / folder;
  one.out = dir.string();
  std::error_code ec;
  fs::create_directories(dir, ec);
  const auto t0 = std::chrono::steady_clock::now();
  int code = 0;
  {
    StdoutTo log(dir / "evolve.log");
    code = runEvolveOn(one, {});
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json row = resultRow(clip, dir, code, wall_s, ranks.rank);
  if (Status s = writeFileAtomically(dir / "result.json", row.dump(2) + "\n"); !s.ok())
    std::fprintf(stderr, "sinew: warning: %s\n", s.message().c_str());
  return row;
}

std::string csvField(const nlohmann::json& row, const char* key) {
  if (!row.contains(key)) return "";
  const nlohmann::json& v = row.at(key);
  if (v.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v.get<double>());
    return text;
  }
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (s.find_first_of(",\"\n") != std::string::npos) {
    std::string quoted = "\"";
    for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
  }
  return s;
}

// summary.csv and summary.json from every OUT/<folder>/result.json there is (in batch order).
// Returns how many rows they have.
Result<int> writeSummary(const fs::path& out, const std::vector<std::string>& folders) {
  static const char* kColumns[] = {
      "clip",        "status",       "stood_up_s", "fell",        "fell_because",
      "distance_m",  "speed_m_s",    "tracking_deg", "cost",      "generations",
      "evaluations", "wall_s",       "rank",         "folder"};
  nlohmann::json rows = nlohmann::json::array();
  std::ostringstream csv;
  for (size_t c = 0; c < std::size(kColumns); ++c) csv << (c ? "," : "") << kColumns[c];
  csv << '\n';
  for (const std::string& folder : folders) {
    std::ifstream in(out / folder / "result.json");
    if (!in) continue;
    nlohmann::json row;
    try {
      row = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception&) {
      continue;  // being written by another task right now: the next summary has it
    }
    for (size_t c = 0; c < std::size(kColumns); ++c)
      csv << (c ? "," : "") << csvField(row, kColumns[c]);
    csv << '\n';
    rows.push_back(std::move(row));
  }
  if (Status s = writeFileAtomically(out / "summary.csv", csv.str()); !s.ok()) return s;
  const nlohmann::json summary = {{"format", "sinew.batch_summary"}, {"clips", rows}};
  if (Status s = writeFileAtomically(out / "summary.json", summary.dump(2) + "\n"); !s.ok())
    return s;
  return static_cast<int>(rows.size());
}

void printRow(const nlohmann::json& row, int done, int total) {
  if (row.value("status", "") != "ok") {
    std::printf("[%d/%d] %s: %s\n", done, total, row.at("folder").get<std::string>().c_str(),
                row.value("status", "").c_str());
  } else {
    std::printf(
        "[%d/%d] %s: up %.1f s, %.1f m, %.2f m/s, tracking %.1f deg, cost %.2f, %d "
        "generations, %.0f s (rank %d)\n",
        done, total, row.at("folder").get<std::string>().c_str(),
        row.at("stood_up_s").get<double>(), row.at("distance_m").get<double>(),
        row.at("speed_m_s").get<double>(), row.at("tracking_deg").get<double>(),
        row.at("cost").get<double>(), row.at("generations").get<int>(),
        row.at("wall_s").get<double>(), row.at("rank").get<int>());
    if (row.value("fell", false) && !row.value("fell_because", "").empty())
      std::printf("    fell: %s\n", row.at("fell_because").get<std::string>().c_str());
  }
  std::fflush(stdout);
}

}  // namespace

int runBatch(const EvolveArgs& args, const distributed::Ranks& ranks) {
  Result<std::vector<fs::path>> clips = batchClips(args.batch);
  if (!clips.ok()) return fail(clips.message());
  const std::vector<std::string> folders = folderNames(clips.value());
  const int total = static_cast<int>(folders.size());
  const fs::path out(args.out);
  if (args.batch_index >= total)
    return fail("--batch-index " + std::to_string(args.batch_index) + ": the batch has " +
                std::to_string(total) + " clips (0.." + std::to_string(total - 1) + ")");
  int failures = 0, done = 0, rows = 0;
  auto finished = [&](const nlohmann::json& row) {
    if (row.value("exit_code", 1) != 0) ++failures;
    printRow(row, ++done, args.batch_index >= 0 ? 1 : total);
    Result<int> wrote = writeSummary(out, folders);
    if (!wrote.ok()) std::fprintf(stderr, "sinew: %s\n", wrote.message().c_str());
    rows = wrote.ok() ? wrote.value() : rows;
  };
  if (ranks.rank == 0)
    std::printf(
        "batch of %d clips from %s into %s%s\n", total, args.batch.c_str(), args.out.c_str(),
        ranks.size > 1 ? (", over " + std::to_string(ranks.size - 1) + " ranks").c_str() : "");
  if (args.batch_index >= 0) {
    const size_t i = static_cast<size_t>(args.batch_index);
    finished(evolveClip(args, clips.value()[i], folders[i], ranks));
  } else if (ranks.size == 1) {
    for (size_t i = 0; i < folders.size(); ++i)
      finished(evolveClip(args, clips.value()[i], folders[i], ranks));
  } else {
#if SINEW_HAVE_MPI
    if (ranks.rank == 0) {
      distributed::dispatch(ranks, total, [&](int job, int, int) {
        std::ifstream in(out / folders[static_cast<size_t>(job)] / "result.json");
        nlohmann::json row = nlohmann::json::parse(in, nullptr, false);
        if (row.is_discarded())
          row = {{"folder", folders[static_cast<size_t>(job)]},
                 {"status", "failed: no result.json"},
                 {"exit_code", 1}};
        finished(row);
      });
    } else {
      for (int job = distributed::nextJob(-1, 0); job >= 0;) {
        const nlohmann::json row = evolveClip(args, clips.value()[static_cast<size_t>(job)],
                                              folders[static_cast<size_t>(job)], ranks);
        job = distributed::nextJob(job, row.value("exit_code", 1));
      }
      return 0;
    }
#endif
  }
  if (ranks.rank == 0)
    std::printf("wrote %s: summary.csv, summary.json (%d of %d clips%s)\n", args.out.c_str(), rows,
                total,
                failures > 0 ? (", " + std::to_string(failures) + " failed here").c_str() : "");
  return failures > 0 ? 1 : 0;
}

}  // namespace sinew::app
