// Reading and writing the optimisers' saved state (internal to the search module). Every reader
// names the field it could not read: "<where>: <key>: expected ...".
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sinew/core/status.h"

namespace sinew::search::state_json {

using nlohmann::json;

// A cost: finite as a number, otherwise "nan", "inf" or "-inf" (JSON has no such numbers).
json cost(double value);
// Rows of equal length: (rows x cols) values, row after row.
json rows(const std::vector<double>& values, size_t cols);

// The field `key` of `object`, or a message naming it.
Result<const json*> field(const json& object, const char* key, const std::string& where);

Status readCost(const json& object, const char* key, const std::string& where, double& out);
// A finite number.
Status readNumber(const json& object, const char* key, const std::string& where, double& out);
Status readInt(const json& object, const char* key, const std::string& where, long long min,
               long long max, long long& out);
Status readInt(const json& object, const char* key, const std::string& where, int min, int max,
               int& out);
Status readUint64(const json& object, const char* key, const std::string& where,
                  std::uint64_t& out);
Status readBool(const json& object, const char* key, const std::string& where, bool& out);
Status readString(const json& object, const char* key, const std::string& where, std::string& out);
// An array of `size` finite numbers (any size when size == kAnySize).
inline constexpr size_t kAnySize = static_cast<size_t>(-1);
Status readVector(const json& object, const char* key, const std::string& where, size_t size,
                  std::vector<double>& out);
// An array of at most `max_size` costs (numbers, "nan", "inf", "-inf").
Status readCosts(const json& object, const char* key, const std::string& where, size_t max_size,
                 std::vector<double>& out);
// An array of `rows` arrays of `cols` finite numbers, into one vector row after row.
Status readRows(const json& object, const char* key, const std::string& where, size_t rows,
                size_t cols, std::vector<double>& out);

}  // namespace sinew::search::state_json
