#pragma once
// Renders what the robot's downward-tilted camera sees of the floor: floor colour with a light
// world-fixed texture, tape, marks and obstacle footprints, by projecting their ground polygons
// through the camera model (no per-pixel warp), with optional Gaussian pixel noise. Output is the
// real driver's frame type. Worn tape (gaps, a faded colour: TapeWear.hpp), exposure and glare
// (CameraEffects.hpp) come from the scenario.
//
// The texture: one speckle per kSpeckleCell-metre floor cell, its place, size and shade drawn
// from a hash of the cell (the same floor in every run). A speckle's colour is the floor colour
// times a factor in [0.85, 1.15] (floors darker than 56 per channel: plus or minus up to 12
// levels instead). A real floor is never one flat colour and its image changes as the robot
// moves; the camera health rules rely on both (firmware/health).
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "firmware/perception/CameraModel.hpp"
#include "hal/Types.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/sensors/CameraEffects.hpp"
#include "host_sim/sensors/ConvexFill.hpp"
#include "loader/FirmwareConfigBuilder.hpp"

namespace carril::sim {

class CameraRenderer {
 public:
  CameraRenderer(const Scenario& scenario, std::uint64_t seed);
  const fw::CameraModel& model() const { return cam_; }
  // Renders the view from a robot at `pose` into `frame` (width/height set from the camera spec).
  // `as_rendered`: the caller vouches that `frame` holds this renderer's last render into it,
  // untouched since; then only what that render drew on the floor is put back to floor.
  void render(const Pose2& pose, hal::CameraFrame& frame, bool as_rendered = false);
  // Test only: render with the plain floor fill and texture walk the fast paths must equal.
  void use_reference_path(bool on) { reference_ = on; }
  // Frames drawn over their predecessor (unfill) rather than on a whole floor fill.
  std::uint64_t unfills() const { return unfills_; }

 private:
  struct Poly {
    std::vector<Vec2> pts;  // world frame, convex
    Rgb color;
    double cx, cy, r;  // bounding circle, for culling
  };
  void add_poly(std::vector<Vec2> pts, Rgb color);
  // A stretch of tape along `pts` (quads with round joins where it turns).
  void add_tape(const std::vector<Vec2>& pts, double width_m, Rgb color);
  // Projects the world floor polygon `pts` seen from `pose` and fills it; scratch vectors reused.
  void draw(const std::vector<Vec2>& pts, Rgb color, const Pose2& pose, double co, double si,
            cv::Mat& img);
  // The floor texture: the cells that may show, in world order; speckles that cannot show skipped.
  void draw_texture(const Pose2& pose, cv::Mat& img);
  // The plain texture walk (every cell of the world box round the visible floor), for tests.
  void draw_texture_reference(const Pose2& pose, cv::Mat& img);
  // Speckle `h`'s quad round its world centre (cx, cy) [m], 4 to 10 cm across; into speckle_.
  void speckle_quad(std::uint64_t h, double cx, double cy);
  // The speckle of floor cell (i, j) with hash h: its centre in the world and in the frame of a
  // robot at `pose` (co, si: cos and sin of its yaw) [m]; false when outside the robot-frame box
  // of visible floor.
  bool speckle_centre(const Pose2& pose, double co, double si, std::uint64_t h, std::int64_t i,
                      std::int64_t j, Vec2& world, Vec2& robot) const;
  // Sets every pixel of `img` to colour `c` (the bytes cv::Mat::setTo writes, without its loop).
  static void fill_floor(Rgb c, cv::Mat& img);
  // Puts floor colour `c` back where the last frame drew (drawn_): the same bytes as fill_floor()
  // on a frame holding that render.
  void unfill(Rgb c, cv::Mat& img) const;
  // Whether a floor disc at robot-frame (x, y) of radius r [m] can put a pixel in the image.
  bool may_show(double x, double y, double r) const;

  const Scenario& scenario_;
  fw::CameraModel cam_;
  std::vector<Poly> polys_;  // drawn in order: obstacles last, over the tape
  double view_radius_m_;     // floor points further than this from the camera are not visible
  double texture_x0_, texture_x1_, texture_y_;  // robot-frame box holding the visible floor [m]
  // Robot-frame floor half-planes a*x + b*y + c >= 0 [m] ((a, b) a unit vector): a point on the
  // negative side of any is behind the near plane or projects 2 px or more outside the image.
  struct HalfPlane {
    double a, b, c;
  };
  std::vector<HalfPlane> view_;
  // Robot-frame convex polygon holding every speckle centre that may show: the centre box cut by
  // the half-planes moved out by the largest speckle radius. Its world copy is rebuilt per frame.
  std::vector<Vec2> texture_region_, region_world_;
  bool reference_ = false;
  std::vector<fw::Vec3> in_, out_;
  std::vector<FixedPt> px_;       // the projected polygon [1/16 px]
  std::vector<cv::Point> cv_px_;  // its copy for cv::fillConvexPoly (reference path)
  std::vector<Vec2> speckle_;
  double noise_std_;
  // Precomputed N(0, std) samples, rounded: each as max(v, 0) and max(-v, 0).
  std::vector<std::uint8_t> noise_up_, noise_down_;
  std::mt19937_64 rng_;
  CameraEffects effects_;  // exposure and glare
  std::uint64_t frames_ = 0;
  // What the last frame drew over the floor, for unfill(): each polygon's vertices (drawn_pts_
  // from `first`, n of them) and the pixel box holding every pixel it set (a polygon's fill and
  // outline stay within its rounded vertices' box; one pixel more is kept), or the glare's box
  // (n = 0). drawn_frame_: the buffer it was drawn into (null when none is kept: noise touched
  // every pixel), drawn_floor_ the floor colour under it.
  struct Drawn {
    std::uint32_t first, n;
    int x0, y0, x1, y1;
  };
  std::vector<Drawn> drawn_;
  std::vector<FixedPt> drawn_pts_;
  bool keep_drawn_ = false;
  std::uint64_t unfills_ = 0;
  const std::uint8_t* drawn_frame_ = nullptr;
  Rgb drawn_floor_{};
};

// The firmware configuration's own mapping, so the rendered image is the one it expects.
using loader::camera_mount;

}  // namespace carril::sim
