#pragma once
// Full-resolution measurement of one blob found on the decimated mask. Binary cells of d x d
// pixels place a sharp edge anywhere within a cell, which biases a blob's width by up to a pixel
// per side (and, through the perspective taper of the tape, its centroid). So the blob is
// rebuilt at full resolution: cells whose 3x3 neighbourhood lies inside the blob are taken as
// solid, and every pixel of the cells along its boundary (inside and out) is classified the way
// the thesis's pipeline classifies it (5x5 Gaussian [1 4 6 4 1]^2 / 256 with reflected borders,
// HSV, the threshold window), then the 5x5 opening (two 3x3 erosions, two 3x3 dilations) is
// applied to that window of rows, and the moments of the result and of its outline are summed.
#include <cstdint>
#include <memory>

#include "firmware/perception/BlobLabeler.hpp"
#include "firmware/perception/LineDetector.hpp"

namespace carril::fw {

// Integer moments of one blob at full resolution. Pixel (u, v) has its centre at (u, v).
struct BlobSums {
  static constexpr int kBands = 16;
  std::int64_t n = 0, su = 0, sv = 0, suu = 0, svv = 0, suv = 0;        // area pixels
  std::int64_t bn = 0, bsu = 0, bsv = 0, bsuu = 0, bsvv = 0, bsuv = 0;  // outline pixels
  int u_min = 0, u_max = -1, v_min = 0, v_max = -1;                     // bounding box
  // The centre line: pixel count and sums in bands of rows, bottom (largest v) first.
  int bands = 0;
  std::int64_t band_n[kBands] = {}, band_su[kBands] = {}, band_sv[kBands] = {};
};

class BlobRefiner {
 public:
  // Boundary pixels are blurred 8 columns at a time, up to 4 rows at a time.
  static constexpr int kChunk = 8, kChunkBytes = 3 * kChunk, kChunkRows = 4;

  // For width x height frames and masks decimated by d (1, 2 or 4).
  BlobRefiner(int width, int height, int decimation);
  ~BlobRefiner();
  BlobRefiner(const BlobRefiner&) = delete;
  BlobRefiner& operator=(const BlobRefiner&) = delete;

  // Measures component `id` of `lab`, labelled on `cells`, in the BGR frame `bgr` for the colour
  // window `t`. Returns the number of boundary pixels it classified.
  int measure(const std::uint8_t* bgr, const ColorThreshold& t, const RunLabeler& lab,
              const BitImage& cells, int id, BlobSums& out);

 private:
  // The blob's cells, one row of words per cell row (with a cleared row above and below).
  std::uint64_t* blob_row(int y) { return blob_.get() + std::ptrdiff_t(y + 1) * cell_stride_; }
  // Writes blob `id`'s cells (cell rows y0..y1) into blob_, clearing rows cy0 - 1..cy1 + 1.
  void mark_blob(const RunLabeler& lab, int id, int y0, int y1, int cy0, int cy1);
  // Full-resolution mask of cell rows cy0..cy1, words k0..k1: solid cells set, boundary cells'
  // pixels classified as OpenCV would. Returns the number of pixels classified.
  int rebuild_window(const std::uint8_t* bgr, const ColorThreshold& t, const BitImage& cells,
                     int cy0, int cy1, int k0, int k1);
  // Area and outline moments of the window's mask rows v0..v1 (the blob's rows y0..y1 in bands).
  void window_moments(int y0, int y1, int v0, int v1, int k0, int k1, BlobSums& out) const;
  // Blurred BGR of the chunk at column u0 (a multiple of kChunk), rows v0..v0 + rows - 1, all
  // 2 px inside the image. The horizontal pass of each row of a chunk is done once per measure()
  // call and kept in the chunk's ring of kHSlots rows: a cell row's chunks need the d + 4 rows
  // round it, so without the ring each row's pass was done up to three times.
  void blur_chunk(const std::uint8_t* bgr, int u0, int v0, int rows,
                  std::uint16_t out[][kChunkBytes]);
  static constexpr int kHSlots = 8;              // >= kChunkRows + 4, a power of two
  int w_, h_, d_, log2_d_, stride_;              // log2_d_: d as a shift (d is 1, 2 or 4)
  std::unique_ptr<std::uint64_t[]> mask_, tmp_;  // h_ x stride_ full-resolution rows
  std::unique_ptr<std::uint64_t[]> blob_;        // the blob's cells, (cells high + 2) rows
  int cell_w_, cell_h_, cell_stride_;
  int chunks_ = 0;                         // kChunk-pixel chunks per row
  std::unique_ptr<std::uint16_t[]> hsum_;  // per chunk, kHSlots rows of kChunkBytes sums
  std::unique_ptr<std::uint64_t[]> htag_;  // per chunk and slot: (gen_ << 16) | row held
  std::uint64_t gen_ = 0;                  // measure() calls so far
};

}  // namespace carril::fw
