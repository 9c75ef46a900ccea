#include "tools/scene/json_reader.h"

#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <sstream>

namespace jetshell::json {
namespace {

std::string typeName(const nlohmann::json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_boolean()) return "a boolean";
  if (j.is_null()) return "null";
  if (j.is_array()) return "an array";
  return "an object";
}

/// Tracks the pointer of the value being parsed, to name a repeated key.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(std::string name) : name_(std::move(name)) {}
  bool operator()(int, nlohmann::json::parse_event_t event, nlohmann::json&) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        enterChild();
        frames_.push_back({event == E::object_start, {}, "", -1});
        break;
      case E::object_end:
      case E::array_end:
        frames_.pop_back();
        break;
      case E::key: {
        Frame& top = frames_.back();
        // The key event carries the key in the parsed value, which the library hands over as a json string.
        top.key = pendingKey_;
        if (!top.keys.insert(top.key).second)
          throw InputError(name_ + ": " + pointer() + ": repeated key (each key may appear once per object)");
        break;
      }
      case E::value:
        enterChild();
        break;
    }
    return true;
  }
  void setKey(const std::string& k) { pendingKey_ = k; }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;
    int index;
  };
  void enterChild() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }
  std::string pointer() const {
    std::string p;
    for (const Frame& f : frames_) p += "/" + (f.object ? escapeKey(f.key) : std::to_string(f.index));
    return p;
  }
  std::string name_;
  std::vector<Frame> frames_;
  std::string pendingKey_;
};

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string escapeKey(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

nlohmann::json parse(const std::string& text, const std::string& name) {
  DuplicateKeyCheck duplicates(name);
  // The callback sees a key event with the key as its parsed value.
  const int maxDepth = inputLimits().maxJsonDepth;
  auto callback = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if ((event == E::object_start || event == E::array_start) && depth >= maxDepth)
      throw InputError(name + ": nested too deeply (at most " + std::to_string(maxDepth) + " levels of arrays and objects)");
    if (event == E::key) {
      const std::string& key = parsed.get_ref<const std::string&>();
      if (static_cast<std::int64_t>(key.size()) > inputLimits().maxStringBytes)
        throw InputError(name + ": a key of " + std::to_string(key.size()) + " bytes is too long (at most " +
                         std::to_string(inputLimits().maxStringBytes) + ")");
      duplicates.setKey(key);
    }
    return duplicates(depth, event, parsed);
  };
  try {
    return nlohmann::json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    // Turn the byte offset into line:column; the library's own text follows "parse error at ...: ".
    std::size_t line = 1, column = 1;
    for (std::size_t k = 0; k + 1 < e.byte && k < text.size(); ++k) {
      if (text[k] == '\n') ++line, column = 1;
      else ++column;
    }
    std::string what = e.what();
    const std::size_t colon = what.find(": ", what.find("parse error"));
    if (colon != std::string::npos) what = what.substr(colon + 2);
    std::ostringstream s;
    s << name << ":" << line << ":" << column << ": invalid JSON: " << what;
    throw InputError(s.str());
  } catch (const nlohmann::json::out_of_range& e) {
    // A number too large for a double ("number overflow parsing '1e999'"): locate the quoted token.
    std::string what = e.what();
    what = what.substr(what.find(']') + 2);
    const std::size_t open = what.find('\''), close = what.rfind('\'');
    std::size_t line = 1, column = 1;
    if (open != std::string::npos && close > open) {
      const std::size_t at = text.find(what.substr(open + 1, close - open - 1));
      for (std::size_t k = 0; k < at && k < text.size(); ++k) {
        if (text[k] == '\n') ++line, column = 1;
        else ++column;
      }
    }
    std::ostringstream s;
    s << name << ":" << line << ":" << column << ": invalid JSON: " << what;
    throw InputError(s.str());
  }
}

nlohmann::json parseFile(const std::string& path, const std::string& what) {
  return parse(readInputFile(path, inputLimits().maxJsonBytes, what), path);
}

std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t bestDistance = std::numeric_limits<std::size_t>::max();
  for (const std::string& c : candidates) {
    const std::size_t d = editDistance(word, c);
    if (d < bestDistance) best = c, bestDistance = d;
  }
  return bestDistance <= std::max<std::size_t>(2, word.size() / 3) ? best : "";
}

void Value::typeError(const std::string& what) const {
  error("expected " + what + ", got " + typeName(*j_));
}

void Value::error(const std::string& message) const {
  throw InputError((pointer_.empty() ? "(root)" : pointer_) + ": " + message);
}

double Value::number() const {
  if (!j_->is_number()) typeError("a number");
  return j_->get<double>();
}

int Value::integer() const { return integer(std::numeric_limits<int>::min(), std::numeric_limits<int>::max()); }

int Value::integer(int minimum, int maximum) const {
  if (!j_->is_number()) typeError("an integer");
  const double d = j_->get<double>();
  if (!(std::isfinite(d) && std::floor(d) == d)) error("expected an integer, got " + j_->dump());
  if (d > maximum) throw InputError(pointer_ + " = " + j_->dump() + ": too large (at most " + std::to_string(maximum) + ")");
  if (d < minimum) throw InputError(pointer_ + " = " + j_->dump() + ": must be >= " + std::to_string(minimum));
  return static_cast<int>(d);
}

bool Value::boolean() const {
  if (!j_->is_boolean()) typeError("true or false");
  return j_->get<bool>();
}

std::string Value::string() const {
  if (!j_->is_string()) typeError("a string");
  const std::string& text = j_->get_ref<const std::string&>();
  const std::int64_t limit = inputLimits().maxStringBytes;
  if (static_cast<std::int64_t>(text.size()) > limit)
    error("a string of " + std::to_string(text.size()) + " bytes is too long (at most " + std::to_string(limit) + ")");
  return text;
}

Eigen::Vector3d Value::vec3() const {
  if (!j_->is_array() || j_->size() != 3) typeError("an array of 3 numbers [x, y, z]");
  Eigen::Vector3d v;
  for (int c = 0; c < 3; ++c) {
    const Value e((*j_)[static_cast<std::size_t>(c)], pointer_ + "/" + std::to_string(c));
    v[c] = e.number();
    if (!std::isfinite(v[c])) {
      std::ostringstream m;
      m << e.pointer() << " = " << v[c] << ": must be finite";
      throw InputError(m.str());
    }
  }
  return v;
}

std::vector<Value> Value::array() const {
  if (!j_->is_array()) typeError("an array");
  std::vector<Value> out;
  for (std::size_t k = 0; k < j_->size(); ++k) out.emplace_back((*j_)[k], pointer_ + "/" + std::to_string(k));
  return out;
}

Object Value::object(const std::vector<std::string>& allowed, const std::string& what) const {
  if (!j_->is_object()) typeError("an object (" + what + ")");
  for (const auto& item : j_->items()) {
    if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
    const std::string hint = closest(item.key(), allowed);
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw InputError(pointer_ + "/" + escapeKey(item.key()) + ": unknown key in " + what +
                     (hint.empty() ? " (allowed: " + list + ")" : " (did you mean \"" + hint + "\"?)"));
  }
  return Object(*this);
}

Value Object::at(const std::string& key) const {
  if (!has(key)) throw InputError(member(key) + ": missing (required)");
  return Value(v_.raw()[key], member(key));
}

std::optional<Value> Object::find(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return Value(v_.raw()[key], member(key));
}

double Object::number(const std::string& key, double fallback) const {
  const auto v = find(key);
  return v ? v->number() : fallback;
}

int Object::integer(const std::string& key, int fallback) const {
  const auto v = find(key);
  return v ? v->integer() : fallback;
}

int Object::integer(const std::string& key, int fallback, int minimum, int maximum) const {
  const auto v = find(key);
  return v ? v->integer(minimum, maximum) : fallback;
}

bool Object::boolean(const std::string& key, bool fallback) const {
  const auto v = find(key);
  return v ? v->boolean() : fallback;
}

std::string Object::string(const std::string& key, const std::string& fallback) const {
  const auto v = find(key);
  return v ? v->string() : fallback;
}

Eigen::Vector3d Object::vec3(const std::string& key, const Eigen::Vector3d& fallback) const {
  const auto v = find(key);
  return v ? v->vec3() : fallback;
}

std::string Object::choice(const std::string& key, const std::vector<std::string>& options,
                           const std::string& fallback) const {
  const auto v = find(key);
  if (!v) return fallback;
  const std::string s = v->string();
  if (std::find(options.begin(), options.end(), s) != options.end()) return s;
  std::string list;
  for (const std::string& o : options) list += (list.empty() ? "\"" : ", \"") + o + "\"";
  const std::string hint = closest(s, options);
  v->error("\"" + s + "\" is not one of " + list + (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
}

}  // namespace jetshell::json
