#include "cli/analyze_plot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <system_error>

#include "sinew/core/file_io.h"
#include "sinew/spectral/plot.h"

extern char** environ;

namespace sinew::app {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// The program's full path if it is an executable file in a PATH directory, else empty.
std::filesystem::path findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return {};
  std::string dirs = path;
  size_t begin = 0;
  while (begin <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', begin), dirs.size());
    const std::string dir = dirs.substr(begin, end - begin);
    const std::filesystem::path candidate =
        std::filesystem::path(dir.empty() ? "." : dir) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    begin = end + 1;
  }
  return {};
}

// Runs a program with arguments (no shell, so paths need no quoting); its exit code, or -1.
int runProgram(const std::filesystem::path& program, const std::vector<std::string>& arguments) {
  std::vector<std::string> argv_strings = {program.string()};
  argv_strings.insert(argv_strings.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& s : argv_strings) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

Status writePng(const std::filesystem::path& path, const std::string& svg) {
  const std::filesystem::path converter = findOnPath("rsvg-convert");
  if (converter.empty()) {
    return Status::error(path.string() +
                         ": writing PNG needs rsvg-convert, which is not on PATH; install it "
                         "(sudo apt-get install librsvg2-bin) or write an .svg instead");
  }
  // Both intermediate files sit beside the target, so the final rename stays on one file system
  // and a failed conversion leaves any existing PNG untouched.
  const std::string stem = path.string() + ".tmp-" + std::to_string(::getpid());
  const std::filesystem::path svg_path = stem + ".svg";
  const std::filesystem::path png_path = stem + ".png";
  if (Status status = writeFileAtomically(svg_path, svg); !status.ok()) return status;
  const int code = runProgram(converter, {"--format=png", "--background-color=white",
                                          "--output=" + png_path.string(), svg_path.string()});
  std::error_code ignored;
  std::filesystem::remove(svg_path, ignored);
  if (code != 0) {
    std::filesystem::remove(png_path, ignored);
    return Status::error(
        path.string() + ": rsvg-convert failed (" +
        (code < 0 ? std::string("could not run it") : "exit code " + std::to_string(code)) + ")");
  }
  std::error_code error;
  std::filesystem::rename(png_path, path, error);
  if (error) {
    std::filesystem::remove(png_path, ignored);
    return Status::error(path.string() + ": cannot write: " + error.message());
  }
  return {};
}

}  // namespace

Status writePlot(const std::filesystem::path& path, const motion::Skeleton& skeleton,
                 const motion::Clip& clip, const spectral::MotionSpectrum& spectrum,
                 const std::vector<std::string>& joint_names) {
  const std::string ext = lowerExtension(path);
  if (ext != ".svg" && ext != ".png") {
    return Status::error("--plot " + path.string() +
                         ": expected a file name ending in .svg or .png");
  }
  spectral::PlotSettings settings;
  settings.joints = joint_names;
  Result<std::string> svg = spectral::plotSvg(skeleton, clip, spectrum, settings);
  if (!svg.ok()) return Status::error("--plot: " + svg.message());
  if (ext == ".svg") return writeFileAtomically(path, svg.value());
  return writePng(path, svg.value());
}

}  // namespace sinew::app
