#pragma once
// The lethal costmap cells round a rectangular body, gathered once a tick in the body frame, and
// the checks that keep the body off them: how far it can move along an arc, whether it can turn
// in place, which cell is nearest. A square body turning in place sweeps its circumscribed
// circle, not its inscribed one: its corners are checked, not only its front edge.
//
// Every check pads the body by pad_m plus half a cell (a cell is a square, not its centre).
// A cell already inside that padding at the current pose only stops the bare body (plus half a
// cell): moving along a wall passed close is allowed, moving into it is not.
#include <cstddef>
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/StaticVector.hpp"

namespace carril::fw {

class BodyGuard {
 public:
  // Cells gathered per tick; a window holding more (or a non-finite pose) is "crowded": every
  // motion check reports blocked.
  static constexpr std::size_t kMaxCells = 2048;
  // How the missions use the guard (goto and waypoints alike): arcs are checked no tighter than
  // kMaxCurvature, a turn in place kTurnMarginRad beyond what it turns in the reaction time, and
  // a blocked turn looks for a place it is clear from every kEscapeStepM up to kEscapeM.
  static constexpr double kMaxCurvature = 20.0;  // [1/m]
  static constexpr double kTurnMarginRad = 0.1;  // [rad]
  static constexpr double kEscapeStepM = 0.05;   // [m]
  static constexpr double kEscapeM = 1.0;        // [m]

  // The body's half length and half width [m], the clearance kept round it [m], and the radius
  // round the centre within which cells are gathered [m].
  BodyGuard(double half_length_m, double half_width_m, double pad_m, double radius_m);

  // The lethal cells of grid within the radius of pose, in the body frame. Never allocates.
  void gather(const Pose2& pose, const RollingGrid<std::uint8_t>& grid);
  // Adds another grid's lethal cells to those gathered (a second layer of the same frame).
  void add_cells(const Pose2& pose, const RollingGrid<std::uint8_t>& grid);
  // Adds points of another frame (`pose` is the body's pose in it) within the radius and outside
  // the body, as cells: lidar returns, which hold wherever the localisation puts the robot.
  void add_points(const Vec2* points, std::size_t count, const Pose2& pose);

  struct Nearest {
    bool found = false;
    double d_m = 0.0;  // centre to the cell's centre [m]
    Vec2 p{0.0, 0.0};  // the cell, body frame [m]
  };
  // The gathered cell nearest the centre.
  Nearest nearest() const;
  // The cell nearest the centre among those within within_m of p (body frame): an obstacle's
  // edge followed from tick to tick, never the far side of a gap.
  Nearest nearest_around(const Vec2& p, double within_m) const;

  // From p (body frame) to the nearest gathered cell [m]; 1e300 when none was gathered.
  double distance_to(const Vec2& p) const;
  struct Corridor {
    double first_m = 0.0;      // along the line to the first cell, length_m if none [m]
    double mean_side_m = 0.0;  // mean offset left of the line of the cells within depth_m past
                               // the first (which side of the line the obstacle lies on) [m]
    std::size_t cells = 0;     // those cells
    Vec2 first_p{0.0, 0.0};    // the first cell, body frame [m]
  };
  // Along the unit direction dir (body frame): the cells whose centres lie ahead of the centre
  // within half_width_m of the line, up to length_m.
  Corridor corridor(const Vec2& dir, double half_width_m, double length_m,
                    double depth_m = 0.0) const;
  // How far [m] the padded body can move along an arc of curvature k [1/m] (forward, or backward
  // with reverse) before it meets a cell, up to max_m (returned when nothing is met).
  double free_length(double k, bool reverse, double max_m) const;
  // How far [m] the padded body travels driving the body-frame twist t (any mix of vx, vy and
  // wz: a mecanum robot's strafe, an arc) before it meets a cell, up to max_m along its path;
  // max_m when nothing is met. A twist with no translation travels nothing: 0 ... but then
  // rotation_clear() is the question.
  double free_travel(const Twist& t, double max_m) const;
  // The padded body can turn in place through angle_rad (its sign the direction) [rad], here or
  // moved shift_m straight ahead (behind when negative) [m].
  bool rotation_clear(double angle_rad, double shift_m = 0.0) const;
  // Where a turn through angle_rad that is blocked here becomes clear: the nearest straight move,
  // every step_m up to max_m and behind first at each distance, from which the turn is clear and
  // whose way is free for the move and at least min_free_m. The signed move [m] (negative:
  // back), or 0 when there is none.
  double escape_shift(double angle_rad, double step_m, double max_m, double min_free_m) const;

  // The body is the disc inscribed in the rectangle (a round robot whose firmware footprint is
  // the square round it): every check uses the disc from now on.
  void set_round(bool round) { round_ = round; }
  // A cell already within the padding at the current pose stops any motion that brings it nearer
  // than by grazing (a quarter of the travel) or to within a centimetre of it (a rear corner
  // swinging into a box beside it), not only one that meets the bare body.
  void set_no_closer(bool on) { no_closer_ = on; }
  // Points added from now on (add_points: lidar returns, a surface measured where it is) count
  // as exact points, not as cells half a cell round them; gathered cells keep their half cell.
  void set_exact_points(bool exact) { exact_points_ = exact; }
  // Drops the gathered cells (not the points) for which keep(x, y) (body frame) is false: cells
  // the lidar sees now, whose surfaces its returns give exactly.
  template <typename Keep>
  void keep_cells_if(Keep keep) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < cells_.size(); ++i) {
      const Cell& k = cells_[i];
      if (k.grow == 0.0F || keep(double(k.x), double(k.y))) cells_[n++] = k;
    }
    cells_.truncate(n);
  }
  // The radius gathered from now on [m].
  void set_radius(double radius_m) { radius_ = radius_m; }
  std::size_t cells() const { return cells_.size(); }
  bool crowded() const { return crowded_; }
  double half_length() const { return hl_; }
  double half_width() const { return hw_; }
  double pad() const { return pad_; }
  double margin() const { return pad_ + half_cell_; }  // the padding every check adds [m]
  // The padded body's circumscribed radius: nothing nearer the centre, it turns freely [m].
  double swept_radius() const;

 private:
  struct Cell {
    float x, y;  // body frame [m]
    float grow;  // how far round its centre it reaches: half a cell, or 0 for an exact point
  };
  // The cell lies in the body at (x, y, yaw) (body frame of the gather pose), grown by grow [m].
  bool inside(const Cell& c, double x, double y, double yaw, double grow) const;
  // Some cell meets the body at (x, y, yaw): the padding for cells clear of the body at (x0, 0,
  // 0), half a cell for cells already inside it there. With no_closer, `travel` is how far the
  // motion has gone to get there [m] and `clear0` the body's clearance at (x0, y0) [m].
  bool hits(double x, double y, double yaw, double x0 = 0.0, double y0 = 0.0, double travel = 0.0,
            double clear0 = 0.0) const;
  // How far outside the body at (x, y, yaw) the cell's reach is; 0 or less: in it [m].
  double gap(const Cell& k, double x, double y, double yaw) const;
  // The least gap over the cells, body at (x0, y0) unturned [m]; 1e300 with none.
  double clearance_at(double x0, double y0) const;

  double hl_, hw_, pad_, radius_;
  bool round_ = false;
  bool exact_points_ = false;
  bool no_closer_ = false;
  double half_cell_ = 0.0;  // of the grid last gathered [m]
  bool crowded_ = false;
  StaticVector<Cell, kMaxCells> cells_;
};

}  // namespace carril::fw
