#include "state_json.h"

#include <cmath>
#include <limits>

namespace sinew::search::state_json {
namespace {

std::string numbers(size_t size) {
  return size == kAnySize ? "an array of finite numbers"
                          : "an array of " + std::to_string(size) + " finite numbers";
}

bool finiteNumber(const json& value) {
  return value.is_number() && std::isfinite(value.get<double>());
}

}  // namespace

json cost(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0.0 ? "inf" : "-inf";
  return value;
}

json rows(const std::vector<double>& values, size_t cols) {
  json out = json::array();
  for (size_t start = 0; start + cols <= values.size() && cols > 0; start += cols) {
    out.push_back(std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(start),
                                      values.begin() + static_cast<std::ptrdiff_t>(start + cols)));
  }
  return out;
}

Result<const json*> field(const json& object, const char* key, const std::string& where) {
  if (!object.is_object()) return Status::error(where + ": expected a JSON object");
  const auto it = object.find(key);
  if (it == object.end()) return Status::error(where + ": " + key + ": missing");
  return &*it;
}

Status readCost(const json& object, const char* key, const std::string& where, double& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  const json& v = *value.value();
  if (finiteNumber(v)) {
    out = v.get<double>();
    return {};
  }
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    if (s == "nan") out = std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") out = std::numeric_limits<double>::infinity();
    if (s == "-inf") out = -std::numeric_limits<double>::infinity();
    if (s == "nan" || s == "inf" || s == "-inf") return {};
  }
  return Status::error(where + ": " + key + ": expected a number, \"nan\", \"inf\" or \"-inf\"");
}

Status readCosts(const json& object, const char* key, const std::string& where, size_t max_size,
                 std::vector<double>& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  const json& v = *value.value();
  const std::string expected = "expected an array of at most " + std::to_string(max_size) +
                               " costs (numbers, \"nan\", \"inf\", \"-inf\")";
  if (!v.is_array() || v.size() > max_size)
    return Status::error(where + ": " + key + ": " + expected);
  out.clear();
  for (size_t i = 0; i < v.size(); ++i) {
    double c = 0.0;
    const json holder = {{"value", v[i]}};
    if (!readCost(holder, "value", where, c).ok())
      return Status::error(where + ": " + key + "[" + std::to_string(i) + "]: " + expected);
    out.push_back(c);
  }
  return {};
}

Status readNumber(const json& object, const char* key, const std::string& where, double& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  if (!finiteNumber(*value.value()))
    return Status::error(where + ": " + key + ": expected a finite number");
  out = value.value()->get<double>();
  return {};
}

Status readInt(const json& object, const char* key, const std::string& where, long long min,
               long long max, long long& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  const json& v = *value.value();
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + std::to_string(...).
  std::string range = "[";
  range += std::to_string(min);
  range += ", ";
  range += std::to_string(max);
  range += "]";
  if (!v.is_number_integer())
    return Status::error(where + ": " + key + ": expected an integer in " + range);
  if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(max))
    return Status::error(where + ": " + key + ": expected an integer in " + range);
  const long long value_ll = v.get<long long>();
  if (value_ll < min || value_ll > max)
    return Status::error(where + ": " + key + ": expected an integer in " + range);
  out = value_ll;
  return {};
}

Status readInt(const json& object, const char* key, const std::string& where, int min, int max,
               int& out) {
  long long wide = 0;
  if (Status s = readInt(object, key, where, static_cast<long long>(min),
                         static_cast<long long>(max), wide);
      !s.ok())
    return s;
  out = static_cast<int>(wide);
  return {};
}

Status readUint64(const json& object, const char* key, const std::string& where,
                  std::uint64_t& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  const json& v = *value.value();
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<long long>() >= 0))
    return Status::error(where + ": " + key + ": expected an unsigned 64-bit integer");
  out = v.get<std::uint64_t>();
  return {};
}

Status readBool(const json& object, const char* key, const std::string& where, bool& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  if (!value.value()->is_boolean())
    return Status::error(where + ": " + key + ": expected true or false");
  out = value.value()->get<bool>();
  return {};
}

Status readString(const json& object, const char* key, const std::string& where, std::string& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  if (!value.value()->is_string()) return Status::error(where + ": " + key + ": expected a string");
  out = value.value()->get<std::string>();
  return {};
}

Status readVector(const json& object, const char* key, const std::string& where, size_t size,
                  std::vector<double>& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  const json& v = *value.value();
  if (!v.is_array() || (size != kAnySize && v.size() != size))
    return Status::error(where + ": " + key + ": expected " + numbers(size) +
                         (v.is_array() ? ", found " + std::to_string(v.size()) : ""));
  out.clear();
  out.reserve(v.size());
  for (const json& x : v) {
    if (!finiteNumber(x)) return Status::error(where + ": " + key + ": expected " + numbers(size));
    out.push_back(x.get<double>());
  }
  return {};
}

Status readRows(const json& object, const char* key, const std::string& where, size_t rows_count,
                size_t cols, std::vector<double>& out) {
  Result<const json*> value = field(object, key, where);
  if (!value.ok()) return value.status();
  const json& v = *value.value();
  const std::string expected = "expected " + std::to_string(rows_count) + " arrays of " +
                               std::to_string(cols) + " finite numbers";
  if (!v.is_array() || v.size() != rows_count)
    return Status::error(where + ": " + key + ": " + expected +
                         (v.is_array() ? ", found " + std::to_string(v.size()) + " arrays" : ""));
  out.clear();
  out.reserve(rows_count * cols);
  for (size_t r = 0; r < rows_count; ++r) {
    const json& row = v[r];
    if (!row.is_array() || row.size() != cols)
      return Status::error(where + ": " + key + "[" + std::to_string(r) + "]: " + expected +
                           (row.is_array() ? ", found " + std::to_string(row.size()) : ""));
    for (const json& x : row) {
      if (!finiteNumber(x))
        return Status::error(where + ": " + key + "[" + std::to_string(r) + "]: " + expected);
      out.push_back(x.get<double>());
    }
  }
  return {};
}

}  // namespace sinew::search::state_json
