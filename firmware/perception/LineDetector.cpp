#include "firmware/perception/LineDetector.hpp"

#include "firmware/core/Param.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "firmware/core/Lanes.hpp"
#include "firmware/perception/BitRuns.hpp"
#include "firmware/perception/BlobLabeler.hpp"
#include "firmware/perception/BlobRefiner.hpp"
#include "firmware/perception/ColorClassifier.hpp"
#include "firmware/perception/FloorBox.hpp"

// The pipeline, against the thesis's OpenCV one (GaussianBlur 5x5, cvtColor HSV, inRange, erode
// x2, dilate x2, findContours, largest contour's moments and fitLine):
//  1. Decimate: each d x d block of the frame is averaged (the average is the blur) and its colour
//     looked up in a table built at construction that holds the HSV verdict for the tape and the
//     end-mark windows (ColorClassifier). Both masks come out of one pass, packed 64 cells a word.
//     Only the blocks near sampled blocks of either colour are classified, which gives the whole
//     frame's cleaned-up masks exactly (sparse classification, below).
//  2. Clean: one 3x3 erosion and one 3x3 dilation of the decimated masks (at d = 2 a cell is
//     2 px, so this is the full-resolution two-and-two; at d = 1 it is done twice, as OpenCV).
//  3. Label the 8-connected components by runs (BlobLabeler) and take the largest ones.
//  4. Rebuild each of those at full resolution (BlobRefiner): solid cells stay solid, the pixels
//     of the cells along its boundary are classified as the thesis's pipeline does (5x5 blur,
//     HSV, window) and the 5x5 opening is applied. Binary cells alone would put a sharp edge up
//     to a pixel off (a 2 px cell half covered by tape is all tape or all floor), and that bias
//     moves the centroid of a tapering blob by more than a pixel.
//  5. Per blob, from full-resolution moments of its area and of its outline pixels:
//     - area as cv::contourArea measures it: the contour polygon through the outline pixels'
//       centres encloses N - B/2 - 1 pixels' worth of area (Pick's theorem; N pixels, B of them
//       on the outline), which is what the minimum area is compared with;
//     - centroid of that polygon: the area moments with the outline pixels counted half;
//     - direction: the total-least-squares line through the outline pixels (cv::fitLine with
//       DIST_L2 on the contour), i.e. the principal axis of the outline pixels' covariance.

namespace carril::fw {

namespace {

constexpr int kMaxBlobs = 4;
constexpr double kRadToDeg = 180.0 / kPi;

int normalised_decimation(int d) {
  return d == 1 || d == 4 ? d : 2;
}

// Classification. Per row of blocks: the block sums of each channel, quantised to 6 bits, for
// every byte position of a span (straight loops over the interleaved row, which the compiler
// vectorises), then one table lookup per block into a row of verdict bytes, packed 64 cells a
// word into the two masks.
//
// Sparse classification (the default): the cleanup that follows is an opening, which keeps only
// the union of the k x k squares of cells that are all set (k = 3; 5 at d = 1, where it is done
// twice; at the image's edges the squares are clipped, since erosion counts outside as set).
// Every such square, clipped or not, holds a sampled block: one of every kSampleEvery-th block of
// every kSampleEvery-th row, with the last row and column sampled too. So only the sampled blocks
// are classified first, and then only the cells within k - 1 of a sampled block that shows either
// colour; cells never classified count as clear. Every square the opening keeps lies whole in
// such a neighbourhood, so it is found all set, and no square can be found all set that is not:
// the cleaned-up masks are exactly those of the whole frame, at a fraction of the cost (a frame
// with no tape costs its samples; a tape costs a band a few cells wider than itself).
constexpr int kSampleEvery = 3;

// The next sampled row or column after `i` of `n` (every kSampleEvery-th, then the last).
int next_sample(int i, int n) {
  if (i + kSampleEvery < n) return i + kSampleEvery;
  return i == n - 1 ? n : n - 1;
}

// The table index of block (x, by): its average colour quantised to 6 bits a channel.
template <int D>
std::uint32_t block_index(const std::uint8_t* img, int row_bytes, int x, int by) {
  constexpr int kShift = D == 1 ? 2 : (D == 2 ? 4 : 6);
  unsigned sum[3] = {0, 0, 0};
  for (int j = 0; j < D; ++j) {
    const std::uint8_t* p =
        img + (std::size_t(by) * D + std::size_t(j)) * std::size_t(row_bytes) + 3 * D * x;
    for (int i = 0; i < D; ++i) {
      for (int c = 0; c < 3; ++c) sum[c] += p[3 * i + c];
    }
  }
  return color_lut::index(sum[0] >> kShift, sum[1] >> kShift, sum[2] >> kShift);
}

// The table verdict of block (x, by): bit 0 tape colour, bit 1 end-mark colour.
template <int D>
std::uint8_t block_verdict(const std::uint8_t* img, int row_bytes, const std::uint8_t* lut, int x,
                           int by) {
  return lut[block_index<D>(img, row_bytes, x, by)];
}

// block_verdict at d = 2 with the four pixels' sums in 16-bit lanes: the two rows' first eight
// bytes each (b g r b g r . .), then lanes 0-2 plus lanes 3-5. The same sums, so the same verdict,
// in about half the instructions. `p` is the block's first byte; its eight bytes must lie inside
// the row (the caller takes block_verdict for a last column that would run past it).
std::uint8_t block_verdict_lanes(const std::uint8_t* p, int row_bytes, const std::uint8_t* lut) {
  const lanes::U16x8 s = lanes::widen8(p) + lanes::widen8(p + row_bytes);
  const lanes::U16x8 t =
      (s + __builtin_shufflevector(s, lanes::U16x8{}, 3, 4, 5, 6, 7, 8, 8, 8)) >> 4;
  return lut[color_lut::index(t[0], t[1], t[2])];
}

// At d = 2, eight sampled blocks in a row (every kSampleEvery-th) span FloorBox::kRunBytes bytes.
constexpr int kRunSamples = 8;
static_assert(kRunSamples * kSampleEvery * 6 == FloorBox::kRunBytes, "a run of eight samples");

// Verdicts of block columns c0..c1 of block row `by` into verdict[c0..c1].
template <int D>
void classify_span(const std::uint8_t* img, int width, const std::uint8_t* lut, std::uint16_t* vsum,
                   std::uint8_t* q, std::uint8_t* verdict, int by, int c0, int c1) {
  constexpr int kShift = D == 1 ? 2 : (D == 2 ? 4 : 6);  // block sum to 6 bits
  const int row_bytes = width * 3;
  const int n = row_bytes - 3 * (D - 1);  // positions whose block lies inside the row
  const int i0 = 3 * D * c0, i1 = 3 * D * (c1 + 1) < n ? 3 * D * (c1 + 1) : n;
  const std::uint8_t* p = img + std::size_t(by) * D * std::size_t(row_bytes);
  if constexpr (D == 2) {
    const std::uint8_t* p1 = p + row_bytes;
    for (int i = i0; i < i1; ++i) {
      q[i] = static_cast<std::uint8_t>((p[i] + p1[i] + p[i + 3] + p1[i + 3]) >> kShift);
    }
  } else {
    const int vs1 = i1 + 3 * (D - 1);  // <= row_bytes
    for (int i = i0; i < vs1; ++i) {
      unsigned sum = 0;
      for (int j = 0; j < D; ++j) sum += p[std::size_t(j) * std::size_t(row_bytes) + i];
      vsum[i] = static_cast<std::uint16_t>(sum);
    }
    for (int i = i0; i < i1; ++i) {
      unsigned sum = 0;
      for (int m = 0; m < D; ++m) sum += vsum[i + 3 * m];
      q[i] = static_cast<std::uint8_t>(sum >> kShift);
    }
  }
  for (int x = c0; x <= c1; ++x) {
    const std::uint8_t* c3 = q + 3 * D * x;
    verdict[x] = lut[color_lut::index(c3[0], c3[1], c3[2])];
  }
}

// Packs verdict bytes 64k..64k+63 into word k of the two mask rows and clears them: bit 0 of
// eight bytes at a time with a multiply (bit 0 of byte i lands in bit 56 + i).
void pack_word(std::uint8_t* verdict, int k, std::uint64_t* line_row, std::uint64_t* end_row) {
  constexpr std::uint64_t kLow = 0x0101010101010101ULL, kPack = 0x0102040810204080ULL;
  std::uint64_t lw = 0, ew = 0;
  static_assert(std::endian::native == std::endian::little, "byte i of a word is bits 8i..8i+7");
  std::uint8_t* v = verdict + 64 * k;
  for (int g = 0; g < 8; ++g) {
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, v + 8 * g, sizeof bytes);  // one load, not eight
    lw |= (((bytes & kLow) * kPack) >> 56) << (8 * g);
    ew |= ((((bytes >> 1) & kLow) * kPack) >> 56) << (8 * g);
  }
  std::memset(v, 0, 64);
  line_row[k] = lw;
  end_row[k] = ew;
}

struct SampleRuns {
  long tested = 0, outside = 0;
};

// Every block of the frame (the reference the sparse pass must equal). Returns blocks classified.
template <int D>
long classify_whole(const std::uint8_t* img, int width, const std::uint8_t* lut,
                    std::uint16_t* vsum, std::uint8_t* q, std::uint8_t* verdict,
                    const BitImage& line, const BitImage& end) {
  for (int by = 0; by < line.height; ++by) {
    classify_span<D>(img, width, lut, vsum, q, verdict, by, 0, line.width - 1);
    for (int k = 0; k < line.stride; ++k) pack_word(verdict, k, line.row(by), end.row(by));
  }
  return long(line.width) * line.height;
}

// The sparse pass (see above): `need` (same shape as the masks) is scratch. `reach` is k - 1.
// Returns blocks classified, the samples included.
// `box`: at d = 2, the floor box (or null); `runs` counts the runs of eight samples tested
// against it and those that were not inside.
template <int D>
long classify_sparse(const std::uint8_t* img, int width, const std::uint8_t* lut,
                     std::uint16_t* vsum, std::uint8_t* q, std::uint8_t* verdict,
                     const BitImage& line, const BitImage& end, const BitImage& need, int reach,
                     const FloorBox* box, SampleRuns& runs) {
  const int w = line.width, h = line.height, row_bytes = width * 3;
  const std::size_t words = std::size_t(line.stride) * std::size_t(h);
  for (std::size_t i = 0; i < words; ++i) {
    need.bits[i] = 0;
    line.bits[i] = 0;
    end.bits[i] = 0;
  }
  long blocks = 0;
  for (int by = 0; by < h; by = next_sample(by, h)) {
    const int y0 = by - reach > 0 ? by - reach : 0, y1 = by + reach < h - 1 ? by + reach : h - 1;
    const auto mark = [&](int x) {
      const int a = x - reach > 0 ? x - reach : 0, b = x + reach < w - 1 ? x + reach : w - 1;
      for (int y = y0; y <= y1; ++y) bits::set_range(need.row(y), a, b);
    };
    // The columns next_sample() gives: every kSampleEvery-th below the last, then the last. At
    // d = 2, the lanes up to the last block whose eight bytes fit in the row.
    int x = 0;
    if constexpr (D == 2) {
      const std::uint8_t* row = img + std::size_t(by) * 2 * std::size_t(row_bytes);
      const int x_lanes = (row_bytes - 8) / 6;  // 6x + 8 <= row_bytes
      constexpr int kRunBlocks = kRunSamples * kSampleEvery;
      // Runs of eight samples on the floor box first, each sample of a run outside it on its own.
      for (; box != nullptr && x + kRunBlocks - kSampleEvery < w - 1 &&
             6 * x + FloorBox::kRunBytes <= row_bytes;
           x += kRunBlocks) {
        ++runs.tested;
        if (box->holds_run(row + 6 * x, row_bytes)) continue;
        ++runs.outside;
        for (int j = 0; j < kRunBlocks; j += kSampleEvery) {
          if (block_verdict_lanes(row + 6 * (x + j), row_bytes, lut) != 0) mark(x + j);
        }
      }
      for (; x < w - 1 && x <= x_lanes; x += kSampleEvery) {
        if (block_verdict_lanes(row + 6 * x, row_bytes, lut) != 0) mark(x);
      }
    }
    for (; x < w - 1; x += kSampleEvery) {
      if (block_verdict<D>(img, row_bytes, lut, x, by) != 0) mark(x);
    }
    if (block_verdict<D>(img, row_bytes, lut, w - 1, by) != 0) mark(w - 1);
    blocks += (w - 2 + kSampleEvery) / kSampleEvery + 1;
  }
  for (int by = 0; by < h; ++by) {
    const std::uint64_t* nr = need.row(by);
    for (int k = 0; k < line.stride; ++k) {
      std::uint64_t bits_left = nr[k];
      if (bits_left == 0) continue;
      // Each run of needed cells within the word.
      while (bits_left != 0) {
        const int lo = std::countr_zero(bits_left);
        const int len = std::countr_one(bits_left >> lo);
        classify_span<D>(img, width, lut, vsum, q, verdict, by, 64 * k + lo, 64 * k + lo + len - 1);
        blocks += len;
        bits_left = len + lo >= 64 ? 0 : bits_left & (bits::kAll << (lo + len));
      }
      pack_word(verdict, k, line.row(by), end.row(by));
    }
  }
  return blocks;
}

// The floor box (FloorBox.hpp) at d = 2: grown from the floor's colour, taken as the most common
// table index among the clear blocks of a grid over the frame, and grown again when most runs of
// samples fall outside it, at most once every kBoxRetry frames: growing reads at most
// kBoxWidth^3 + 6 kBoxWidth^2 table cells (14 to 27 us on average on the host, over 2,197 seeds
// for each of four colour pairs).
constexpr int kBoxWidth = 32;  // [6-bit levels] at most half of each channel's range
constexpr int kBoxRetry = 30;  // [frames]

std::uint32_t floor_seed(const std::uint8_t* img, int width, int height, const std::uint8_t* lut,
                         bool& found) {
  constexpr int kGx = 8, kGy = 6;
  const int bw = width / 2, bh = height / 2;
  std::uint32_t idx[kGx * kGy];
  int n = 0;
  for (int j = 0; j < kGy; ++j) {
    for (int i = 0; i < kGx; ++i) {
      const std::uint32_t k = block_index<2>(img, width * 3, (2 * i + 1) * bw / (2 * kGx),
                                             (2 * j + 1) * bh / (2 * kGy));
      if (lut[k] == 0) idx[n++] = k;
    }
  }
  int best = -1, best_count = 0;
  for (int a = 0; a < n; ++a) {
    int count = 0;
    for (int b = 0; b < n; ++b) count += idx[b] == idx[a];
    if (count > best_count) {
      best = a;
      best_count = count;
    }
  }
  found = best >= 0;
  return found ? idx[best] : 0;
}

}  // namespace

struct LineDetector::Buffers {
  Buffers(int width, int height, int cells_w, int cells_h, int d)
      : stride(bit_stride(cells_w)),
        words(std::make_unique<std::uint64_t[]>(std::size_t(3) * stride * cells_h)),
        lut(std::make_unique<std::uint8_t[]>(color_lut::kSize)),
        vsum(std::make_unique<std::uint16_t[]>(std::size_t(width) * 3)),
        q(std::make_unique<std::uint8_t[]>(std::size_t(width) * 3)),
        m(std::make_unique<std::uint8_t[]>(std::size_t(stride) * 64)),
        labeler(cells_h, max_runs(cells_w, cells_h)),
        refiner(width, height, d) {
    BitImage* images[] = {&line, &end, &tmp};
    for (int i = 0; i < 3; ++i) {
      *images[i] = {words.get() + std::size_t(i) * stride * cells_h, cells_w, cells_h, stride};
    }
  }
  // Room for a run in every eighth cell: a tape frame has one or two runs a row; a frame that
  // needs more is speckle or a patterned floor and is reported as saturated.
  static int max_runs(int w, int h) { return w * h / 8 > 1024 ? w * h / 8 : 1024; }

  int stride;
  std::unique_ptr<std::uint64_t[]> words;
  std::unique_ptr<std::uint8_t[]> lut;
  std::unique_ptr<std::uint16_t[]> vsum;  // one row of vertical block sums
  std::unique_ptr<std::uint8_t[]> q;      // one row of quantised block sums
  std::unique_ptr<std::uint8_t[]> m;      // one row of table verdicts, whole words, zero padded
  BitImage line, end, tmp;
  RunLabeler labeler;
  BlobRefiner refiner;
  FloorBox box;
  SampleRuns runs;
  bool box_in_use = false;  // the box is valid and most runs lay inside it last frame
  int box_age = kBoxRetry;  // frames since the box was last grown
};

LineDetector::LineDetector(const CameraModel& camera, const LineDetectorConfig& config)
    : cam_(camera), cfg_(config) {
  const int w = camera.mount().width, h = camera.mount().height;
  cfg_.decimation = normalised_decimation(config.decimation);
  const double scale = double(w) * h / (640.0 * 480.0);
  if (cfg_.min_end_area_px <= 0) cfg_.min_end_area_px = 1500.0 * scale;
  ref_area_px_ = cfg_.min_area_px > 0 ? cfg_.min_area_px : 6000.0 * scale;
  if (cfg_.min_area_px > 0) {
    min_blob_px_ = cfg_.min_area_px;
  } else {
    // The floor rule. Its smallest pixel area is where a pixel covers the most floor (the far
    // corners of the view): a 9 x 9 grid of the image's pixels bounds it for the labeler's
    // candidates, each blob is then measured where it lies.
    min_floor_m2_ = cfg_.tape_width_m * cfg_.min_piece_m;
    double most = 0.0;
    for (int i = 0; i <= 8; ++i) {
      for (int j = 0; j <= 8; ++j) {
        const Vec2 px(0.5 + (w - 1.0) * i / 8.0, 0.5 + (h - 1.0) * j / 8.0);
        most = std::fmax(most, pixel_floor_area_m2(px));
      }
    }
    min_blob_px_ = most > 0.0 ? std::fmax(1.0, min_floor_m2_ / (1.25 * most)) : 1.0;
    min_blob_px_ = std::fmin(min_blob_px_, ref_area_px_);  // tape on its own always counts
  }
  const int d = cfg_.decimation;
  buf_ = std::make_unique<Buffers>(w, h, w / d > 0 ? w / d : 1, h / d > 0 ? h / d : 1, d);
  color_lut::build(cfg_.line, cfg_.end, buf_->lut.get());
}

LineDetector::~LineDetector() = default;

double LineDetector::pixel_floor_area_m2(const Vec2& px) const {
  // The pixel's four corners on the floor, and the quadrilateral's area (shoelace).
  const double du[4] = {-0.5, 0.5, 0.5, -0.5}, dv[4] = {-0.5, -0.5, 0.5, 0.5};
  Vec2 q[4];
  for (int k = 0; k < 4; ++k) {
    if (!cam_.pixel_to_floor(px + Vec2(du[k], dv[k]), q[k])) return 0.0;
  }
  double a2 = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Vec2& p0 = q[k];
    const Vec2& p1 = q[(k + 1) % 4];
    a2 += p0.x() * p1.y() - p1.x() * p0.y();
  }
  return 0.5 * std::fabs(a2);
}

namespace {

// Blob statistics from its full-resolution moments (see the pipeline notes at the top).
Blob make_blob(const BlobSums& s, int width, int height) {
  Blob b;
  const double n = double(s.n), bn = double(s.bn);
  b.area_px = n - 0.5 * bn - 1.0 > 0.0 ? n - 0.5 * bn - 1.0 : 0.0;
  const double a = n - 0.5 * bn;  // > 0: at most every pixel is an outline pixel
  b.centroid_px =
      Vec2((double(s.su) - 0.5 * double(s.bsu)) / a, (double(s.sv) - 0.5 * double(s.bsv)) / a);
  // Outline covariance (times bn^2), exact in integers before the conversion.
  const double cuu = double(s.bn * s.bsuu - s.bsu * s.bsu);
  const double cvv = double(s.bn * s.bsvv - s.bsv * s.bsv);
  const double cuv = double(s.bn * s.bsuv - s.bsu * s.bsv);
  const double theta = 0.5 * std::atan2(2.0 * cuv, cuu - cvv);
  Vec2 axis(std::cos(theta), std::sin(theta));
  if (axis.y() > 0.0 || (axis.y() == 0.0 && axis.x() < 0.0)) axis = -axis;
  b.axis_px = axis;
  b.angle_deg = std::atan2(axis.y(), axis.x()) * kRadToDeg;
  // Area covariance with each pixel a unit square (+1/12 on the diagonal): never singular.
  const double n2 = n * n;
  const double auu = double(s.n * s.suu - s.su * s.su) / n2 + 1.0 / 12.0;
  const double avv = double(s.n * s.svv - s.sv * s.sv) / n2 + 1.0 / 12.0;
  const double auv = double(s.n * s.suv - s.su * s.sv) / n2;
  const double mid = 0.5 * (auu + avv);
  const double rad = std::sqrt(0.25 * (auu - avv) * (auu - avv) + auv * auv);
  const double minor = mid - rad > 1.0 / 12.0 ? mid - rad : 1.0 / 12.0;
  b.elongation = std::sqrt((mid + rad) / minor);
  b.u_min = s.u_min;
  b.u_max = s.u_max;
  b.v_min = s.v_min;
  b.v_max = s.v_max;
  b.touches_edge = s.u_min == 0 || s.v_min == 0 || s.u_max == width - 1 || s.v_max == height - 1;
  for (int i = 0; i < s.bands; ++i) {
    if (s.band_n[i] == 0) continue;
    const double bnd = double(s.band_n[i]);
    b.centerline_px.push_back(Vec2(double(s.band_su[i]) / bnd, double(s.band_sv[i]) / bnd));
  }
  return b;
}

// Labels `mask` and fills `blobs` with up to `max_out` blobs of at least `min_area`, largest
// first. False when the mask saturated the run storage.
// With `floor_of` (the floor rule), a blob counts when its area times the floor area of a pixel
// at its centroid is at least min_floor_m2, or it is at least sure_area (tape on its own: near
// the robot, where a pixel covers little floor, the floor rule would be stricter than the
// thesis's); min_area then only bounds the candidates.
template <typename FloorArea>
bool find_blobs(RunLabeler& lab, BlobRefiner& refiner, const hal::CameraFrame& frame,
                const BitImage& mask, const ColorThreshold& t, int d, double min_area, int max_out,
                StaticVector<Blob, kMaxBlobs>& blobs, const FloorArea& floor_of,
                double min_floor_m2, double sure_area) {
  blobs.clear();
  if (!lab.label(mask)) return false;
  constexpr int kCandidates = 6;
  int ids[kCandidates], cells[kCandidates];
  // Candidates by cell count, with slack: the full-resolution area can exceed the cells' by the
  // boundary cells' partial pixels.
  const int min_cells = int(0.8 * min_area / (d * d));
  const int n = lab.largest(min_cells > 1 ? min_cells : 1, kCandidates, ids, cells);
  for (int i = 0; i < n; ++i) {
    BlobSums sums;
    refiner.measure(frame.bgr.data(), t, lab, mask, ids[i], sums);
    if (sums.n == 0) continue;
    const Blob b = make_blob(sums, frame.width, frame.height);
    if (b.area_px < min_area) continue;
    if (min_floor_m2 > 0.0 && b.area_px < sure_area &&
        b.area_px * floor_of(b.centroid_px) < min_floor_m2) {
      continue;
    }
    if (blobs.full() && b.area_px <= blobs.back().area_px) continue;
    if (blobs.full()) blobs.pop_back();
    blobs.push_back(b);
    for (std::size_t j = blobs.size() - 1; j > 0 && blobs[j - 1].area_px < blobs[j].area_px; --j) {
      const Blob tmp = blobs[j];
      blobs[j] = blobs[j - 1];
      blobs[j - 1] = tmp;
    }
    if (int(blobs.size()) > max_out) blobs.pop_back();
  }
  return true;
}

}  // namespace

bool LineDetector::detect(const hal::CameraFrame& frame, LineDetection& out) {
  const int w = cam_.mount().width, h = cam_.mount().height;
  if (frame.width != w || frame.height != h) return false;
  // A camera outside what the HAL's frame can hold (or too small to decimate) is never served.
  if (w > hal::kMaxImageWidth || h > hal::kMaxImageHeight || w < 16 || h < 16) return false;
  const int d = cfg_.decimation;
  Buffers& bf = *buf_;
  const std::uint8_t* img = frame.bgr.data();
  // Noise cleanup: an opening of about 5 x 5 px, as the thesis's two erosions and two dilations.
  const int rounds = d == 1 ? 2 : 1;
  const int reach = 2 * rounds;  // a kept square's cells lie within this of a sampled block
  // One call for each decimation, the sparse pass or (the reference) every block.
  const auto classify = [&](auto decimation) {
    constexpr int D = decltype(decimation)::value;
    return cfg_.sparse ? classify_sparse<D>(img, w, bf.lut.get(), bf.vsum.get(), bf.q.get(),
                                            bf.m.get(), bf.line, bf.end, bf.tmp, reach,
                                            bf.box_in_use ? &bf.box : nullptr, bf.runs)
                       : classify_whole<D>(img, w, bf.lut.get(), bf.vsum.get(), bf.q.get(),
                                           bf.m.get(), bf.line, bf.end);
  };
  const long blocks = d == 2   ? classify(std::integral_constant<int, 2>{})
                      : d == 4 ? classify(std::integral_constant<int, 4>{})
                               : classify(std::integral_constant<int, 1>{});
  classified_blocks_ += std::uint64_t(blocks);
  if (cfg_.sparse && d == 2) {
    // Grown when there is none yet, or when most runs fell outside it (the floor changed).
    box_runs_tested_ += std::uint64_t(bf.runs.tested);
    box_runs_inside_ += std::uint64_t(bf.runs.tested - bf.runs.outside);
    // A box most runs fall outside of (a noisy image, a floor of another colour) only costs its
    // tests: it is set aside until the next try.
    ++bf.box_age;
    if (2 * bf.runs.outside > bf.runs.tested) bf.box_in_use = false;
    if (!bf.box_in_use && bf.box_age >= kBoxRetry) {
      bool found = false;
      const std::uint32_t seed = floor_seed(img, w, h, bf.lut.get(), found);
      bf.box = found ? FloorBox::grow(bf.lut.get(), seed, kBoxWidth) : FloorBox{};
      bf.box_in_use = bf.box.valid();
      bf.box_age = 0;
      ++floor_boxes_;
    }
    bf.runs = SampleRuns{};
  }
  for (const BitImage* m : {&bf.line, &bf.end}) {
    for (int i = 0; i < rounds; ++i) erode3x3(*m, *m, bf.tmp);
    for (int i = 0; i < rounds; ++i) dilate3x3(*m, *m, bf.tmp);
  }

  out = LineDetection{};
  out.stamp_ns = frame.stamp_ns;
  out.seq = frame.seq;
  const auto floor_of = [this](const Vec2& px) { return pixel_floor_area_m2(px); };
  const bool line_ok =
      find_blobs(bf.labeler, bf.refiner, frame, bf.line, cfg_.line, d, min_blob_px_, kMaxBlobs,
                 out.blobs, floor_of, min_floor_m2_, ref_area_px_);
  out.detected = line_ok && !out.blobs.empty();
  out.sure = out.detected && out.blobs[0].area_px >= ref_area_px_;
  if (out.detected) {
    const Blob& b = out.blobs[0];
    for (const Vec2& p : b.centerline_px) {
      Vec2 f;
      if (cam_.pixel_to_floor(p, f)) out.centerline_floor.push_back(f);
    }
    if (!out.centerline_floor.empty()) {
      out.near_floor = out.centerline_floor[0];
      out.far_floor = out.centerline_floor.back();
    }
    // Direction on the floor: map two points a few tens of pixels either side of the centroid
    // along the image axis (fewer when the far one would leave the floor).
    bool mapped = cam_.pixel_to_floor(b.centroid_px, out.centroid_floor);
    bool angle_ok = false;
    for (double k = 0.0625 * w; mapped && !angle_ok && k >= 1.0; k *= 0.5) {
      Vec2 near, far;
      angle_ok = cam_.pixel_to_floor(b.centroid_px - k * b.axis_px, near) &&
                 cam_.pixel_to_floor(b.centroid_px + k * b.axis_px, far);
      if (angle_ok) out.angle_floor_rad = std::atan2(far.y() - near.y(), far.x() - near.x());
    }
    // Confidence, the product of three terms in 0..1:
    //  - size: area / (2 x the thesis's minimum area, 6000 px at 640x480), capped at 1 (a strip
    //    through the whole image is about that; a short piece or one at the edge a fraction);
    //  - shape: 0.5 + 0.5 x min(1, (elongation - 1) / 3): a strip (elongation >= 4) scores 1, a
    //    round blob 0.5, since a tape seen end-on or at a corner can be compact;
    //  - agreement: 1 - 0.5 x (second blob's area / largest's): a fork or a second segment of
    //    comparable size makes the choice of the largest uncertain.
    // 0 when the centroid does not map onto the floor, and 0 (not detected) for a saturated mask.
    const double size = b.area_px / (2.0 * ref_area_px_);
    const double shape = 0.5 + 0.5 * std::fmin(1.0, (b.elongation - 1.0) / 3.0);
    const double second = out.blobs.size() > 1 ? out.blobs[1].area_px / b.area_px : 0.0;
    const double c = std::fmin(1.0, size) * shape * (1.0 - 0.5 * second);
    out.confidence = mapped && angle_ok ? float(c) : 0.0F;
  }

  StaticVector<Blob, kMaxBlobs> ends;
  if (find_blobs(bf.labeler, bf.refiner, frame, bf.end, cfg_.end, d, cfg_.min_end_area_px, 1, ends,
                 floor_of, 0.0, 0.0) &&
      !ends.empty()) {
    out.end_blob = ends[0];
    out.end_detected = cam_.pixel_to_floor(out.end_blob.centroid_px, out.end_floor);
  }
  return true;
}

}  // namespace carril::fw

namespace carril::fw {

namespace {
void check_threshold(Checks& c, const char* which, const ColorThreshold& t) {
  c.fail_if(t.h_hi > 179, which, "hue above 179 (OpenCV's 0..179 hue)")
      .fail_if(t.h_lo > 179, which, "hue above 179 (OpenCV's 0..179 hue)")
      .fail_if(t.s_lo > t.s_hi || t.v_lo > t.v_hi, which,
               "a saturation or value lower bound above its upper bound (only hue wraps)");
}
}  // namespace

std::span<const Param<LineDetectorConfig>> LineDetectorConfig::params() {
  using C = LineDetectorConfig;
  static constexpr Param<C> kParams[] = {
      CARRIL_PARAM(C, decimation, "px", 1, 4,
                   "1, 2 or 4: the detector works on n x n pixel blocks"),
      CARRIL_PARAM(C, tape_width_m, "m", 0.005, 0.5, "the tape's width"),
      CARRIL_PARAM(C, min_piece_m, "m", 0.01, 2.0,
                   "a tape blob counts when its pixel area times the floor area of a pixel where "
                   "it lies (through the camera model) covers `tape_width_m` x `min_piece_m`: the "
                   "same piece counts near the robot and at the far edge of the view (a blob of "
                   "6000 px scaled, tape on its own, counts wherever it lies)"),
      CARRIL_PARAM(
          C, min_area_px, "px", 0.0, 1e7,
          "> 0: a fixed smallest tape blob in pixels instead of the floor rule (the thesis used "
          "6000 at 640x480), and every blob kept is tape on its own; 0: a blob of at least 6000 px "
          "scaled by the image area over 640x480 is tape on its own, a smaller one (worn tape "
          "between gaps, or a speck) is a piece, taken for tape only where it continues the "
          "remembered tape (on its path or its continuation up to 0.6 m past its end, running the "
          "same way; `tape_pieces_taken` and `tape_pieces_refused` in the mission's counters)"),
      CARRIL_PARAM(C, min_end_area_px, "px", 0.0, 1e7,
                   "smallest end mark; 0: 1500 scaled the same way"),
  };
  return kParams;
}

Status LineDetectorConfig::validate() const {
  Checks c("detector");
  c.params(*this, params());
  check_threshold(c, "line", line);
  check_threshold(c, "end", end);
  return c
      .fail_if(decimation != 1 && decimation != 2 && decimation != 4, "decimation",
               "expected 1, 2 or 4")
      .result();
}

}  // namespace carril::fw
