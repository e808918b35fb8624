#pragma once
// Takes each new sample of a device that the sensor frame carries (a laser scan, a camera frame,
// a point cloud: hal types stamped with the driver's sequence number) once per consumer: the raw
// sensors' counterpart of Reader<T>, which does the same for the bus's topics. Each consumer holds
// its own, so one taking a scan does not hide it from another. Sequence 0 is a driver's "nothing
// yet" and is never taken.
#include <cstdint>

namespace carril::fw {

template <class Sample>
class SampleReader {
 public:
  // `s` is a sample this reader has not taken (nullptr and sequence 0 are not).
  bool fresh(const Sample* s) const { return s != nullptr && s->seq != 0 && s->seq != seen_; }
  // `s` if fresh, marking it taken; else nullptr.
  const Sample* take(const Sample* s) {
    if (!fresh(s)) return nullptr;
    seen_ = s->seq;
    return s;
  }
  // A sample has been taken since start-up.
  bool ever() const { return seen_ != 0; }

 private:
  std::uint32_t seen_ = 0;
};

}  // namespace carril::fw
