#include "host_sim/app/CoverageScore.hpp"

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "host_sim/output/PlotUtil.hpp"
#include "host_sim/output/RunOutputs.hpp"

namespace carril::sim {

CoverageScore::CoverageScore(const Scenario& s, const fw::FirmwareConfig& c,
                             const fw::OccupancyGrid& map)
    : tool_m_(c.coverage.tool_width_m),
      speed_mps_(c.coverage.speed_mps),
      area_(std::size_t(map.nx()) * std::size_t(map.ny())),
      map_(map) {
  fw::CoverageAreaConfig ac;
  ac.robot_radius_m = std::min(c.footprint().half_length_m, c.footprint().half_width_m);
  ac.tool_width_m = tool_m_;
  if (!c.coverage.area.empty()) {
    ac.polygon = c.coverage.area.begin();
    ac.polygon_size = c.coverage.area.size();
  }
  fw::Status st = area_.build(map, ac);
  int i = 0, j = 0;
  if (st && !(map.cell_of(s.robot.start.x, s.robot.start.y, i, j) && area_.keep_component(i, j))) {
    st = fw::Status::error("the start pose is not where the robot's centre fits");
  }
  if (st) st = grid_.init(map.info());
  if (!st) throw std::invalid_argument(s.source_path + ": mission.area: " + st.message());
  grid_.set_mask(area_.coverable());
}

void CoverageScore::add(const Pose2& p) {
  const fw::Pose2 now{p.x, p.y, p.yaw_rad};
  grid_.sweep(last_.value_or(now), now, tool_m_);
  last_ = now;
}

CoverageFigures CoverageScore::figures() const {
  CoverageFigures f;
  f.covered = grid_.covered_fraction();
  f.overlap = grid_.overlap_fraction();
  const double r = map_.resolution();
  f.area_m2 = double(grid_.mask_cells()) * r * r;
  f.lower_bound_s = f.area_m2 / (tool_m_ * speed_mps_);
  return f;
}

bool CoverageScore::write_png(const std::string& dir, std::string& error) const {
  // 4 px a cell, y up: walls black, outside the area grey, in it: unswept red, then swept once
  // green, twice yellow, three times or more orange to purple.
  constexpr int kPx = 4;
  const int nx = map_.nx(), ny = map_.ny();
  cv::Mat img(ny * kPx, nx * kPx, CV_8UC3, cv::Scalar(160, 160, 160));
  const cv::Vec3b kWall(30, 30, 30), kUnswept(60, 60, 230), kOnce(80, 190, 80),
      kTwice(60, 220, 230), kThrice(40, 140, 250), kMore(160, 60, 160);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      cv::Vec3b c(160, 160, 160);
      if (map_.at(i, j) == 254) {
        c = kWall;
      } else if (grid_.in_mask(i, j)) {
        const int n = grid_.count(i, j);
        c = n == 0 ? kUnswept : n == 1 ? kOnce : n == 2 ? kTwice : n == 3 ? kThrice : kMore;
      } else if (grid_.count(i, j) > 0) {
        c = cv::Vec3b(150, 200, 150);
      }
      img(cv::Rect(i * kPx, (ny - 1 - j) * kPx, kPx, kPx)).setTo(cv::Scalar(c[0], c[1], c[2]));
    }
  }
  const CoverageFigures f = figures();
  char text[160];
  std::snprintf(
      text, sizeof text,
      "covered %.1f %%  overlap %.1f %%  (red unswept, green 1, yellow 2, orange 3, purple 4+)",
      100.0 * f.covered, 100.0 * f.overlap);
  cv::putText(img, text, cv::Point(6, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  const std::string path = dir + "/coverage.png";
  std::string png, why;
  if (!plot::encode_png(img, png, why) || !write_file_atomic(path, png, why)) {
    error = path + ": cannot write the coverage heat map: " + why;
    return false;
  }
  return true;
}

}  // namespace carril::sim
