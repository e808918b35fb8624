// velocities.png: vx, vy and wz against time, three stacked panels sharing the time axis.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "host_sim/output/PlotUtil.hpp"
#include "host_sim/output/Plots.hpp"

namespace carril::sim {
namespace {

constexpr int kWidth = 1000, kHeight = 700;
constexpr int kLeft = 80, kRight = 20, kTop = 40, kBottom = 46, kGap = 16;
constexpr double kClampAbs = 1e6;  // plotted values are clamped here so ranges never overflow

const cv::Scalar kBlack(0, 0, 0), kGrid(225, 225, 225), kZero(110, 110, 110);

struct Series {
  const char* label;
  double TrajectoryRow::*field;
  cv::Scalar color;
};

struct Axis {
  double lo = 0.0, hi = 1.0;  // data range
  int p0 = 0, p1 = 1;         // pixel range (p0 maps lo)
  double px(double v) const { return p0 + (v - lo) / (hi - lo) * (p1 - p0); }
};

double clamped(double v) {
  return std::clamp(v, -kClampAbs, kClampAbs);
}

// Integer tick multiples of `step` inside [lo, hi]; counted, not accumulated, so no drift.
template <typename F>
void for_ticks(double lo, double hi, double step, F f) {
  const double k0 = std::ceil(lo / step - 1e-9), k1 = std::floor(hi / step + 1e-9);
  for (double k = k0; k <= k1 && k - k0 < 50; k += 1.0) f(k * step);
}

void draw_panel(cv::Mat& img, cv::Rect frame, const Series& s,
                const std::vector<TrajectoryRow>& rows, const Axis& tx, bool x_labels,
                bool have_data) {
  cv::rectangle(img, frame, cv::Scalar(255, 255, 255), cv::FILLED);
  Axis ty;
  ty.p0 = frame.y + frame.height;
  ty.p1 = frame.y;
  // y range: the data and zero, padded; a flat series gets +/-1 around its value.
  double lo = 0.0, hi = 0.0;
  for (const TrajectoryRow& r : rows) {
    const double v = r.*s.field;
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, clamped(v));
    hi = std::max(hi, clamped(v));
  }
  if (hi - lo < 1e-9) {
    lo -= 1.0;
    hi += 1.0;
  } else {
    const double pad = 0.08 * (hi - lo);
    lo -= pad;
    hi += pad;
  }
  ty.lo = lo;
  ty.hi = hi;

  const double ystep = plot::nice_step(hi - lo, 5);
  for_ticks(lo, hi, ystep, [&](double v) {
    const int y = static_cast<int>(std::lround(ty.px(v)));
    cv::line(img, {frame.x, y}, {frame.x + frame.width, y}, kGrid, 1);
    cv::line(img, {frame.x - 5, y}, {frame.x, y}, kBlack, 1);
    plot::put_text(img, plot::tick_label(v, ystep), {8, y + 5}, 0.42, kBlack);
  });
  const double xstep = plot::nice_step(tx.hi - tx.lo, 10);
  for_ticks(tx.lo, tx.hi, xstep, [&](double t) {
    const int x = static_cast<int>(std::lround(tx.px(t)));
    cv::line(img, {x, frame.y}, {x, frame.y + frame.height}, kGrid, 1);
    cv::line(img, {x, frame.y + frame.height}, {x, frame.y + frame.height + 5}, kBlack, 1);
    if (x_labels)
      plot::put_text(img, plot::tick_label(t, xstep), {x - 10, frame.y + frame.height + 20}, 0.42,
                     kBlack);
  });
  const int y0 = static_cast<int>(std::lround(ty.px(0.0)));
  cv::line(img, {frame.x, y0}, {frame.x + frame.width, y0}, kZero, 1);

  // The series, broken wherever a value is not finite.
  std::vector<cv::Point> run;
  auto flush = [&] {
    if (run.size() >= 2) cv::polylines(img, run, false, s.color, 2, cv::LINE_AA, 0);
    run.clear();
  };
  for (const TrajectoryRow& r : rows) {
    const double v = r.*s.field;
    if (!std::isfinite(v) || !std::isfinite(r.t)) {
      flush();
      continue;
    }
    run.emplace_back(static_cast<int>(std::lround(tx.px(std::clamp(r.t, tx.lo, tx.hi)))),
                     static_cast<int>(std::lround(ty.px(clamped(v)))));
  }
  flush();

  cv::rectangle(img, frame, kBlack, 1);
  // The label on a light box, so that the curve under it does not hide it.
  int baseline = 0;
  const cv::Size ts = cv::getTextSize(s.label, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &baseline);
  plot::shade_rect(img, cv::Rect(frame.x + 2, frame.y + 2, ts.width + 12, ts.height + 12),
                   cv::Scalar(255, 255, 255), 0.85);
  plot::put_text(img, s.label, {frame.x + 8, frame.y + 8 + ts.height}, 0.5, s.color, 0, 1);
  if (!have_data) {
    plot::put_text(img, "no data", {frame.x + frame.width / 2 - 35, frame.y + frame.height / 2},
                   0.7, kZero, 0, 2);
  }
}

}  // namespace

bool render_velocities_png(const std::vector<TrajectoryRow>& rows, const RunSummary& summary,
                           std::string& png, std::string& error) {
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(242, 242, 242));
  plot::put_text(img, "velocities - " + summary.scenario, {kLeft, 26}, 0.6, kBlack,
                 kWidth - kLeft - kRight);

  Axis tx;
  tx.p0 = kLeft;
  tx.p1 = kWidth - kRight;
  bool have_t = false;
  for (const TrajectoryRow& r : rows) {
    if (!std::isfinite(r.t)) continue;
    const double t = clamped(r.t);
    tx.lo = have_t ? std::min(tx.lo, t) : t;
    tx.hi = have_t ? std::max(tx.hi, t) : t;
    have_t = true;
  }
  if (!have_t) tx.lo = 0.0;
  if (!(tx.hi - tx.lo > 1e-9)) tx.hi = tx.lo + 1.0;

  const Series series[] = {{"vx [m/s]", &TrajectoryRow::vx, cv::Scalar(180, 119, 31)},
                           {"vy [m/s]", &TrajectoryRow::vy, cv::Scalar(44, 160, 44)},
                           {"wz [rad/s]", &TrajectoryRow::wz, cv::Scalar(14, 127, 255)}};
  const int panel_h = (kHeight - kTop - kBottom - 2 * kGap) / 3;
  for (int i = 0; i < 3; ++i) {
    const cv::Rect frame(kLeft, kTop + i * (panel_h + kGap), kWidth - kLeft - kRight, panel_h);
    draw_panel(img, frame, series[i], rows, tx, i == 2, have_t);
  }
  plot::put_text(img, "t [s]", {kWidth / 2 - 15, kHeight - 6}, 0.5, kBlack);
  return plot::encode_png(img, png, error);
}

}  // namespace carril::sim
