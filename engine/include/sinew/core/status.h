// Errors as values. Anything that crosses a module or thread boundary and can fail returns a
// Status or a Result<T> whose message a user can read ("walk.bvh:140: expected 132 numbers,
// found 131"). Exceptions, where a module uses them internally, never escape it.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace sinew {

class [[nodiscard]] Status {
 public:
  Status() = default;  // success
  static Status error(std::string message) { return Status(std::move(message), true); }

  bool ok() const { return !failed_; }
  const std::string& message() const { return message_; }

 private:
  Status(std::string message, bool failed) : message_(std::move(message)), failed_(failed) {}
  std::string message_;
  bool failed_ = false;
};

// A value or the message saying why there is none.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}  // NOLINT: implicit on purpose
  Result(Status error) : state_(std::move(error)) {}  // NOLINT: must be a failed Status

  bool ok() const { return std::holds_alternative<T>(state_); }
  // Precondition: ok().
  T& value() & { return std::get<T>(state_); }
  const T& value() const& { return std::get<T>(state_); }
  T&& value() && { return std::get<T>(std::move(state_)); }
  // Empty when ok().
  const std::string& message() const {
    static const std::string kEmpty;
    return ok() ? kEmpty : std::get<Status>(state_).message();
  }
  Status status() const { return ok() ? Status() : std::get<Status>(state_); }

 private:
  std::variant<T, Status> state_;
};

}  // namespace sinew
