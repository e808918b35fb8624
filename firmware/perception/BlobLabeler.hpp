#pragma once
// Binary masks packed 64 cells to a word, 3x3 morphology on them, and 8-connected component
// labelling by runs: the runs of each row are linked to the overlapping runs of the row above by
// union-find over fixed-capacity arrays, and each component's cell count and bounding box are
// accumulated. All storage is allocated by the constructor; labelling never allocates.
#include <cstddef>
#include <cstdint>
#include <memory>

namespace carril::fw {

// Row-major bit image; bit x % 64 of word x / 64 of a row is cell x. Bits past `width` are 0.
struct BitImage {
  std::uint64_t* bits = nullptr;
  int width = 0, height = 0;
  int stride = 0;  // words per row
  std::uint64_t* row(int y) const { return bits + std::ptrdiff_t(y) * stride; }
};

// Words per row for a width.
inline int bit_stride(int width) {
  return (width + 63) / 64;
}

// 3x3 erosion, pixels outside the image counting as set (cv::erode's default border), and 3x3
// dilation, outside counting as clear (cv::dilate's). `tmp` has the same shape; src may be dst.
void erode3x3(const BitImage& src, const BitImage& dst, const BitImage& tmp);
void dilate3x3(const BitImage& src, const BitImage& dst, const BitImage& tmp);

class RunLabeler {
 public:
  // For masks of up to `height` rows, with room for max_runs runs per mask.
  RunLabeler(int height, int max_runs);
  ~RunLabeler();
  RunLabeler(const RunLabeler&) = delete;
  RunLabeler& operator=(const RunLabeler&) = delete;

  // Labels the mask's 8-connected components. False (and no components) when the mask has more
  // runs than the capacity: a saturated frame (speckle, a patterned floor), nothing overflows.
  bool label(const BitImage& m);
  int run_count() const { return n_runs_; }

  // The up to k largest components with at least min_cells cells, largest first: their ids in
  // `ids`, their cell counts in `cells`. Returns how many.
  int largest(int min_cells, int k, int* ids, int* cells) const;

  // The runs, in row order; after label(), root(i) is run i's component id.
  struct Run {
    std::int16_t x0, x1, y;
  };
  const Run& run(int i) const { return runs_[i]; }
  int root(int i) const { return parent_[i]; }
  int row_begin(int y) const { return row_start_[y]; }  // first run of row y (y <= height)
  // A component's bounding box in cells, inclusive: x0, x1, y0, y1.
  const std::int16_t* box(int id) const { return &box_[std::size_t(id) * 4]; }

 private:
  int find(int i);
  void unite(int a, int b);

  int height_, max_runs_;
  int n_runs_ = 0;
  std::unique_ptr<Run[]> runs_;
  std::unique_ptr<std::int32_t[]> parent_;     // union-find; after label(): each run's root
  std::unique_ptr<std::int32_t[]> cells_;      // per root: cell count
  std::unique_ptr<std::int16_t[]> box_;        // per root: x0, x1, y0, y1
  std::unique_ptr<std::int32_t[]> row_start_;  // per row (and one past the last): first run
};

}  // namespace carril::fw
