#include "firmware/perception/BlobLabeler.hpp"

#include <bit>

#include "firmware/perception/BitRuns.hpp"

namespace carril::fw {

namespace {

using bits::kAll;
using bits::valid_bits;

bool row_empty(const std::uint64_t* r, int stride) {
  std::uint64_t any = 0;
  for (int k = 0; k < stride; ++k) any |= r[k];
  return any == 0;
}

// 3x3 min (erode) or max (dilate) filter, separable: along rows into tmp, then across rows.
// Outside the image is `fill`: set for erosion, clear for dilation.
// Only the rows that can come out non-empty are computed: a mask is mostly empty (the end-mark
// mask usually wholly), and an empty row filters to an empty row in either pass (erosion's
// padding bits aside, which the last word's mask removes), so rows of `src` outside its first
// and last non-empty row read as zero, and the result is the same as over the whole image.
template <bool kErode>
void morph(const BitImage& src, const BitImage& dst, const BitImage& tmp) {
  const std::uint64_t fill = kErode ? kAll : 0;
  const int s = src.stride, h = src.height;
  int y0 = 0, y1 = h - 1;
  while (y0 < h && row_empty(src.row(y0), s)) ++y0;
  while (y1 >= y0 && row_empty(src.row(y1), s)) --y1;
  // Rows of the result that can be non-empty: erosion keeps within the set rows, dilation grows
  // them by one.
  const bool empty = y0 > y1;
  const int a = kErode || empty ? y0 : (y0 > 0 ? y0 - 1 : 0);
  const int b = kErode || empty ? y1 : (y1 + 1 < h ? y1 + 1 : h - 1);
  if (dst.bits != src.bits) {
    for (int y = 0; y < h; ++y) {
      if (y >= a && y <= b) continue;
      std::uint64_t* out = dst.row(y);
      for (int k = 0; k < s; ++k) out[k] = 0;
    }
  }
  if (empty) return;  // empty in, empty out
  const std::uint64_t last = valid_bits(src.width, s - 1);
  for (int y = y0; y <= y1; ++y) bits::hpass3<kErode>(src.row(y), s, last, tmp.row(y));
  // A neighbour row outside the image is `fill`; one inside it but outside [y0, y1] is empty.
  const auto tmp_row = [&](int y, std::uint64_t& constant) -> const std::uint64_t* {
    constant = y < 0 || y >= h ? fill : 0;
    return y >= y0 && y <= y1 ? tmp.row(y) : nullptr;
  };
  for (int y = a; y <= b; ++y) {
    std::uint64_t up_c = 0, mid_c = 0, dn_c = 0;
    const std::uint64_t* up = tmp_row(y - 1, up_c);
    const std::uint64_t* mid = tmp_row(y, mid_c);
    const std::uint64_t* dn = tmp_row(y + 1, dn_c);
    std::uint64_t* out = dst.row(y);
    for (int k = 0; k < s; ++k) {
      const std::uint64_t u = up ? up[k] : up_c, m = mid ? mid[k] : mid_c, d = dn ? dn[k] : dn_c;
      const std::uint64_t v = kErode ? (u & m & d) : (u | m | d);
      out[k] = k + 1 < s ? v : (v & last);
    }
  }
}

}  // namespace

void erode3x3(const BitImage& src, const BitImage& dst, const BitImage& tmp) {
  morph<true>(src, dst, tmp);
}
void dilate3x3(const BitImage& src, const BitImage& dst, const BitImage& tmp) {
  morph<false>(src, dst, tmp);
}

RunLabeler::RunLabeler(int height, int max_runs)
    : height_(height),
      max_runs_(max_runs),
      runs_(std::make_unique<Run[]>(std::size_t(max_runs))),
      parent_(std::make_unique<std::int32_t[]>(std::size_t(max_runs))),
      cells_(std::make_unique<std::int32_t[]>(std::size_t(max_runs))),
      box_(std::make_unique<std::int16_t[]>(std::size_t(max_runs) * 4)),
      row_start_(std::make_unique<std::int32_t[]>(std::size_t(height) + 1)) {}

RunLabeler::~RunLabeler() = default;

int RunLabeler::find(int i) {
  while (parent_[i] != i) {
    parent_[i] = parent_[parent_[i]];
    i = parent_[i];
  }
  return i;
}

void RunLabeler::unite(int a, int b) {
  const int ra = find(a), rb = find(b);
  // The smaller index becomes the root, so every run's parent precedes it.
  if (ra < rb) {
    parent_[rb] = ra;
  } else if (rb < ra) {
    parent_[ra] = rb;
  }
}

bool RunLabeler::label(const BitImage& m) {
  n_runs_ = 0;
  int prev_begin = 0, prev_end = 0;
  const int rows = m.height < height_ ? m.height : height_;
  for (int y = 0; y <= height_; ++y) row_start_[y] = 0;
  for (int y = 0; y < rows; ++y) {
    const std::uint64_t* r = m.row(y);
    const int begin = n_runs_;
    row_start_[y] = begin;
    if (row_empty(r, m.stride)) {  // most rows of a tape mask, every row of an unseen end mark
      prev_begin = prev_end = begin;
      continue;
    }
    // Stores a run; false when the run storage is full (the frame is then reported saturated).
    const auto add = [&](int x0, int x1) {
      if (n_runs_ == max_runs_) return false;
      runs_[n_runs_] = {std::int16_t(x0), std::int16_t(x1), std::int16_t(y)};
      parent_[n_runs_] = n_runs_;
      ++n_runs_;
      return true;
    };
    bits::RunScanner scan;
    bool ok = true;
    for (int k = 0; k < m.stride && ok; ++k) ok = scan.word(r[k], k, add);
    // A run reaching the last cell of a row whose width is a multiple of 64 ends there.
    if (!ok || !scan.finish(m.width - 1, add)) {
      n_runs_ = 0;
      return false;
    }
    // 8-connectivity: runs touch when they overlap or meet at a corner.
    int j = prev_begin;
    for (int i = begin; i < n_runs_; ++i) {
      while (j < prev_end && runs_[j].x1 < runs_[i].x0 - 1) ++j;
      for (int k = j; k < prev_end && runs_[k].x0 <= runs_[i].x1 + 1; ++k) unite(i, k);
    }
    prev_begin = begin;
    prev_end = n_runs_;
  }
  for (int y = rows; y <= height_; ++y) row_start_[y] = n_runs_;
  // Every parent precedes its run, so one forward pass leaves each run pointing at its root.
  for (int i = 0; i < n_runs_; ++i) {
    const int root = parent_[parent_[i]];
    parent_[i] = root;
    const Run& run = runs_[i];
    std::int16_t* b = &box_[std::size_t(root) * 4];
    if (root == i) {
      cells_[i] = 0;
      b[0] = run.x0;
      b[1] = run.x1;
      b[2] = run.y;
      b[3] = run.y;
    }
    cells_[root] += run.x1 - run.x0 + 1;
    if (run.x0 < b[0]) b[0] = run.x0;
    if (run.x1 > b[1]) b[1] = run.x1;
    b[3] = run.y;  // rows come in order
  }
  return true;
}

int RunLabeler::largest(int min_cells, int k, int* ids, int* cells) const {
  int n = 0;
  for (int i = 0; i < n_runs_; ++i) {
    if (parent_[i] != i || cells_[i] < min_cells) continue;
    const int c = cells_[i];
    if (n == k && c <= cells[n - 1]) continue;
    int p = n < k ? n++ : n - 1;
    while (p > 0 && cells[p - 1] < c) {
      ids[p] = ids[p - 1];
      cells[p] = cells[p - 1];
      --p;
    }
    ids[p] = i;
    cells[p] = c;
  }
  return n;
}

}  // namespace carril::fw
