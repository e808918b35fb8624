#pragma once
// How often a cleaning tool has swept each cell of a map: the coverage mission marks it with its
// localised pose, the simulator with the true pose to score a run. The tool is a segment of
// tool_width centred on the robot, across its heading; sweep(from, to) marks the cells whose
// centres it passed over between two poses (and the cells under it at `to`, a strip one cell
// deep, so a robot standing still still marks what it stands on).
//
// Pass rule: a cell's count is the number of separate passes of the tool over it. A cell is
// counted when it enters the tool: at most once per sweep() call, and not again while it stays
// under the tool from one call to the next (a cell marked by the previous call is not counted).
// A full turn on the spot passes the tool twice over every cell of its disk. Counts saturate at
// 255.
//
// Storage is sized by init(); sweep() and the queries never allocate.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"

namespace carril::fw {

class CoverageGrid {
 public:
  // Allocates counts for a map of info's size (init time). A step between two poses longer than
  // max_step_m is a jump (a relocalisation): only the tool at the new pose is marked [m].
  Status init(const MapInfo& info, double max_step_m = 1.0);
  bool ready() const { return counts_ != nullptr; }
  const MapInfo& info() const { return info_; }
  std::size_t size() const { return n_; }  // cells

  // Forgets every pass (the mask stays).
  void clear();
  // The cells the statistics count: mask[j * nx + i] != 0 (copied); nullptr = every cell. O(n).
  void set_mask(const std::uint8_t* mask);

  // Marks the cells the tool passed over from `from` to `to` (map frame) [m, rad]; tool_width_m
  // across the heading [m]. Work is bounded by the swept area (one jump: one tool's strip).
  void sweep(const Pose2& from, const Pose2& to, double tool_width_m);

  // Passes over cell (i, j) so far (0 outside the map).
  std::uint8_t count(int i, int j) const {
    return contains(i, j) ? counts_[index(i, j)] : std::uint8_t{0};
  }
  bool in_mask(int i, int j) const { return contains(i, j) && mask_[index(i, j)] != 0; }
  bool contains(int i, int j) const { return i >= 0 && j >= 0 && i < info_.nx && j < info_.ny; }

  std::size_t mask_cells() const { return mask_cells_; }        // cells counted [cells]
  std::size_t covered_cells() const { return covered_; }        // mask cells swept once or more
  std::size_t overlapped_cells() const { return overlapped_; }  // mask cells swept twice or more
  std::size_t swept_cells() const { return swept_; }            // any cell swept, mask or not
  // Covered mask cells / mask cells [0, 1] (0 for an empty mask).
  double covered_fraction() const;
  // Mask cells swept more than once / mask cells swept [0, 1] (0 when none is swept).
  double overlap_fraction() const;
  // The first mask cell never swept at row-major index >= `index` (j * nx + i); false when none
  // is left. O(cells scanned).
  bool next_unswept(std::size_t& index) const;
  // Counts, row-major from the lower-left cell (heat maps).
  const std::uint8_t* counts() const { return counts_.get(); }

 private:
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(info_.nx) +
           static_cast<std::size_t>(i);
  }
  void mark_step(const Pose2& a, const Pose2& b, double half);
  void mark_strip(const Pose2& p, double half);
  void mark_convex(const Vec2* pts, int n);
  void mark(std::size_t k);

  MapInfo info_;
  std::size_t n_ = 0;
  double max_step_m_ = 1.0;
  std::unique_ptr<std::uint8_t[]> counts_;
  std::unique_ptr<std::uint8_t[]> mask_;
  std::unique_ptr<std::uint32_t[]> stamp_;  // the sweep() call that last marked the cell
  std::uint32_t pass_ = 1;                  // this call's number (stamps start at 0)
  std::size_t mask_cells_ = 0, covered_ = 0, overlapped_ = 0, swept_ = 0;
};

}  // namespace carril::fw
