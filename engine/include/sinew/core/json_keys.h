// Keys a reader of Sinew's JSON files (coefficients, controllers) does not know: each is a
// warning naming the file and the field, not an error, so a newer file still reads.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace sinew {

// For every key of `object` (when it is an object) not in `known`, appends
// "<where>: unknown key '<prefix><key>' (ignored)" to `warnings` (nothing when warnings is null).
// `prefix` names a nested object by its path ("search.").
void unknownKeys(const nlohmann::json& object, const std::vector<const char*>& known,
                 const std::string& where, std::vector<std::string>* warnings,
                 const std::string& prefix = "");

}  // namespace sinew
