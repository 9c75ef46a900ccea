// Strict reading of JSON scene files: every value is read through its JSON pointer, so each error names the
// field ("/actors/0/material/poissonRatio: expected a number, got a string"), and objects reject unknown keys
// (with a "did you mean" hint). Files are parsed with comments allowed and duplicate keys rejected. Sizes are
// bounded (core/input_limits.h): the file, the nesting depth, every string, every integer (each field states its
// own range).
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace jetshell::json {

/// Parses JSON text; `name` names the source in errors ("scene.json:3:14: invalid JSON: ..."). // and /* */
/// comments are allowed; a repeated key in one object is an error naming its pointer.
nlohmann::json parse(const std::string& text, const std::string& name);

/// Reads and parses a JSON file (a regular file of at most inputLimits().maxJsonBytes; `what` names it in
/// errors: "scene file").
nlohmann::json parseFile(const std::string& path, const std::string& what);

/// Escapes a key for a JSON pointer (RFC 6901: ~ → ~0, / → ~1).
std::string escapeKey(const std::string& key);

class Object;

/// One JSON value and its pointer.
class Value {
 public:
  Value(const nlohmann::json& j, std::string pointer) : j_(&j), pointer_(std::move(pointer)) {}
  const nlohmann::json& raw() const { return *j_; }
  const std::string& pointer() const { return pointer_; }

  double number() const;         // any finite or infinite number; use the check:: helpers for ranges
  int integer() const;           // a number with an integral value that fits an int
  /// An integer in [minimum, maximum]: "<pointer> = 20000000: too large (at most 10000000)".
  int integer(int minimum, int maximum) const;
  bool boolean() const;
  std::string string() const;    // at most inputLimits().maxStringBytes
  Eigen::Vector3d vec3() const;  // [x, y, z], finite
  std::vector<Value> array() const;
  /// This value as an object whose keys must all be in `allowed`; `what` names it in the hint
  /// ("a shell actor").
  Object object(const std::vector<std::string>& allowed, const std::string& what) const;

  bool isObject() const { return j_->is_object(); }
  bool isArray() const { return j_->is_array(); }

  /// "<pointer>: expected <what>, got <type>".
  [[noreturn]] void typeError(const std::string& what) const;
  /// "<pointer>: <message>".
  [[noreturn]] void error(const std::string& message) const;

 private:
  const nlohmann::json* j_;
  std::string pointer_;
};

/// A JSON object whose keys were checked against an allowed list.
class Object {
 public:
  Object(const Value& v) : v_(v) {}
  const std::string& pointer() const { return v_.pointer(); }
  bool has(const std::string& key) const { return v_.raw().contains(key); }
  /// A required member: "<pointer>/<key>: missing (required)".
  Value at(const std::string& key) const;
  std::optional<Value> find(const std::string& key) const;

  double number(const std::string& key, double fallback) const;
  int integer(const std::string& key, int fallback) const;
  int integer(const std::string& key, int fallback, int minimum, int maximum) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  Eigen::Vector3d vec3(const std::string& key, const Eigen::Vector3d& fallback) const;
  /// A string member that must be one of `options`.
  std::string choice(const std::string& key, const std::vector<std::string>& options, const std::string& fallback) const;
  std::string member(const std::string& key) const { return pointer() + "/" + escapeKey(key); }

 private:
  Value v_;
};

/// The closest of `candidates` to `word` by edit distance, or "" when none is close.
std::string closest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace jetshell::json
