#include "firmware/perception/BlobRefiner.hpp"

#include <bit>
#include <cstring>

#include "firmware/core/Check.hpp"
#include "firmware/core/Lanes.hpp"
#include "firmware/perception/BitRuns.hpp"
#include "firmware/perception/ColorClassifier.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

namespace {

using bits::kAll;
using bits::set_range;
using bits::valid_bits;
constexpr int kMaxWords = (hal::kMaxImageWidth + 63) / 64;

// 5x5 erosion or dilation of rows v0..v1, words k0..k1 of a full-width mask: the thesis's two
// 3x3 passes in one. Rows and columns outside the image count as `fill` (set for erosion, as
// cv::erode); rows and words outside the window inside the image are clear (nothing of the blob
// is there). The same as two 3x3 passes with those borders: a pixel two away inside the image is
// reached through one between them, also inside, and the first pass leaves nothing outside the
// window (a clear pixel erodes to clear; the window's margin holds what dilation grows into).
template <bool kErode>
void morph5_window(std::uint64_t* m, std::uint64_t* tmp, int s, int width, int height, int v0,
                   int v1, int k0, int k1) {
  const std::uint64_t fill = kErode ? kAll : 0, last = valid_bits(width, s - 1);
  const std::uint64_t pad = fill & ~last;  // bits past the image's right edge
  const std::uint64_t left_out = k0 == 0 ? fill : 0, right_out = k1 == s - 1 ? fill : 0;
  for (int v = v0; v <= v1; ++v) {
    const std::uint64_t* r = m + std::ptrdiff_t(v) * s;
    std::uint64_t* h = tmp + std::ptrdiff_t(v) * s;
    std::uint64_t prev = left_out, cur = r[k0] | (k0 == s - 1 ? pad : 0);
    for (int k = k0; k <= k1; ++k) {
      const std::uint64_t next = k < k1 ? (r[k + 1] | (k + 1 == s - 1 ? pad : 0)) : right_out;
      const std::uint64_t l1 = (cur << 1) | (prev >> 63), l2 = (cur << 2) | (prev >> 62);
      const std::uint64_t r1 = (cur >> 1) | (next << 63), r2 = (cur >> 2) | (next << 62);
      h[k] = kErode ? (cur & l1 & l2 & r1 & r2) : (cur | l1 | l2 | r1 | r2);
      prev = cur;
      cur = next;
    }
  }
  for (int v = v0; v <= v1; ++v) {
    // Rows v - 2 .. v + 2: inside the window, their pass; outside the image, fill; else clear.
    const std::uint64_t* rows[5];
    std::uint64_t outside[5];
    for (int j = 0; j < 5; ++j) {
      const int vv = v + j - 2;
      rows[j] = vv >= v0 && vv <= v1 ? tmp + std::ptrdiff_t(vv) * s : nullptr;
      outside[j] = vv < 0 || vv >= height ? fill : 0;
    }
    std::uint64_t* out = m + std::ptrdiff_t(v) * s;
    for (int k = k0; k <= k1; ++k) {
      std::uint64_t r = rows[2][k];
      for (int j : {0, 1, 3, 4}) {
        const std::uint64_t x = rows[j] ? rows[j][k] : outside[j];
        r = kErode ? (r & x) : (r | x);
      }
      out[k] = k + 1 < s ? r : (r & last);
    }
  }
}

using U64x2 = std::uint64_t __attribute__((vector_size(16)));

// In each lane, each of the 32 low bits doubled: bit i to bits 2i and 2i + 1.
U64x2 spread2(U64x2 v) {
  v &= 0xFFFFFFFFULL;
  v = (v | (v << 16)) & 0x0000FFFF0000FFFFULL;
  v = (v | (v << 8)) & 0x00FF00FF00FF00FFULL;
  v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0FULL;
  v = (v | (v << 2)) & 0x3333333333333333ULL;
  v = (v | (v << 1)) & 0x5555555555555555ULL;
  return v | (v << 1);
}

// Words k0..k1 of two rows of pixels (pa, pb) from two rows of cells (a, b; cs words each): each
// cell is 2^log2_d pixels wide (1, 2 or 4). The two rows go through the bit spreading together,
// one per lane.
void upsample(const std::uint64_t* a, const std::uint64_t* b, int cs, std::uint64_t* pa,
              std::uint64_t* pb, int k0, int k1, int log2_d) {
  for (int k = k0; k <= k1; ++k) {
    const int ck = k >> log2_d;
    const U64x2 w = ck < cs ? U64x2{a[ck], b[ck]} : U64x2{0, 0};
    U64x2 p;
    if (log2_d == 0) {
      p = w;
    } else if (log2_d == 1) {
      p = spread2(w >> (32 * (k & 1)));
    } else {
      p = spread2(spread2((w >> (16 * (k & 3))) & 0xFFFF));
    }
    pa[k] = p[0];
    pb[k] = p[1];
  }
}

int reflect101(int i, int n) {
  return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i);
}

// cv::GaussianBlur with ksize 5 and sigma 0 is the binomial kernel [1 4 6 4 1]^2 / 256,
// computed exactly and rounded half up (OpenCV's fixed-point path); borders reflected (101).
constexpr int kTaps[5] = {1, 4, 6, 4, 1};

// The threshold test on a blurred colour: cv::cvtColor to HSV and cv::inRange, with the cheap
// tests first (V, then S; the hue only when the window limits it).
bool blurred_in(const ColorThreshold& t, int b, int g, int r) {
  const int v = b > g ? (b > r ? b : r) : (g > r ? g : r);
  if (v < t.v_lo || v > t.v_hi) return false;  // most floor pixels stop here
  const int vmin = b < g ? (b < r ? b : r) : (g < r ? g : r);
  const int diff = v - vmin;
  using namespace hsv_detail;
  const int sat = (diff * kTables.sdiv[v] + (1 << (kShift - 1))) >> kShift;
  if (sat < t.s_lo || sat > t.s_hi) return false;
  if (t.h_lo == 0 && t.h_hi >= 179) return true;
  return in_threshold(t, bgr_to_hsv8(b, g, r));
}

// One pixel anywhere, borders reflected.
bool pixel_in(const std::uint8_t* img, int w, int h, int u, int v, const ColorThreshold& t) {
  int sb = 0, sg = 0, sr = 0;
  const std::size_t row = std::size_t(w) * 3;
  for (int j = 0; j < 5; ++j) {
    const std::uint8_t* line = img + std::size_t(reflect101(v + j - 2, h)) * row;
    for (int i = 0; i < 5; ++i) {
      const std::uint8_t* p = line + std::size_t(reflect101(u + i - 2, w)) * 3;
      const int k = kTaps[j] * kTaps[i];
      sb += k * p[0];
      sg += k * p[1];
      sr += k * p[2];
    }
  }
  return blurred_in(t, (sb + 128) >> 8, (sg + 128) >> 8, (sr + 128) >> 8);
}

constexpr int kChunkBytes = BlobRefiner::kChunkBytes;

using lanes::load16;
using lanes::store16;
using lanes::U16x8;
using lanes::widen8;

// Horizontal pass of the blur for the 8 pixels u0..u0+7 of row v (at least 2 px inside the
// image): 24 sums of five taps, one per byte (at most 16 x 255: no overflow).
void hblur_chunk(const std::uint8_t* img, int w, int u0, int v, std::uint16_t* out) {
  const std::uint8_t* p = img + std::size_t(v) * std::size_t(w) * 3 + std::size_t(u0 - 2) * 3;
  for (int i = 0; i < kChunkBytes; i += 8) {
    const std::uint8_t* q = p + i;
    store16(out + i,
            widen8(q) + 4 * widen8(q + 3) + 6 * widen8(q + 6) + 4 * widen8(q + 9) + widen8(q + 12));
  }
}

// Vertical pass for one row of a chunk from the horizontal sums of the five rows round it,
// rounded half up (at most 256 x 255 + 128: no overflow in 16 bits).
void vblur_row(const std::uint16_t* a, const std::uint16_t* b, const std::uint16_t* c,
               const std::uint16_t* d, const std::uint16_t* e, std::uint16_t* out) {
  for (int i = 0; i < kChunkBytes; i += 8) {
    const U16x8 s = load16(a + i) + 4 * load16(b + i) + 6 * load16(c + i) + 4 * load16(d + i) +
                    load16(e + i) + 128;
    store16(out + i, s >> 8);
  }
}

std::int64_t sum1(std::int64_t a, std::int64_t b) {
  return (a + b) * (b - a + 1) / 2;
}
std::int64_t sq_prefix(std::int64_t n) {
  return n < 0 ? 0 : n * (n + 1) * (2 * n + 1) / 6;
}

}  // namespace

BlobRefiner::BlobRefiner(int width, int height, int decimation)
    : w_(width),
      h_(height),
      d_(decimation),
      log2_d_(decimation == 1 ? 0 : (decimation == 2 ? 1 : 2)),
      stride_(bit_stride(width)),
      mask_(std::make_unique<std::uint64_t[]>(std::size_t(height) * bit_stride(width))),
      tmp_(std::make_unique<std::uint64_t[]>(std::size_t(height) * bit_stride(width))),
      cell_w_(width / decimation),
      cell_h_(height / decimation),
      cell_stride_(bit_stride(width / decimation)) {
  // The upsampling and the window's cell words take d as a shift (LineDetector normalises it).
  CARRIL_CHECK(decimation == 1 || decimation == 2 || decimation == 4);
  blob_ = std::make_unique<std::uint64_t[]>(std::size_t(cell_h_ + 2) * cell_stride_);
  chunks_ = (width + kChunk - 1) / kChunk;
  hsum_ = std::make_unique<std::uint16_t[]>(std::size_t(kHSlots) * std::size_t(chunks_) *
                                            std::size_t(kChunkBytes));
  htag_ = std::make_unique<std::uint64_t[]>(std::size_t(kHSlots) * std::size_t(chunks_));
  for (std::size_t i = 0; i < std::size_t(kHSlots) * std::size_t(chunks_); ++i)
    htag_[i] = ~std::uint64_t{0};
}

BlobRefiner::~BlobRefiner() = default;

void BlobRefiner::mark_blob(const RunLabeler& lab, int id, int y0, int y1, int cy0, int cy1) {
  const int cs = cell_stride_;
  for (int y = cy0 - 1; y <= cy1 + 1; ++y) {
    if (y < -1 || y > cell_h_) continue;
    for (int k = 0; k < cs; ++k) blob_row(y)[k] = 0;
  }
  for (int y = y0; y <= y1; ++y) {
    for (int i = lab.row_begin(y); i < lab.row_begin(y + 1); ++i) {
      if (lab.root(i) == id) set_range(blob_row(y), lab.run(i).x0, lab.run(i).x1);
    }
  }
}

void BlobRefiner::blur_chunk(const std::uint8_t* bgr, int u0, int v0, int rows,
                             std::uint16_t out[][kChunkBytes]) {
  // The chunk's ring of horizontal sums: slot (v & (kHSlots - 1)) holds row v when its tag says so.
  const int chunk = u0 / kChunk;
  std::uint64_t* tags = htag_.get() + std::size_t(chunk) * kHSlots;
  std::uint16_t* ring = hsum_.get() + std::size_t(chunk) * kHSlots * kChunkBytes;
  const std::uint64_t gen = gen_ << 16;
  if (!CARRIL_CHECK(rows >= 1 && rows <= kChunkRows)) return;
  const std::uint16_t* hs[kChunkRows + 4];
  for (const std::uint16_t*& h : hs) h = ring;  // valid in every entry; rows + 4 are set below
  for (int r = 0; r < rows + 4; ++r) {
    const int v = v0 - 2 + r, slot = v & (kHSlots - 1);
    std::uint16_t* h = ring + slot * kChunkBytes;
    if (tags[slot] != (gen | std::uint64_t(v))) {
      hblur_chunk(bgr, w_, u0, v, h);
      tags[slot] = gen | std::uint64_t(v);
    }
    hs[r] = h;
  }
  for (int o = 0; o < rows; ++o)
    vblur_row(hs[o], hs[o + 1], hs[o + 2], hs[o + 3], hs[o + 4], out[o]);
}

int BlobRefiner::rebuild_window(const std::uint8_t* bgr, const ColorThreshold& t,
                                const BitImage& cells, int cy0, int cy1, int k0, int k1) {
  const int cs = cell_stride_, s = stride_;
  // Solid cells (their 3x3 neighbourhood inside the blob; outside the image counts as inside)
  // and boundary cells (the 3x3 dilation of the blob minus the solid cells).
  const std::uint64_t last = valid_bits(cells.width, cs - 1);
  std::uint64_t er[3][kMaxWords], di[3][kMaxWords], solid[kMaxWords], band[kMaxWords],
      solid_px[kMaxWords], band_px[kMaxWords];
  int classified = 0;
  // The cell words under pixel words k0..k1: the only ones upsampled below, so the only ones
  // worked out.
  const int ck0 = k0 >> log2_d_, ck1 = (k1 >> log2_d_) < cs ? (k1 >> log2_d_) : cs - 1;
  // Row yy's horizontal passes go to slot (yy + 3) % 3 and serve the three cell rows round it.
  const auto pass_row = [&](int yy) {
    const int r = (yy + 3) % 3;
    if (yy < 0 || yy >= cell_h_) {
      for (int k = ck0; k <= ck1; ++k) {
        er[r][k] = kAll;
        di[r][k] = 0;
      }
    } else {
      bits::hpass3<true>(blob_row(yy), cs, last, er[r], ck0, ck1);
      bits::hpass3<false>(blob_row(yy), cs, last, di[r], ck0, ck1);
    }
  };
  pass_row(cy0 - 1);
  pass_row(cy0);
  for (int y = cy0; y <= cy1; ++y) {
    pass_row(y + 1);
    for (int k = ck0; k <= ck1; ++k) {
      const std::uint64_t valid = k + 1 < cs ? kAll : last;
      solid[k] = er[0][k] & er[1][k] & er[2][k] & valid;
      band[k] = (di[0][k] | di[1][k] | di[2][k]) & valid & ~solid[k];
    }
    upsample(solid, band, cs, solid_px, band_px, k0, k1, log2_d_);
    const int vy = d_ * y, rows = vy + d_ <= h_ ? d_ : h_ - vy;
    for (int j = 0; j < rows; ++j) {
      std::uint64_t* m = mask_.get() + std::ptrdiff_t(vy + j) * s;
      for (int k = k0; k <= k1; ++k) m[k] = solid_px[k];
    }
    // Boundary pixels, 8 columns at a time (all the cell row's pixel rows together).
    const bool rows_inside = vy >= 2 && vy + rows + 2 <= h_;
    static_assert(std::has_single_bit(unsigned(kChunk)), "a chunk starts at a multiple of kChunk");
    constexpr std::uint64_t kChunkMask = (std::uint64_t{1} << kChunk) - 1;
    for (int k = k0; k <= k1; ++k) {
      // The chunks that hold band pixels, in order, found from the lowest set bit left: most of
      // a word's chunks hold none (a tape's edge band is a few pixels wide).
      for (std::uint64_t left = band_px[k]; left != 0;) {
        const int c = std::countr_zero(left) & ~(kChunk - 1);
        const std::uint64_t bits = (left >> c) & kChunkMask;
        left &= ~(kChunkMask << c);
        const int u0 = 64 * k + c;
        if (rows_inside && u0 >= 2 && u0 + kChunk + 2 <= w_) {
          std::uint16_t px[kChunkRows][kChunkBytes];
          blur_chunk(bgr, u0, vy, rows, px);
          for (int j = 0; j < rows; ++j) {
            std::uint64_t* m = mask_.get() + std::ptrdiff_t(vy + j) * s;
            for (std::uint64_t b = bits; b != 0; b &= b - 1) {
              const int i = std::countr_zero(b);
              ++classified;
              const std::uint16_t* q = &px[j][3 * i];
              if (blurred_in(t, q[0], q[1], q[2])) m[k] |= std::uint64_t{1} << (c + i);
            }
          }
        } else {
          for (int j = 0; j < rows; ++j) {
            std::uint64_t* m = mask_.get() + std::ptrdiff_t(vy + j) * s;
            for (std::uint64_t b = bits; b != 0; b &= b - 1) {
              const int i = std::countr_zero(b);
              ++classified;
              if (pixel_in(bgr, w_, h_, u0 + i, vy + j, t)) m[k] |= std::uint64_t{1} << (c + i);
            }
          }
        }
      }
    }
  }
  return classified;
}

void BlobRefiner::window_moments(int y0, int y1, int v0, int v1, int k0, int k1,
                                 BlobSums& out) const {
  const int s = stride_;
  const std::uint64_t* m = mask_.get();
  // Moments of the area (by runs) and of the outline (pixels with a 4-neighbour outside).
  const int vb0 = d_ * y0, vb1 = d_ * y1 + d_ - 1;
  out.bands = vb1 - vb0 + 1 < BlobSums::kBands ? vb1 - vb0 + 1 : BlobSums::kBands;
  out.u_min = w_;
  out.v_min = h_;
  for (int v = v0; v <= v1; ++v) {
    const std::uint64_t* row = m + std::ptrdiff_t(v) * s;
    const std::uint64_t* up = v > v0 ? row - s : nullptr;
    const std::uint64_t* dn = v < v1 ? row + s : nullptr;
    int band_i = (vb1 - v) * out.bands / (vb1 - vb0 + 1);
    band_i = band_i < 0 ? 0 : (band_i >= out.bands ? out.bands - 1 : band_i);
    std::int64_t bc = 0, bsu = 0, bsuu = 0, rn = 0, rsu = 0, rsuu = 0;
    const auto add_run = [&](std::int64_t a, std::int64_t b) {
      rn += b - a + 1;
      rsu += sum1(a, b);
      rsuu += sq_prefix(b) - sq_prefix(a - 1);
      out.u_min = int(a) < out.u_min ? int(a) : out.u_min;
      out.u_max = int(b) > out.u_max ? int(b) : out.u_max;
      return true;
    };
    bits::RunScanner scan;
    for (int k = k0; k <= k1; ++k) {
      const std::uint64_t w = row[k];
      const std::uint64_t left = (w << 1) | (k > k0 ? row[k - 1] >> 63 : 0);
      const std::uint64_t right = (w >> 1) | (k < k1 ? row[k + 1] << 63 : 0);
      const std::uint64_t inner = w & left & right & (up ? up[k] : 0) & (dn ? dn[k] : 0);
      for (std::uint64_t o = w & ~inner; o != 0; o &= o - 1) {
        const std::int64_t u = 64 * k + std::countr_zero(o);
        ++bc;
        bsu += u;
        bsuu += u * u;
      }
      scan.word(w, k, add_run);
    }
    // A run to the end of the window's last word.
    scan.finish(64 * k1 + 63 < w_ ? 64 * k1 + 63 : w_ - 1, add_run);
    if (rn == 0) continue;
    const std::int64_t vv = v;
    out.v_min = v < out.v_min ? v : out.v_min;
    out.v_max = v;
    out.n += rn;
    out.su += rsu;
    out.sv += rn * vv;
    out.suu += rsuu;
    out.svv += rn * vv * vv;
    out.suv += rsu * vv;
    out.bn += bc;
    out.bsu += bsu;
    out.bsv += bc * vv;
    out.bsuu += bsuu;
    out.bsvv += bc * vv * vv;
    out.bsuv += bsu * vv;
    out.band_n[band_i] += rn;
    out.band_su[band_i] += rsu;
    out.band_sv[band_i] += rn * vv;
  }
}

int BlobRefiner::measure(const std::uint8_t* bgr, const ColorThreshold& t, const RunLabeler& lab,
                         const BitImage& cells, int id, BlobSums& out) {
  out = BlobSums{};
  const std::int16_t* box = lab.box(id);
  const int y0 = box[2], y1 = box[3];
  const int cy0 = y0 > 0 ? y0 - 1 : 0, cy1 = y1 + 1 < cell_h_ ? y1 + 1 : cell_h_ - 1;
  // The window: the blob's bounding box and one cell round it; words k0..k1 of each pixel row.
  const int cx0 = box[0] > 0 ? box[0] - 1 : 0, cx1 = box[1] + 1 < cell_w_ ? box[1] + 1 : box[1];
  const int k0 = (d_ * cx0) >> 6;
  const int k1 = (d_ * cx1 + d_ - 1 < w_ ? d_ * cx1 + d_ - 1 : w_ - 1) >> 6;
  mark_blob(lab, id, y0, y1, cy0, cy1);
  ++gen_;  // the frame may have changed since the last call: no cached row is valid
  const int classified = rebuild_window(bgr, t, cells, cy0, cy1, k0, k1);
  // The thesis's opening at full resolution, on this window of rows.
  const int v0 = d_ * cy0, v1 = d_ * cy1 + d_ - 1 < h_ ? d_ * cy1 + d_ - 1 : h_ - 1;
  std::uint64_t* m = mask_.get();
  std::uint64_t* tmp = tmp_.get();
  morph5_window<true>(m, tmp, stride_, w_, h_, v0, v1, k0, k1);
  morph5_window<false>(m, tmp, stride_, w_, h_, v0, v1, k0, k1);
  window_moments(y0, y1, v0, v1, k0, k1, out);
  return classified;
}

}  // namespace carril::fw
