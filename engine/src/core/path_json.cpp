#include "sinew/core/path_json.h"

#include <optional>

#include <nlohmann/json.hpp>

#include "sinew/core/text.h"

namespace sinew {

void writePathJson(nlohmann::json& object, const std::string& key, const std::string& path) {
  object[key] = toUtf8(path);
  if (!isValidUtf8(path)) object[key + "_encoding"] = "latin1";
}

Status readPathJson(const nlohmann::json& object, const std::string& key, std::string& out,
                    const std::string& where) {
  if (!object.contains(key)) return Status();
  const nlohmann::json& value = object.at(key);
  if (!value.is_string())
    return Status::error(where + key + ": expected a string, got " +
                         value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  out = value.get<std::string>();
  const std::string encoding = key + "_encoding";
  if (!object.contains(encoding)) return Status();
  if (object.at(encoding) != "latin1")
    return Status::error(
        where + encoding + ": expected \"latin1\", got " +
        object.at(encoding).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  std::optional<std::string> bytes = latin1FromUtf8(out);
  if (!bytes)
    return Status::error(where + key + ": not Latin-1 text, which " + encoding + " says it is");
  out = std::move(*bytes);
  return Status();
}

}  // namespace sinew
