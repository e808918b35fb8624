#pragma once
// Wavefront (Dijkstra from the goal) over a uint8 costmap, 8-connected, then steepest descent
// from the robot. Buffers are sized once by init(); start()/step()/extract_path() never allocate.
// A plan may be spread over several ticks: step() expands at most a given number of cells.
//
// Cost model: a step from cell u into cell v costs length * (1 + cost_weight * cost(v) / 252),
// length 1 (orthogonal) or sqrt 2 (diagonal), in cells. Lethal (254) and inscribed (253) are
// impassable, unknown (255) too unless allow_unknown (then it costs unknown_cost). A diagonal
// step between two impassable orthogonal neighbours is not allowed (no squeezing through).
//
// Queue: an indexed 4-ary min-heap in an array of one slot per cell (decrease-key in place, so
// its capacity is exactly the cell count). Cost grid: copied into an internal grid with a
// one-cell impassable border, so neighbour lookups need no bounds checks.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct WavefrontConfig {
  bool allow_unknown = false;       // unknown (255) cells passable at unknown_cost
  std::uint8_t unknown_cost = 200;  // cost of an unknown cell when allowed [0, 252]
  double cost_weight = 3.0;         // extra traversal per unit of cell cost / 252 [-]

  Status validate() const;
  bool operator==(const WavefrontConfig&) const = default;
};

// A cell of the planning grid, window index from its lower-left corner.
struct GridCell {
  int x = 0;
  int y = 0;
};

enum class WavefrontStatus : std::uint8_t {
  Idle,         // nothing started
  Running,      // expansion under way
  Done,         // the start's distance is final, or the whole reachable grid was expanded
  GoalOutside,  // goal not inside the grid
  GoalBlocked,  // goal on an impassable cell
  BadGrid,      // grid larger than init()'s maximum, or no buffers
};

enum class PathResult : std::uint8_t {
  Ok,
  NotReady,     // the expansion has not finished (or was never started)
  Unreachable,  // no path from that cell (outside, blocked or cut off)
  TooLong,      // the path does not fit in the output
};

const char* to_string(WavefrontStatus s);
const char* to_string(PathResult r);

class WavefrontPlanner {
 public:
  static constexpr float kInfinity = 3.0e38f;  // distance of a cell not (yet) reached

  // Allocates buffers for grids up to max_nx * max_ny cells (init time). false on bad sizes.
  bool init(int max_nx, int max_ny, const WavefrontConfig& cfg);
  // Replaces the configuration (takes effect at the next start()).
  void set_config(const WavefrontConfig& cfg) { cfg_ = cfg; }
  const WavefrontConfig& config() const { return cfg_; }

  // Starts a wavefront from the goal over `costs` (row-major nx * ny, index y * nx + x, COPIED:
  // the caller may reuse its buffer). O(nx * ny) to reset the field. Returns Running, or
  // GoalOutside / GoalBlocked / BadGrid (then nothing is expanded).
  WavefrontStatus start(const std::uint8_t* costs, int nx, int ny, int goal_x, int goal_y);
  // Same from a costmap window, goal by GLOBAL cell index; planner cells are window indices
  // (global - origin).
  WavefrontStatus start(const RollingGrid<std::uint8_t>& grid, int goal_cx, int goal_cy);
  // Optional: the robot's cell; step() then stops as soon as that cell's distance is final.
  // Cleared by start(). A start outside the grid is ignored (full expansion).
  void set_start(int start_x, int start_y);

  // Expands at most max_expansions cells. Running while work remains, Done when finished.
  WavefrontStatus step(std::uint32_t max_expansions);
  WavefrontStatus status() const { return status_; }
  std::uint32_t expanded() const { return expanded_; }  // cells settled since start()

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  // True when the cell's distance to the goal is final and finite.
  bool reachable(int x, int y) const;
  // Traversal cost to the goal [cell lengths, weighted]; kInfinity when not reachable (yet).
  float cost_to_goal(int x, int y) const;

  // Traversal cost of one step into a cell of cost `cell_cost` (as float, exactly what the
  // expansion adds) [cell lengths]: 1 or sqrt 2 times 1 + cost_weight * cell_cost / 252.
  float step_weight(std::uint8_t cell_cost, bool diagonal) const;

  // Steepest descent on the field from (start_x, start_y) to the goal: at each cell the
  // neighbour minimising step cost + distance (exactly the Dijkstra relation, so the distance
  // strictly falls: no local minima); ties go to the first in E, N, W, S, NE, NW, SW, SE order.
  // out receives the cells from start to goal inclusive.
  template <std::size_t N>
  PathResult extract_path(int start_x, int start_y, StaticVector<GridCell, N>& out) const {
    out.clear();
    return extract_impl(start_x, start_y, &out, &push_cell<N>);
  }

 private:
  using PushFn = bool (*)(void* out, GridCell c);
  template <std::size_t N>
  static bool push_cell(void* out, GridCell c) {
    return static_cast<StaticVector<GridCell, N>*>(out)->try_push_back(c);
  }
  PathResult extract_impl(int sx, int sy, void* out, PushFn push) const;

  bool prepare(int nx, int ny);
  WavefrontStatus seed(int goal_x, int goal_y);
  std::size_t pidx(int x, int y) const {
    return std::size_t(y + 1) * std::size_t(stride_) + std::size_t(x + 1);
  }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < nx_ && y < ny_; }
  bool diagonal_open(std::size_t u, int k) const;

  // Heap operations (indexed 4-ary min-heap on dist_).
  void heap_push_or_decrease(std::uint32_t cell, float key);
  std::uint32_t heap_pop();
  void sift_up(std::uint32_t slot, std::uint32_t cell, float key);
  void sift_down(std::uint32_t slot, std::uint32_t cell, float key);

  static constexpr std::uint8_t kBlocked = 255;          // impassable in the internal grid
  static constexpr std::uint32_t kUnseen = 0xFFFFFFFFu;  // pos_: never queued
  static constexpr std::uint32_t kClosed = 0xFFFFFFFEu;  // pos_: distance final

  WavefrontConfig cfg_;
  int max_nx_ = 0, max_ny_ = 0;
  int nx_ = 0, ny_ = 0, stride_ = 0;
  std::size_t padded_ = 0;

  std::unique_ptr<std::uint8_t[]> cost_;  // internal cost per padded cell (kBlocked = wall)
  std::unique_ptr<float[]> dist_;         // distance to goal per padded cell
  std::unique_ptr<std::uint32_t[]> pos_;  // heap slot, kUnseen or kClosed per padded cell
  struct HeapEntry {
    float key;
    std::uint32_t cell;
  };
  std::unique_ptr<HeapEntry[]> heap_;
  std::uint32_t heap_size_ = 0;

  std::uint8_t translate_[256] = {};  // costmap value -> internal cost (kBlocked = impassable)
  float factor_[256] = {};            // orthogonal step weight per internal cost
  float factor_diag_[256] = {};       // diagonal step weight per internal cost
  std::ptrdiff_t offset_[8] = {};
  std::uint32_t expanded_ = 0;
  std::size_t start_cell_ = 0;  // 0: none (index 0 is a border cell, never a real one)
  WavefrontStatus status_ = WavefrontStatus::Idle;
};

}  // namespace carril::fw
