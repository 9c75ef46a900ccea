#include "tools/scene/selector.h"

#include "tools/scene/checks.h"
#include "tools/scene/shapes.h"

#include <algorithm>
#include <limits>

namespace jetshell {

void validate(const VertexSelector& s, const std::string& where) {
  if (s.empty()) throw InputError(where + ": selects nothing (give at least one criterion, or \"all\": true)");
  if (s.box) {
    check::finite(s.box->min, where + "/box/min");
    check::finite(s.box->max, where + "/box/max");
    for (int c = 0; c < 3; ++c)
      if (s.box->min[c] > s.box->max[c])
        check::fail(where + "/box/min[" + std::to_string(c) + "]", s.box->min[c], "must be <= max");
  }
  if (s.plane) {
    check::finite(s.plane->point, where + "/plane/point");
    check::nonZero(s.plane->normal, where + "/plane/normal");
    check::nonNegative(s.plane->distance, where + "/plane/distance");
  }
  if (s.nearest) check::finite(*s.nearest, where + "/nearest");
}

namespace {

std::vector<int> selectOne(const VertexSelector& s, const SelectionContext& ctx, const std::string& where) {
  validate(s, where);
  const Positions& X = *ctx.worldPositions;
  const int n = static_cast<int>(X.rows());
  std::vector<char> pass(static_cast<std::size_t>(n), 1);
  if (s.indices) {
    std::vector<char> listed(static_cast<std::size_t>(n), 0);
    for (std::size_t k = 0; k < s.indices->size(); ++k) {
      const int v = (*s.indices)[k];
      if (v < 0 || v >= n) {
        throw InputError(where + "/indices/" + std::to_string(k) + " = " + std::to_string(v) + ": out of range [0, " +
                         std::to_string(n) + ")");
      }
      listed[static_cast<std::size_t>(v)] = 1;
    }
    for (int v = 0; v < n; ++v) pass[v] = pass[v] && listed[v];
  }
  if (s.group) {
    const auto it = ctx.shape->vertexGroups.find(*s.group);
    if (it == ctx.shape->vertexGroups.end()) {
      std::string known;
      for (const auto& g : ctx.shape->vertexGroups) known += (known.empty() ? "" : ", ") + g.first;
      throw InputError(where + "/group = \"" + *s.group + "\": unknown group of " + ctx.shape->source +
                       (known.empty() ? " (it has none)" : " (known: " + known + ")"));
    }
    std::vector<char> member(static_cast<std::size_t>(n), 0);
    for (int v : it->second) member[static_cast<std::size_t>(v)] = 1;
    for (int v = 0; v < n; ++v) pass[v] = pass[v] && member[v];
  }
  if (s.box) {
    for (int v = 0; v < n; ++v) {
      const Eigen::Vector3d x = X.row(v);
      pass[v] = pass[v] && (x.array() >= s.box->min.array()).all() && (x.array() <= s.box->max.array()).all();
    }
  }
  if (s.plane) {
    const Eigen::Vector3d nhat = check::unitDirection(s.plane->normal, where + "/plane/normal");
    for (int v = 0; v < n; ++v) {
      const Eigen::Vector3d x = X.row(v);
      pass[v] = pass[v] && std::abs((x - s.plane->point).dot(nhat)) <= s.plane->distance;
    }
  }
  if (s.boundaryOnly)
    for (int v = 0; v < n; ++v) pass[v] = pass[v] && (*ctx.boundaryVertex)[static_cast<std::size_t>(v)];
  std::vector<int> out;
  if (s.nearest) {
    int best = -1;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (int v = 0; v < n; ++v) {
      if (!pass[v]) continue;
      const double d = (Eigen::Vector3d(X.row(v)) - *s.nearest).squaredNorm();
      if (d < bestDistance) best = v, bestDistance = d;  // ties keep the lowest index
    }
    if (best >= 0) out.push_back(best);
    return out;
  }
  for (int v = 0; v < n; ++v)
    if (pass[v]) out.push_back(v);
  return out;
}

}  // namespace

std::vector<int> selectVertices(const VertexSelection& selection, const SelectionContext& context,
                                const std::string& where) {
  if (selection.empty()) throw InputError(where + ": selects nothing (an empty list)");
  std::vector<int> out;
  for (std::size_t k = 0; k < selection.size(); ++k) {
    const std::string w = selection.size() == 1 ? where : where + "/" + std::to_string(k);
    const std::vector<int> part = selectOne(selection[k], context, w);
    out.insert(out.end(), part.begin(), part.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (out.empty()) throw InputError(where + ": no vertex matches the selection");
  return out;
}

}  // namespace jetshell
