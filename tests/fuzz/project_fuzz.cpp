// libFuzzer target for project files (.sinew.json, app/project): any input must give a project or
// a message naming the file, never a crash, a hang, an escaped exception, a sanitizer report or an
// allocation sized by a number in the file. A project that is read must be valid, write back
// without null (JSON's stand-in for nan and inf), and read back to the same project.
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "project/project.h"

namespace {

constexpr const char* kName = "fuzz.sinew.json";

bool holdsNull(const nlohmann::json& value) {
  if (value.is_null()) return true;
  if (value.is_structured()) {
    for (const nlohmann::json& item : value) {
      if (holdsNull(item)) return true;
    }
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sinew;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::filesystem::path base = "/fuzz/project";
  std::vector<std::string> warnings;
  Result<app::Project> project = app::parseProject(text, base, kName, &warnings);
  if (!project.ok()) {
    if (project.message().rfind(kName, 0) != 0) __builtin_trap();  // the file is named first
    return 0;
  }
  if (!app::validateProject(project.value()).ok()) __builtin_trap();
  const std::string written = app::projectJson(project.value(), base);
  const nlohmann::json document = nlohmann::json::parse(written, nullptr, false);
  if (document.is_discarded() || holdsNull(document)) __builtin_trap();
  Result<app::Project> again = app::parseProject(written, base, kName);
  if (!again.ok() || !(again.value() == project.value())) __builtin_trap();
  return 0;
}
