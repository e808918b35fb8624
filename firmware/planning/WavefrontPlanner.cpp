#include "firmware/planning/WavefrontPlanner.hpp"

#include <cmath>

#include "firmware/mapping/CostValues.hpp"

namespace carril::fw {

namespace {
constexpr float kSqrt2 = 1.41421356237309504880f;
// Orthogonal neighbours of diagonal k (4..7): NE -> E, N; NW -> N, W; SW -> W, S; SE -> S, E.
constexpr int kOrthoA[8] = {0, 0, 0, 0, 0, 1, 2, 3};
constexpr int kOrthoB[8] = {0, 0, 0, 0, 1, 2, 3, 0};
}  // namespace

Status WavefrontConfig::validate() const {
  return Checks("planner")
      .range("unknown_cost", unknown_cost, 0.0, double(cost::kMaxGraded), "cost")
      .range("cost_weight", cost_weight, 0.0, 1000.0, "")
      .result();
}

const char* to_string(WavefrontStatus s) {
  switch (s) {
    case WavefrontStatus::Idle:
      return "idle";
    case WavefrontStatus::Running:
      return "running";
    case WavefrontStatus::Done:
      return "done";
    case WavefrontStatus::GoalOutside:
      return "goal outside the map";
    case WavefrontStatus::GoalBlocked:
      return "goal in obstacle";
    case WavefrontStatus::BadGrid:
      return "grid larger than the planner's buffers";
  }
  return "?";
}

const char* to_string(PathResult r) {
  switch (r) {
    case PathResult::Ok:
      return "ok";
    case PathResult::NotReady:
      return "plan not finished";
    case PathResult::Unreachable:
      return "no path";
    case PathResult::TooLong:
      return "path longer than the output";
  }
  return "?";
}

bool WavefrontPlanner::init(int max_nx, int max_ny, const WavefrontConfig& cfg) {
  if (max_nx <= 0 || max_ny <= 0 || max_nx > 20000 || max_ny > 20000) return false;
  if (!cfg.validate().is_ok()) return false;
  cfg_ = cfg;
  max_nx_ = max_nx;
  max_ny_ = max_ny;
  const std::size_t padded = std::size_t(max_nx + 2) * std::size_t(max_ny + 2);
  cost_ = std::make_unique<std::uint8_t[]>(padded);
  dist_ = std::make_unique<float[]>(padded);
  pos_ = std::make_unique<std::uint32_t[]>(padded);
  heap_ = std::make_unique<HeapEntry[]>(std::size_t(max_nx) * std::size_t(max_ny));
  status_ = WavefrontStatus::Idle;
  return true;
}

float WavefrontPlanner::step_weight(std::uint8_t cell_cost, bool diagonal) const {
  const float f = float(1.0 + cfg_.cost_weight * double(cell_cost) / double(cost::kMaxGraded));
  return diagonal ? f * kSqrt2 : f;
}

// Sizes the padded grid, resets the field and builds the lookup tables. Costs are filled after.
bool WavefrontPlanner::prepare(int nx, int ny) {
  start_cell_ = 0;
  heap_size_ = 0;
  expanded_ = 0;
  if (!cost_ || nx <= 0 || ny <= 0 || nx > max_nx_ || ny > max_ny_) {
    nx_ = ny_ = 0;
    status_ = WavefrontStatus::BadGrid;
    return false;
  }
  nx_ = nx;
  ny_ = ny;
  stride_ = nx + 2;
  padded_ = std::size_t(nx + 2) * std::size_t(ny + 2);
  for (std::size_t i = 0; i < padded_; ++i) {
    dist_[i] = kInfinity;
    pos_[i] = kUnseen;
  }
  // Border rows and columns are walls, so the expansion never needs a bounds check.
  for (int x = 0; x < stride_; ++x) {
    cost_[std::size_t(x)] = kBlocked;
    cost_[std::size_t(ny + 1) * std::size_t(stride_) + std::size_t(x)] = kBlocked;
  }
  for (int y = 1; y <= ny; ++y) {
    cost_[std::size_t(y) * std::size_t(stride_)] = kBlocked;
    cost_[std::size_t(y) * std::size_t(stride_) + std::size_t(nx + 1)] = kBlocked;
  }
  for (int c = 0; c < 256; ++c) {
    const auto u = std::uint8_t(c);
    if (cost::passable(u)) {
      translate_[c] = u;
    } else if (u == cost::kUnknown && cfg_.allow_unknown) {
      translate_[c] = cfg_.unknown_cost;
    } else {
      translate_[c] = kBlocked;
    }
    factor_[c] = step_weight(u, false);
    factor_diag_[c] = step_weight(u, true);
  }
  const auto s = std::ptrdiff_t(stride_);
  const std::ptrdiff_t offsets[8] = {1, s, -1, -s, s + 1, s - 1, -s - 1, -s + 1};
  for (int k = 0; k < 8; ++k) offset_[k] = offsets[k];
  return true;
}

WavefrontStatus WavefrontPlanner::seed(int goal_x, int goal_y) {
  if (!inside(goal_x, goal_y)) return status_ = WavefrontStatus::GoalOutside;
  const std::size_t g = pidx(goal_x, goal_y);
  if (cost_[g] == kBlocked) return status_ = WavefrontStatus::GoalBlocked;
  dist_[g] = 0.0f;
  heap_push_or_decrease(std::uint32_t(g), 0.0f);
  return status_ = WavefrontStatus::Running;
}

WavefrontStatus WavefrontPlanner::start(const std::uint8_t* costs, int nx, int ny, int goal_x,
                                        int goal_y) {
  if (costs == nullptr || !prepare(nx, ny)) return status_ = WavefrontStatus::BadGrid;
  for (int y = 0; y < ny; ++y) {
    const std::uint8_t* in = costs + std::size_t(y) * std::size_t(nx);
    std::uint8_t* row = &cost_[pidx(0, y)];
    for (int x = 0; x < nx; ++x) row[x] = translate_[in[x]];
  }
  return seed(goal_x, goal_y);
}

WavefrontStatus WavefrontPlanner::start(const RollingGrid<std::uint8_t>& grid, int goal_cx,
                                        int goal_cy) {
  if (!grid.ready() || !prepare(grid.nx(), grid.ny())) return status_ = WavefrontStatus::BadGrid;
  const int off = grid.column_offset();
  for (int y = 0; y < ny_; ++y) {
    const std::uint8_t* in = grid.storage_row(y);
    std::uint8_t* row = &cost_[pidx(0, y)];
    // The window row is storage [off, nx) followed by [0, off).
    const int first = nx_ - off;
    for (int x = 0; x < first; ++x) row[x] = translate_[in[off + x]];
    for (int x = first; x < nx_; ++x) row[x] = translate_[in[x - first]];
  }
  return seed(goal_cx - grid.origin_cx(), goal_cy - grid.origin_cy());
}

void WavefrontPlanner::set_start(int start_x, int start_y) {
  start_cell_ = (nx_ > 0 && inside(start_x, start_y)) ? pidx(start_x, start_y) : 0;
}

bool WavefrontPlanner::diagonal_open(std::size_t u, int k) const {
  return cost_[std::size_t(std::ptrdiff_t(u) + offset_[kOrthoA[k]])] != kBlocked ||
         cost_[std::size_t(std::ptrdiff_t(u) + offset_[kOrthoB[k]])] != kBlocked;
}

WavefrontStatus WavefrontPlanner::step(std::uint32_t max_expansions) {
  if (status_ != WavefrontStatus::Running) return status_;
  for (std::uint32_t n = 0; n < max_expansions; ++n) {
    if (start_cell_ != 0 && pos_[start_cell_] == kClosed) return status_ = WavefrontStatus::Done;
    if (heap_size_ == 0) return status_ = WavefrontStatus::Done;
    const std::uint32_t v = heap_pop();
    ++expanded_;
    const float d = dist_[v];
    // Every step INTO v costs v's factor: the robot pays for the cell it enters.
    const float w_orth = factor_[cost_[v]];
    const float w_diag = factor_diag_[cost_[v]];
    for (int k = 0; k < 8; ++k) {
      const auto u = std::size_t(std::ptrdiff_t(v) + offset_[k]);
      if (cost_[u] == kBlocked || pos_[u] == kClosed) continue;
      if (k >= 4 && !diagonal_open(v, k)) continue;
      const float cand = d + (k < 4 ? w_orth : w_diag);
      if (cand < dist_[u]) {
        dist_[u] = cand;
        heap_push_or_decrease(std::uint32_t(u), cand);
      }
    }
  }
  if (start_cell_ != 0 && pos_[start_cell_] == kClosed) return status_ = WavefrontStatus::Done;
  if (heap_size_ == 0) return status_ = WavefrontStatus::Done;
  return status_;
}

bool WavefrontPlanner::reachable(int x, int y) const {
  return nx_ > 0 && inside(x, y) && pos_[pidx(x, y)] == kClosed;
}

float WavefrontPlanner::cost_to_goal(int x, int y) const {
  return reachable(x, y) ? dist_[pidx(x, y)] : kInfinity;
}

PathResult WavefrontPlanner::extract_impl(int sx, int sy, void* out, PushFn push) const {
  if (status_ != WavefrontStatus::Done) return PathResult::NotReady;
  if (!reachable(sx, sy)) return PathResult::Unreachable;
  std::size_t u = pidx(sx, sy);
  // The distance strictly falls at every step, so the walk ends within the cell count.
  for (std::size_t guard = 0; guard <= padded_; ++guard) {
    const auto ux = int(u % std::size_t(stride_)) - 1;
    const auto uy = int(u / std::size_t(stride_)) - 1;
    if (!push(out, GridCell{ux, uy})) return PathResult::TooLong;
    if (dist_[u] == 0.0f) return PathResult::Ok;  // only the goal is at 0
    std::size_t best = 0;
    float best_value = kInfinity;
    for (int k = 0; k < 8; ++k) {
      const auto n = std::size_t(std::ptrdiff_t(u) + offset_[k]);
      if (cost_[n] == kBlocked || pos_[n] != kClosed) continue;
      if (k >= 4 && !diagonal_open(u, k)) continue;
      const float value = dist_[n] + (k < 4 ? factor_[cost_[n]] : factor_diag_[cost_[n]]);
      if (value < best_value) {
        best_value = value;
        best = n;
      }
    }
    if (best == 0 || !(dist_[best] < dist_[u])) return PathResult::Unreachable;
    u = best;
  }
  return PathResult::Unreachable;
}

// ---- indexed 4-ary min-heap: heap_[slot] = {key, cell}, pos_[cell] = slot ----

void WavefrontPlanner::heap_push_or_decrease(std::uint32_t cell, float key) {
  const std::uint32_t slot = pos_[cell];
  if (slot == kUnseen) {
    sift_up(heap_size_++, cell, key);
  } else {
    sift_up(slot, cell, key);  // only ever decreased
  }
}

void WavefrontPlanner::sift_up(std::uint32_t slot, std::uint32_t cell, float key) {
  while (slot > 0) {
    const std::uint32_t parent = (slot - 1) / 4;
    if (!(key < heap_[parent].key)) break;
    heap_[slot] = heap_[parent];
    pos_[heap_[slot].cell] = slot;
    slot = parent;
  }
  heap_[slot] = {key, cell};
  pos_[cell] = slot;
}

void WavefrontPlanner::sift_down(std::uint32_t slot, std::uint32_t cell, float key) {
  for (;;) {
    const std::uint32_t first = 4 * slot + 1;
    if (first >= heap_size_) break;
    const std::uint32_t last = first + 4 < heap_size_ ? first + 4 : heap_size_;
    std::uint32_t best = first;
    float best_key = heap_[first].key;
    for (std::uint32_t c = first + 1; c < last; ++c) {
      if (heap_[c].key < best_key) {
        best_key = heap_[c].key;
        best = c;
      }
    }
    if (!(best_key < key)) break;
    heap_[slot] = heap_[best];
    pos_[heap_[slot].cell] = slot;
    slot = best;
  }
  heap_[slot] = {key, cell};
  pos_[cell] = slot;
}

std::uint32_t WavefrontPlanner::heap_pop() {
  const std::uint32_t top = heap_[0].cell;
  pos_[top] = kClosed;
  --heap_size_;
  if (heap_size_ > 0) {
    const HeapEntry last = heap_[heap_size_];
    sift_down(0, last.cell, last.key);
  }
  return top;
}

}  // namespace carril::fw
