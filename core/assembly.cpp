#include "core/assembly.h"

#include "core/mesh.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace jetshell {

namespace {

/// Greedy colouring of sets of vertices (elements, or blocks of elements): sets of one colour are disjoint.
/// vertices(i, out) lists set i's vertex ids (may include -1, ignored).
template <typename VertexLister>
std::vector<std::vector<int>> colorVertexSets(int numSets, int numVertices, VertexLister&& vertices) {
  // usedColors[v] is a bit set (64 colours per word) of colours already taken by sets touching v.
  std::vector<std::vector<std::uint64_t>> usedColors(static_cast<std::size_t>(numVertices));
  std::vector<std::vector<int>> colors;
  std::vector<std::uint64_t> taken;
  std::vector<int> ids;
  for (int e = 0; e < numSets; ++e) {
    ids.clear();
    vertices(e, ids);
    taken.clear();
    for (int v : ids) {
      if (v < 0) continue;
      const auto& u = usedColors[v];
      if (taken.size() < u.size()) taken.resize(u.size(), 0);
      for (std::size_t w = 0; w < u.size(); ++w) taken[w] |= u[w];
    }
    int color = 0;
    for (std::size_t w = 0;; ++w) {
      const std::uint64_t word = w < taken.size() ? taken[w] : 0;
      if (word != ~std::uint64_t{0}) {
        color = static_cast<int>(w) * 64 + __builtin_ctzll(~word);
        break;
      }
    }
    if (color >= static_cast<int>(colors.size())) colors.resize(color + 1);
    colors[color].push_back(e);
    for (int v : ids) {
      if (v < 0) continue;
      auto& u = usedColors[v];
      const std::size_t w = static_cast<std::size_t>(color) / 64;
      if (u.size() <= w) u.resize(w + 1, 0);
      u[w] |= std::uint64_t{1} << (color % 64);
    }
  }
  return colors;
}

}  // namespace

std::vector<std::vector<int>> colorElements(const StencilTable& table, int numVertices) {
  return colorVertexSets(table.size(), numVertices, [&](int e, std::vector<int>& out) {
    out.assign(table.element(e), table.element(e) + table.width);
  });
}

ElementSchedule scheduleElements(const StencilTable& table, int numVertices, int blockSize) {
  const int ne = table.size();
  if (blockSize <= 0) blockSize = std::clamp(ne / 64, 32, 2048);
  const int numBlocks = (ne + blockSize - 1) / blockSize;
  const auto blockColors = colorVertexSets(numBlocks, numVertices, [&](int b, std::vector<int>& out) {
    const int begin = b * blockSize, end = std::min(ne, begin + blockSize);
    out.assign(table.element(begin), table.element(begin) + static_cast<std::size_t>(end - begin) * table.width);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  });
  ElementSchedule s;
  for (const auto& blocks : blockColors) {
    s.colors.emplace_back();
    for (int b : blocks) s.colors.back().push_back({b * blockSize, std::min(ne, (b + 1) * blockSize)});
  }
  return s;
}

int HessianAssembler::addStencils(const StencilTable& table) {
  if (finalized_) throw std::logic_error("HessianAssembler::addStencils after finalize");
  slots_.push_back(Slot{table, {}, {}, {}, true});
  return static_cast<int>(slots_.size()) - 1;
}

void HessianAssembler::replaceStencils(int slot, const StencilTable& table) {
  if (slot < 0 || slot >= numSlots()) throw std::out_of_range("HessianAssembler::replaceStencils: no such slot");
  if (table.width != slots_[slot].table.width)
    throw std::invalid_argument("HessianAssembler::replaceStencils: the stencil width changed");
  slots_[slot].table = table;
  slots_[slot].stale = true;
  slots_[slot].moving = true;
  finalized_ = false;
}

void HessianAssembler::clearStencils() {
  slots_.clear();
  baseSlots_.clear();
  keptRows_.clear();
  finalized_ = false;
}

void HessianAssembler::setGrowOnly(bool growOnly, double pruneFraction) {
  if (!(pruneFraction >= 0.0)) throw std::invalid_argument("pruneFraction must be >= 0");
  growOnly_ = growOnly;
  pruneFraction_ = pruneFraction;
}

void HessianAssembler::finalize(int numVertices, const std::vector<char>& fixedDof) {
  const int n = numVertices;
  const int ndof = 3 * n;
  std::vector<char> fixed = fixedDof.empty() ? std::vector<char>(static_cast<std::size_t>(ndof), 0) : fixedDof;
  if (static_cast<int>(fixed.size()) != ndof) throw std::invalid_argument("fixedDof has the wrong size");

  // Vertex-block adjacency of the declared stencils: for column vertex j, the row vertices i <= j it couples
  // with (sorted, unique).
  // The slots never replaced since they were declared (the elastic terms; not the moving contact pairs) are the
  // base: their adjacency is kept (keptRows_) and computed again only when the base changes. Every other slot's
  // pairs, replaced now or not, are added to a copy of it in the columns they touch. (Basing it on the slots
  // not replaced this time instead made two moving slots, replaced in turns, redo the base at most finalizes.)
  std::vector<char> base(slots_.size(), 0);
  for (std::size_t k = 0; k < slots_.size(); ++k) base[k] = !slots_[k].moving;
  auto addPairs = [&](const Slot& s, std::vector<std::vector<int>>& rows, std::vector<char>* touched) {
    const int w = s.table.width;
    for (int e = 0; e < s.table.size(); ++e) {
      const int* ids = s.table.element(e);
      for (int a = 0; a < w; ++a) {
        for (int b = 0; b < w; ++b) {
          if (ids[a] < 0 || ids[b] < 0 || ids[a] > ids[b]) continue;
          if (ids[a] >= n || ids[b] >= n) throw std::out_of_range("stencil vertex id out of range");
          rows[ids[b]].push_back(ids[a]);
          if (touched) (*touched)[ids[b]] = 1;
        }
      }
    }
  };
  auto sortUnique = [](std::vector<int>& r) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  };
  if (base != baseSlots_ || static_cast<int>(keptRows_.size()) != n) {
    // The base changed: its adjacency anew (no base slot: the diagonal alone).
    keptRows_.assign(static_cast<std::size_t>(n), {});
    for (int j = 0; j < n; ++j) keptRows_[j].push_back(j);
    for (std::size_t k = 0; k < slots_.size(); ++k)
      if (base[k]) addPairs(slots_[k], keptRows_, nullptr);
    for (auto& r : keptRows_) sortUnique(r);
    baseSlots_ = base;
  }
  std::vector<std::vector<int>> rowsOf = std::move(spareRows_);
  rowsOf.resize(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) rowsOf[j].assign(keptRows_[j].begin(), keptRows_[j].end());
  std::vector<char> touched(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < slots_.size(); ++k)
    if (!base[k]) addPairs(slots_[k], rowsOf, &touched);
  std::int64_t used = 0;
  for (int j = 0; j < n; ++j) {
    auto& r = rowsOf[j];
    if (touched[j]) sortUnique(r);
    used += static_cast<std::int64_t>(r.size());
  }
  usedPairs_ = used;

  // Grow-only: keep the old pattern when the new stencils fit in it; otherwise take the union, unless the union
  // would carry too many stale pairs (then the exact pattern: a pruning reset).
  const bool canKeep = growOnly_ && patternBuilds_ > 0 && static_cast<int>(rows_.size()) == n && fixed == fixedDof_;
  bool newPattern = true;
  if (canKeep) {
    std::vector<std::vector<int>> merged(static_cast<std::size_t>(n));
    std::int64_t mergedPairs = 0;
    bool grew = false;
    for (int j = 0; j < n; ++j) {
      const auto& a = rows_[j];
      const auto& b = rowsOf[j];
      auto& m = merged[j];
      m.reserve(a.size() + b.size());
      std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(m));
      grew = grew || m.size() != a.size();
      mergedPairs += static_cast<std::int64_t>(m.size());
    }
    if (!grew) {
      newPattern = false;
    } else if (static_cast<double>(mergedPairs - used) <= pruneFraction_ * static_cast<double>(used)) {
      rowsOf.swap(merged);
    }
  }
  // Slots not replaced keep their scatter tables with the pattern, or translate them to a new one: only over
  // the same vertices and fixed dofs (their tables then index the current matrix).
  const bool translatable = patternBuilds_ > 0 && static_cast<int>(rows_.size()) == n && fixed == fixedDof_;
  bool everything = !translatable;
  if (newPattern) {
    std::vector<std::int32_t> translation;
    bool anyKept = false;
    for (const Slot& s : slots_) anyKept = anyKept || !s.stale;
    if (translatable && anyKept) translation = translationTo(rowsOf);
    rows_.swap(rowsOf);  // rowsOf keeps the old pattern's buffers for the next finalize
    buildMatrix(n);
    ++patternBuilds_;
    ++patternVersion_;
    if (!translation.empty()) {
      // A block's index is its first entry's, which every block of the pattern has (the diagonal blocks too):
      // translated like an entry, its other entries follow from the new strides.
      auto translate = [&translation](std::vector<std::int32_t>& table) {
        std::int32_t* v = table.data();
        const std::int64_t count = static_cast<std::int64_t>(table.size());
#pragma omp parallel for schedule(static) if (count >= 65536)
        for (std::int64_t k = 0; k < count; ++k) {
          const std::int32_t idx = v[k];
          if (idx >= 0) v[k] = translation[static_cast<std::size_t>(idx)];
          else if (idx <= -2) v[k] = -2 - translation[static_cast<std::size_t>(-2 - idx)];
        }
      };
      for (Slot& s : slots_) {
        if (s.stale) continue;
        translate(s.blocks);
        translate(s.scatter);
      }
    }
  } else {
    ++patternReuses_;
  }
  spareRows_ = std::move(rowsOf);
  fixedDof_ = std::move(fixed);
  patternPairs_ = 0;
  for (const auto& r : rows_) patternPairs_ += static_cast<std::int64_t>(r.size());
  buildScatter(everything);
  finalized_ = true;
  setZero();
}

void HessianAssembler::buildMatrix(int numVertices) {
  const int n = numVertices;
  const int ndof = 3 * n;
  // CSC upper triangle: column 3j+c holds rows 3i..3i+2 of each i < j, then rows 3j..3j+c.
  std::vector<std::int64_t> outer(static_cast<std::size_t>(ndof) + 1, 0);
  for (int j = 0; j < n; ++j) {
    const std::int64_t offDiag = 3 * (static_cast<std::int64_t>(rows_[j].size()) - 1);
    for (int c = 0; c < 3; ++c) outer[3 * j + c + 1] = offDiag + c + 1;
  }
  for (int d = 0; d < ndof; ++d) outer[d + 1] += outer[d];
  if (outer[ndof] > std::numeric_limits<int>::max()) throw std::length_error("Hessian pattern exceeds 2^31 entries");
  const int nnz = static_cast<int>(outer[ndof]);

  matrix_ = Eigen::SparseMatrix<double>(ndof, ndof);
  matrix_.resizeNonZeros(nnz);
  int* outerPtr = matrix_.outerIndexPtr();
  int* innerPtr = matrix_.innerIndexPtr();
  for (int d = 0; d <= ndof; ++d) outerPtr[d] = static_cast<int>(outer[d]);
#pragma omp parallel for schedule(static) if (n >= 4096)
  for (int j = 0; j < n; ++j) {
    for (int c = 0; c < 3; ++c) {
      int p = outerPtr[3 * j + c];
      for (int i : rows_[j]) {
        const int rmax = i == j ? c : 2;
        for (int r = 0; r <= rmax; ++r) innerPtr[p++] = 3 * i + r;
      }
    }
  }
  diagonalIndex_.resize(static_cast<std::size_t>(ndof));
  for (int d = 0; d < ndof; ++d) diagonalIndex_[d] = outerPtr[d + 1] - 1;
  // Column 3j+c starts at outer[3j] + c·stride + c(c+1)/2 (column 3j+c holds stride + c + 1 entries).
  columnStride_.resize(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) columnStride_[j] = 3 * (static_cast<std::int32_t>(rows_[j].size()) - 1);
}

std::vector<std::int32_t> HessianAssembler::translationTo(const std::vector<std::vector<int>>& newRows) const {
  // Column 3j+c holds, per row vertex of rows[j] (ascending, j itself last), 3 entries (c + 1 for j): the entry of
  // row vertex rank k, component r, is at outer[3j+c] + 3k + r in either pattern.
  const int n = static_cast<int>(rows_.size());
  const int* outer = matrix_.outerIndexPtr();
  std::vector<std::int64_t> newOuter(static_cast<std::size_t>(3 * n) + 1, 0);
  for (int j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c)
      newOuter[3 * j + c + 1] = 3 * (static_cast<std::int64_t>(newRows[j].size()) - 1) + c + 1;
  for (int d = 0; d < 3 * n; ++d) newOuter[d + 1] += newOuter[d];
  if (newOuter[3 * n] > std::numeric_limits<int>::max()) throw std::length_error("Hessian pattern exceeds 2^31 entries");
  std::vector<std::int32_t> to(static_cast<std::size_t>(matrix_.nonZeros()), -1);
#pragma omp parallel for schedule(static) if (n >= 4096)
  for (int j = 0; j < n; ++j) {
    const auto& a = rows_[j];
    const auto& b = newRows[j];
    std::size_t q = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      while (q < b.size() && b[q] < a[k]) ++q;
      if (q == b.size() || b[q] != a[k]) continue;
      for (int c = 0; c < 3; ++c) {
        const int rows = a[k] == j ? c + 1 : 3;
        for (int r = 0; r < rows; ++r)
          to[static_cast<std::size_t>(outer[3 * j + c] + 3 * static_cast<std::int64_t>(k) + r)] =
              static_cast<std::int32_t>(newOuter[3 * j + c] + 3 * static_cast<std::int64_t>(q) + r);
      }
    }
  }
  return to;
}

void HessianAssembler::buildScatter(bool everything) {
  const int* outerPtr = matrix_.outerIndexPtr();
  for (Slot& s : slots_) {
    if (!s.stale && !everything) continue;
    s.stale = false;
    const int w = s.table.width;
    const int m = 3 * w;
    const std::size_t perElement = static_cast<std::size_t>(m) * (m + 1) / 2;
    const std::size_t pairs = static_cast<std::size_t>(w) * (w + 1) / 2;
    const int ne = s.table.size();
    // Elements with a fixed dof or a repeated vertex keep a per-entry table; the others one index per block.
    s.entryRow.assign(static_cast<std::size_t>(ne), -1);
    std::int32_t withEntries = 0;
    for (int e = 0; e < ne; ++e) {
      const int* ids = s.table.element(e);
      bool entries = false;
      for (int a = 0; a < w && !entries; ++a) {
        if (ids[a] < 0) continue;
        for (int c = 0; c < 3; ++c) entries = entries || fixedDof_[3 * ids[a] + c];
        for (int b = 0; b < a; ++b) entries = entries || ids[b] == ids[a];
      }
      if (entries) s.entryRow[e] = withEntries++;
    }
    s.blocks.assign(pairs * static_cast<std::size_t>(ne), -1);
    s.scatter.assign(perElement * static_cast<std::size_t>(withEntries), -1);
    // One pattern search per vertex pair of an element (not per dof entry: a ninth of the searches), elements
    // in parallel (each writes only its own table rows).
#pragma omp parallel if (ne >= 4096)
    {
    // rank[a * w + b]: for vertices ids[a] <= ids[b], the position of ids[a] among column ids[b]'s rows.
    std::vector<int> rank(static_cast<std::size_t>(w) * w);
#pragma omp for schedule(static)
    for (int e = 0; e < ne; ++e) {
      const int* ids = s.table.element(e);
      for (int b = 0; b < w; ++b) {
        for (int a = 0; a < w; ++a) {
          const int va = ids[a], vb = ids[b];
          if (va < 0 || vb < 0 || va > vb) continue;
          const auto& r = rows_[vb];
          rank[a * w + b] = static_cast<int>(std::lower_bound(r.begin(), r.end(), va) - r.begin());
        }
      }
      if (s.entryRow[e] < 0) {
        std::int32_t* out = s.blocks.data() + pairs * static_cast<std::size_t>(e);
        std::size_t k = 0;
        for (int b = 0; b < w; ++b) {
          for (int a = 0; a <= b; ++a, ++k) {
            const int va = ids[a], vb = ids[b];
            if (va < 0 || vb < 0) continue;
            // The global block's column vertex is the larger id, its row vertex the smaller.
            const int column = std::max(va, vb);
            const int k2 = va <= vb ? rank[a * w + b] : rank[b * w + a];
            out[k] = outerPtr[3 * column] + 3 * k2;
          }
        }
        continue;
      }
      std::int32_t* out = s.scatter.data() + perElement * static_cast<std::size_t>(s.entryRow[e]);
      std::size_t k = 0;
      for (int q = 0; q < m; ++q) {      // local column
        for (int p = 0; p <= q; ++p) {   // local row
          const int a = p / 3, b = q / 3;
          const int vp = ids[a], vq = ids[b];
          std::int32_t idx = -1;
          if (vp >= 0 && vq >= 0) {
            int rowDof = 3 * vp + p % 3, colDof = 3 * vq + q % 3;
            if (!fixedDof_[rowDof] && !fixedDof_[colDof]) {
              const bool swapped = rowDof > colDof;
              if (swapped) std::swap(rowDof, colDof);
              const int k2 = swapped ? rank[b * w + a] : rank[a * w + b];
              // Entry (rowDof, colDof), rowDof <= colDof: column colDof, block of row vertex rowDof / 3.
              idx = outerPtr[colDof] + 3 * k2 + rowDof % 3;
              // A repeated vertex maps an off-diagonal local entry onto a global diagonal: count it twice.
              if (p != q && rowDof == colDof) idx = -2 - idx;
            }
          }
          out[k++] = idx;
        }
      }
    }
    }
  }
}

void HessianAssembler::setZero() {
  double* v = matrix_.valuePtr();
  const std::int64_t nnz = matrix_.nonZeros();
#pragma omp parallel for simd schedule(static) if (nnz >= kParallelZeroValues)
  for (std::int64_t i = 0; i < nnz; ++i) v[i] = 0.0;
  for (std::size_t d = 0; d < fixedDof_.size(); ++d) {
    if (fixedDof_[d]) v[diagonalIndex_[d]] = 1.0;
  }
}

void HessianAssembler::addElementHessian(int slot, int element, const double* H) {
  const Slot& s = slots_[slot];
  const int w = s.table.width;
  const int m = 3 * w;
  double* v = matrix_.valuePtr();
  const std::int32_t row = s.entryRow[static_cast<std::size_t>(element)];
  if (row >= 0) {
    const std::size_t perElement = static_cast<std::size_t>(m) * (m + 1) / 2;
    const std::int32_t* idx = s.scatter.data() + perElement * static_cast<std::size_t>(row);
    std::size_t k = 0;
    for (int q = 0; q < m; ++q) {
      const double* col = H + static_cast<std::size_t>(q) * m;
      for (int p = 0; p <= q; ++p, ++k) {
        const std::int32_t i = idx[k];
        if (i >= 0) {
          v[i] += col[p];
        } else if (i <= -2) {
          v[-2 - i] += 2.0 * col[p];
        }
      }
    }
    return;
  }
  // Local entry (3a + r, 3b + c) of pair (a, b), a <= b (upper triangle), is H[(3b + c) m + 3a + r]. The global
  // block's entry (row r', column c') is at base + c'·stride + c'(c'+1)/2 + r', stride that of its column vertex.
  const int* ids = s.table.element(element);
  const std::int32_t* base = s.blocks.data() + static_cast<std::size_t>(w) * (w + 1) / 2 * element;
  std::size_t k = 0;
  for (int b = 0; b < w; ++b) {
    const double* colB = H + static_cast<std::size_t>(3 * b) * m;
    for (int a = 0; a <= b; ++a, ++k) {
      const std::int32_t i0 = base[k];
      if (i0 < 0) continue;
      const double* h = colB + 3 * a;  // h[c·m + r] = local (3a + r, 3b + c)
      if (a == b) {
        const std::int32_t stride = columnStride_[ids[b]];
        v[i0] += h[0];
        v[i0 + stride + 1] += h[m];
        v[i0 + stride + 2] += h[m + 1];
        v[i0 + 2 * stride + 3] += h[2 * m];
        v[i0 + 2 * stride + 4] += h[2 * m + 1];
        v[i0 + 2 * stride + 5] += h[2 * m + 2];
      } else if (ids[a] < ids[b]) {  // global block = local block: column c, row r
        const std::int32_t stride = columnStride_[ids[b]];
        for (int c = 0; c < 3; ++c) {
          double* out = v + i0 + c * stride + c * (c + 1) / 2;
          const double* in = h + c * m;
          out[0] += in[0];
          out[1] += in[1];
          out[2] += in[2];
        }
      } else {  // the transpose: global column r (of vertex ids[a]), row c
        const std::int32_t stride = columnStride_[ids[a]];
        for (int r = 0; r < 3; ++r) {
          double* out = v + i0 + r * stride + r * (r + 1) / 2;
          out[0] += h[r];
          out[1] += h[m + r];
          out[2] += h[2 * m + r];
        }
      }
    }
  }
}

std::size_t HessianAssembler::memoryBytes() const {
  std::size_t bytes = static_cast<std::size_t>(matrix_.nonZeros()) * (sizeof(double) + sizeof(int));
  for (const Slot& s : slots_)
    bytes += (s.blocks.size() + s.entryRow.size() + s.scatter.size()) * sizeof(std::int32_t) +
             s.table.ids.size() * sizeof(int);
  bytes += columnStride_.size() * sizeof(std::int32_t);
  for (const auto& r : rows_) bytes += r.size() * sizeof(int);
  for (const auto& r : keptRows_) bytes += r.size() * sizeof(int);
  for (const auto& r : spareRows_) bytes += r.capacity() * sizeof(int);
  return bytes;
}

}  // namespace jetshell
