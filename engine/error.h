// Error values for the boundaries of the library (file loading, scene validation, options).
// Library code never exits the process: it returns an Error naming where and what; the CLI prints
// Error::line() and exits with status 2.
// Thread-safety: plain values.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace penumbra::engine {

struct Error {
  std::string where;  // a file path, "option --width", "scene 'x'", ...
  std::string what;   // the problem, one line, no trailing period
  // One line: control characters (which file contents may carry into a message) become spaces.
  std::string line() const {
    std::string s = where.empty() ? what : where + ": " + what;
    for (char& c : s)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    return s;
  }
};

// Either a value or an Error.
template <class T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design
  Result(Error error) : v_(std::move(error)) {}  // NOLINT
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() { return std::get<0>(v_); }
  const T& value() const { return std::get<0>(v_); }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const Error& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

// For operations that return nothing on success.
struct Ok {};
using Status = Result<Ok>;

}  // namespace penumbra::engine
