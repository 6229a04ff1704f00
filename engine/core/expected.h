#pragma once
// Results with context at API boundaries: a function that can fail on bad input returns
// Expected<T>; the error names what failed and why, and callers add context as it travels up
// ("loading scene.glb: accessor 3: buffer view out of range").
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace engine {

struct Error {
  std::string message;

  // Prefixes this error with where it happened, e.g. withContext("bunny.glb").
  Error withContext(const std::string& context) const { return Error{context + ": " + message}; }
};

// A value asked of an Expected that holds an error, or an error of one that holds a value: a bug
// in the caller, which should have tested ok(). The message carries the error that was not
// handled (std::bad_variant_access would drop it).
class BadExpectedAccess : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

template <class T>
class [[nodiscard]] Expected {
 public:
  Expected(T value) : data_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Expected(Error error) : data_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  T& value() & {
    checkValue();
    return std::get<T>(data_);
  }
  const T& value() const& {
    checkValue();
    return std::get<T>(data_);
  }
  T&& value() && {
    checkValue();
    return std::get<T>(std::move(data_));
  }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const {
    if (ok()) throw BadExpectedAccess("Expected::error() on a result that holds a value");
    return std::get<Error>(data_);
  }

  // Returns this result with `context` prefixed to its error, if any.
  Expected withContext(const std::string& context) && {
    if (ok()) return std::move(*this);
    return error().withContext(context);
  }

 private:
  void checkValue() const {
    if (!ok())
      throw BadExpectedAccess("Expected::value() on an error: " + std::get<Error>(data_).message);
  }

  std::variant<T, Error> data_;
};

// Expected<void>: success or an error.
template <>
class [[nodiscard]] Expected<void> {
 public:
  Expected() = default;
  Expected(Error error) : error_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return !error_.has_value(); }
  explicit operator bool() const { return ok(); }
  const Error& error() const {
    if (ok()) throw BadExpectedAccess("Expected::error() on a result that holds a value");
    return *error_;
  }
  Expected withContext(const std::string& context) && {
    if (ok()) return {};
    return error_->withContext(context);
  }

 private:
  std::optional<Error> error_;
};

using Status = Expected<void>;

inline Error makeError(std::string message) { return Error{std::move(message)}; }

}  // namespace engine

// Propagates an error from an Expected-returning expression; on success binds the value.
#define ENGINE_TRY_ASSIGN(lhs, expr)                    \
  auto ENGINE_CONCAT_(try_, __LINE__) = (expr);         \
  if (!ENGINE_CONCAT_(try_, __LINE__).ok())             \
    return ENGINE_CONCAT_(try_, __LINE__).error();      \
  lhs = std::move(ENGINE_CONCAT_(try_, __LINE__).value())

#define ENGINE_TRY(expr)                                   \
  do {                                                     \
    if (auto engine_try_status_ = (expr); !engine_try_status_.ok()) \
      return engine_try_status_.error();                   \
  } while (0)

#define ENGINE_CONCAT_INNER_(a, b) a##b
#define ENGINE_CONCAT_(a, b) ENGINE_CONCAT_INNER_(a, b)
