#include "sinew/core/json_keys.h"

#include <nlohmann/json.hpp>

namespace sinew {

void unknownKeys(const nlohmann::json& object, const std::vector<const char*>& known,
                 const std::string& where, std::vector<std::string>* warnings,
                 const std::string& prefix) {
  if (warnings == nullptr || !object.is_object()) return;
  for (const auto& item : object.items()) {
    bool found = false;
    for (const char* k : known) found = found || item.key() == k;
    if (!found)
      warnings->push_back(where + ": unknown key '" + prefix + item.key() + "' (ignored)");
  }
}

}  // namespace sinew
