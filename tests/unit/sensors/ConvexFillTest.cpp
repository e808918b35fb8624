// fill_convex_poly against its oracle, the installed OpenCV's cv::fillConvexPoly (LINE_8, shift
// 4): random convex polygons of every kind the renderer can produce and then some, drawn by both
// on the same random background; every byte must be equal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "host_sim/sensors/ConvexFill.hpp"

namespace carril::sim {
namespace {

constexpr int kOne = 1 << kFillShift;  // one pixel in FixedPt units

// The kinds of polygon drawn; each a share of the random cases.
enum class Kind {
  Tiny,       // under 3 px across
  Speckle,    // a few to a few tens of px, as the floor texture
  Sliver,     // long and under a pixel wide
  Large,      // up to ten times the image
  Outside,    // near or well outside the image
  OnGrid,     // vertices on pixel centres and on the half-pixel rounding ties
  Hull,       // integer points' convex hull, a subset of its vertices
  Same,       // all vertices equal
  Collinear,  // all on one line, in order or not
  Extreme,  // out to the renderer's clamp (1e5 px): an int64 clip would overflow (4.6 uses double)
  Count
};

struct Gen {
  std::mt19937_64 rng;
  int w = 1, h = 1;

  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  int iuni(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }
  FixedPt fixed(double x, double y) {
    return {int(std::lround(x * kOne)), int(std::lround(y * kOne))};
  }

  // n points on an ellipse at sorted random angles (convex before rounding to 1/16 px) [px].
  void ellipse(std::vector<FixedPt>& out, int n, double cx, double cy, double rx, double ry) {
    std::vector<double> a(n);
    for (double& t : a) t = uni(0, 2 * M_PI);
    std::sort(a.begin(), a.end());
    const double rot = uni(0, M_PI), co = std::cos(rot), si = std::sin(rot);
    for (double t : a) {
      const double ex = rx * std::cos(t), ey = ry * std::sin(t);
      out.push_back(fixed(cx + co * ex - si * ey, cy + si * ex + co * ey));
    }
  }

  void hull(std::vector<FixedPt>& out, int n) {
    std::vector<FixedPt> p(iuni(3, 30));
    const int x0 = iuni(-4 * kOne, w * kOne), y0 = iuni(-4 * kOne, h * kOne);
    const int span = iuni(1, 40 * kOne);
    for (FixedPt& q : p) q = {x0 + iuni(0, span), y0 + iuni(0, span)};
    std::sort(p.begin(), p.end(),
              [](FixedPt a, FixedPt b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    auto cross = [](FixedPt o, FixedPt a, FixedPt b) {
      return std::int64_t(a.x - o.x) * (b.y - o.y) - std::int64_t(a.y - o.y) * (b.x - o.x);
    };
    std::vector<FixedPt> hl(2 * p.size());  // Andrew's monotone chain
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      while (k >= 2 && cross(hl[k - 2], hl[k - 1], p[i]) <= 0) --k;
      hl[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
      while (k >= t && cross(hl[k - 2], hl[k - 1], p[i]) <= 0) --k;
      hl[k++] = p[i];
    }
    hl.resize(k > 1 ? k - 1 : k);
    // An ordered subset of a convex polygon's vertices is convex.
    while (int(hl.size()) > n) hl.erase(hl.begin() + iuni(0, int(hl.size()) - 1));
    const int start = iuni(0, int(hl.size()) - 1);
    for (std::size_t i = 0; i < hl.size(); ++i) out.push_back(hl[(start + i) % hl.size()]);
  }

  void polygon(Kind kind, std::vector<FixedPt>& out) {
    out.clear();
    // 3 to 8 vertices; one polygon in 20 up to 50, as the renderer's discs (48 vertices, one
    // more after the near-plane cut).
    const int n = iuni(0, 19) == 0 ? iuni(9, 50) : iuni(3, 8);
    const double cx = uni(-4, w + 4), cy = uni(-4, h + 4);
    switch (kind) {
      case Kind::Tiny:
        ellipse(out, n, cx, cy, uni(0, 1.5), uni(0, 1.5));
        break;
      case Kind::Speckle:
        ellipse(out, n, cx, cy, uni(0.5, 20), uni(0.5, 20));
        break;
      case Kind::Sliver:
        ellipse(out, n, cx, cy, uni(2, 3.0 * (w + h)), uni(0, 0.6));
        break;
      case Kind::Large:
        ellipse(out, n, cx, cy, uni(1, 10.0 * (w + h)), uni(1, 10.0 * (w + h)));
        break;
      case Kind::Outside: {
        const double r = uni(0.2, 30), a = uni(0, 2 * M_PI), d = uni(0, 3 * r + 4);
        ellipse(out, n, w / 2.0 + std::cos(a) * (w / 2.0 + d),
                h / 2.0 + std::sin(a) * (h / 2.0 + d), r, uni(0.2, 30));
        break;
      }
      case Kind::OnGrid: {
        ellipse(out, n, cx, cy, uni(0, 12), uni(0, 12));
        const int q = iuni(0, 1) ? kOne : kOne / 2;  // pixel steps or half-pixel ties
        for (FixedPt& p : out) {
          p.x = int(std::lround(double(p.x) / q)) * q;
          p.y = int(std::lround(double(p.y) / q)) * q;
        }
        break;
      }
      case Kind::Hull:
        hull(out, n);
        break;
      case Kind::Same:
        out.assign(n, fixed(cx, cy));
        break;
      case Kind::Collinear: {
        const double a = uni(0, 2 * M_PI), len = uni(0, 2.0 * (w + h));
        std::vector<double> t(n);
        for (double& s : t) s = uni(-len, len);
        if (iuni(0, 1)) std::sort(t.begin(), t.end());
        for (double s : t) out.push_back(fixed(cx + s * std::cos(a), cy + s * std::sin(a)));
        if (iuni(0, 1)) {  // exactly collinear in FixedPt too: an axis-parallel or diagonal line
          const int dx = iuni(-1, 1), dy = iuni(-1, 1), x0 = out[0].x, y0 = out[0].y;
          for (FixedPt& p : out) {
            const int s = iuni(-40 * kOne, 40 * kOne);
            p = {x0 + dx * s, y0 + dy * s};
          }
        }
        break;
      }
      case Kind::Extreme: {
        const double big = 1e5;
        ellipse(out, n, uni(-big, big), uni(-big / 50, big / 50), uni(1, 2 * big), uni(1, 2 * big));
        for (FixedPt& p : out) {
          p.x = std::clamp(p.x, int(-big * kOne), int(big * kOne));
          p.y = std::clamp(p.y, int(-big * kOne), int(big * kOne));
        }
        break;
      }
      case Kind::Count:
        break;
    }
  }
};

std::string describe(int w, int h, const std::vector<FixedPt>& p) {
  std::string s = std::to_string(w) + "x" + std::to_string(h) + " image, polygon";
  for (const FixedPt& q : p) s += " (" + std::to_string(q.x) + "," + std::to_string(q.y) + ")";
  return s + " [1/16 px]";
}

// Draws `p` with both on copies of the same background; whether the two are still equal.
bool draw_both(std::vector<std::uint8_t>& mine, std::vector<std::uint8_t>& ref, int w, int h,
               const std::vector<FixedPt>& p, std::uint8_t b, std::uint8_t g, std::uint8_t r,
               std::vector<cv::Point>& cvp) {
  cvp.assign(p.size(), {});
  for (std::size_t i = 0; i < p.size(); ++i) cvp[i] = {p[i].x, p[i].y};
  cv::Mat img(h, w, CV_8UC3, ref.data());
  cv::fillConvexPoly(img, cvp.data(), int(cvp.size()), cv::Scalar(b, g, r), cv::LINE_8, kFillShift);
  fill_convex_poly(mine.data(), w, h, p.data(), int(p.size()), b, g, r);
  return mine == ref;
}

TEST(ConvexFillTest, EqualsOpenCvOnRandomPolygonsOnSmallImages) {
  Gen gen{std::mt19937_64(20261126)};
  std::vector<std::uint8_t> mine, ref;
  std::vector<FixedPt> poly;
  std::vector<cv::Point> cvp;
  int drawn[int(Kind::Count)] = {}, cases[int(Kind::Count)] = {};
  constexpr int kBlocks = 5000, kPerBlock = 60;
  for (int block = 0; block < kBlocks; ++block) {
    // A new image size and random background every block; within it polygons pile up.
    gen.w = gen.iuni(1, 72);
    gen.h = gen.iuni(1, 56);
    ref.resize(std::size_t(gen.w) * gen.h * 3);
    for (std::uint8_t& v : ref) v = std::uint8_t(gen.rng());
    mine = ref;
    for (int k = 0; k < kPerBlock; ++k) {
      // Extreme polygons cost OpenCV up to 1e5 scanlines above the image: keep them rare.
      const int kind =
          gen.iuni(0, 999) == 0 ? int(Kind::Extreme) : gen.iuni(0, int(Kind::Extreme) - 1);
      gen.polygon(Kind(kind), poly);
      const std::vector<std::uint8_t> before = ref;  // to tally the polygons that set a pixel
      const bool equal = draw_both(mine, ref, gen.w, gen.h, poly, std::uint8_t(gen.rng()),
                                   std::uint8_t(gen.rng()), std::uint8_t(gen.rng()), cvp);
      drawn[kind] += ref != before;
      ++cases[kind];
      ASSERT_TRUE(equal) << "kind " << kind << ", " << describe(gen.w, gen.h, poly);
    }
  }
  // Not vacuous: every kind that can set pixels did, often.
  for (int k = 0; k < int(Kind::Count); ++k) {
    EXPECT_GT(cases[k], 0) << "kind " << k;
    if (Kind(k) != Kind::Same && Kind(k) != Kind::Extreme)
      EXPECT_GT(drawn[k], cases[k] / 10) << "kind " << k;
  }
}

TEST(ConvexFillTest, EqualsOpenCvAtCameraSize) {
  Gen gen{std::mt19937_64(7)};
  gen.w = 640;
  gen.h = 480;
  std::vector<std::uint8_t> ref(std::size_t(gen.w) * gen.h * 3), mine;
  for (std::uint8_t& v : ref) v = std::uint8_t(gen.rng());
  mine = ref;
  std::vector<FixedPt> poly;
  std::vector<cv::Point> cvp;
  const Kind kinds[] = {Kind::Speckle, Kind::Sliver, Kind::Large, Kind::Outside, Kind::Hull};
  for (int k = 0; k < 1500; ++k) {
    const Kind kind = kinds[gen.iuni(0, 4)];
    gen.polygon(kind, poly);
    if (kind == Kind::Hull) {  // the hull's box is near the origin: spread it over the image
      const int dx = gen.iuni(0, 600 * kOne), dy = gen.iuni(0, 440 * kOne);
      for (FixedPt& p : poly) p = {p.x + dx, p.y + dy};
    }
    ASSERT_TRUE(draw_both(mine, ref, gen.w, gen.h, poly, std::uint8_t(gen.rng()),
                          std::uint8_t(gen.rng()), std::uint8_t(gen.rng()), cvp))
        << describe(gen.w, gen.h, poly);
  }
}

TEST(ConvexFillTest, EqualsOpenCvOnHandPickedEdgeCases) {
  const int w = 16, h = 12, o = kOne, half = kOne / 2;
  const std::vector<std::vector<FixedPt>> polys = {
      {{0, 0}, {0, 0}, {0, 0}},                                // one point at a corner
      {{-half, -half}, {-half, -half}, {-half, -half}},        // a point on the rounding tie
      {{-half - 1, 5 * o}, {-half - 1, 6 * o}, {-o, 5 * o}},   // just left of the image
      {{w * o - half, 0}, {w * o - half, h * o}, {w * o, 0}},  // on the right edge's tie
      {{0, 0}, {w * o, 0}, {w * o, h * o}, {0, h * o}},        // the whole image
      {{-1000 * o, -1000 * o}, {1000 * o, -1000 * o}, {0, 1000 * o}},  // far larger
      {{2 * o, 3 * o}, {9 * o, 3 * o}, {5 * o, 3 * o}},                // horizontal, collinear
      {{3 * o, 1 * o}, {3 * o, 10 * o}, {3 * o, 4 * o}},               // vertical, collinear
      {{1 * o + half, 1 * o + half}, {6 * o + half, 1 * o + half}, {6 * o + half, 4 * o + half}},
      {{-100000 * o, -100000 * o}, {100000 * o, -99999 * o}, {5 * o, 100000 * o}},
  };
  std::vector<std::uint8_t> ref(std::size_t(w) * h * 3), mine;
  std::vector<cv::Point> cvp;
  std::mt19937_64 rng(3);
  for (const auto& p : polys) {
    for (std::uint8_t& v : ref) v = std::uint8_t(rng());
    mine = ref;
    EXPECT_TRUE(draw_both(mine, ref, w, h, p, 10, 200, 30, cvp)) << describe(w, h, p);
  }
}

}  // namespace
}  // namespace carril::sim
