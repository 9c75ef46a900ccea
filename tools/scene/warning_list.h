// The scene reader's warnings of one kind (contact coverage, shells inside solids, sliver faces): a scene may hold
// 100,000 actors or pairs, so the first kMostWarnings are listed and the rest counted in one closing line. A
// warning's text is made only when it is listed.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace jetshell {

class WarningList {
 public:
  static constexpr std::size_t kMostWarnings = 20;

  /// Lists make()'s text while fewer than kMostWarnings are listed; counts the warning otherwise.
  template <typename Make>
  void add(Make make) {
    if (warnings_.size() < kMostWarnings) warnings_.push_back(make());
    else ++unlisted_;
  }

  /// The listed warnings, and "and N more <rest>" when some were not listed.
  std::vector<std::string> finish(const std::string& rest) && {
    if (unlisted_ > 0) warnings_.push_back("and " + std::to_string(unlisted_) + " more " + rest);
    return std::move(warnings_);
  }

 private:
  std::vector<std::string> warnings_;
  std::size_t unlisted_ = 0;
};

}  // namespace jetshell
