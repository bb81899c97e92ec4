// Paths in the JSON files Sinew writes (projects, checkpoints, controllers). Paths are bytes, JSON
// text is UTF-8: a path that is not UTF-8 (a Latin-1 folder name, "Hüfte" with ü as 0xFC) is
// written as its Latin-1 reading with "<key>_encoding": "latin1" beside it, and read back as the
// same bytes, so a resumed search or a replayed controller finds its files.
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"

namespace sinew {

// object[key] = the path as UTF-8 text, plus object[key + "_encoding"] = "latin1" when `path`
// is not UTF-8.
void writePathJson(nlohmann::json& object, const std::string& key, const std::string& path);

// The bytes writePathJson stored under `key`; `out` is left as it is when the key is missing.
// Errors read "<where><key>: expected a string, got ..." (so `where` ends in ": " or is empty).
Status readPathJson(const nlohmann::json& object, const std::string& key, std::string& out,
                    const std::string& where);

}  // namespace sinew
