#pragma once
// Gaussian noise for the simulated sensors: Marsaglia and Tsang's ziggurat (J. Stat. Softw. 5(8),
// 2000; 128 layers), fed by 64-bit draws of the sensor's own std::mt19937_64.
//
// Why not std::normal_distribution: its algorithm is left to the standard library (libstdc++'s
// polar method, libc++'s is another), so the same seed gave different runs on different
// libraries; and at a log, a square root and about 2.5 engine draws per sample it was 7 % of a
// square run's time (541 lidar beams at 20 Hz). The ziggurat takes one draw and a multiply for
// 98.8 % of samples, and the numbers are this file's on every platform.
//
// Each draw's low 7 bits pick the layer and its high 32 bits are the signed value, so the two
// are independent (the paper's 32-bit version takes both from one word, a known flaw).
#include <cmath>
#include <cstdint>
#include <random>

namespace carril::sim {

namespace ziggurat {

struct Tables {
  std::uint32_t k[128];  // |value| below k[i]: inside layer i's rectangle, accept at once
  double w[128];         // value -> x for layer i
  double f[128];         // exp(-x_i^2 / 2) at layer i's right edge
  Tables() {
    const double m1 = 2147483648.0;  // 2^31
    double dn = 3.442619855899;      // the tail's start r
    double tn = dn;
    const double vn = 9.91256303526217e-3;  // each layer's area
    const double q = vn / std::exp(-0.5 * dn * dn);
    k[0] = std::uint32_t(dn / q * m1);
    k[1] = 0;
    w[0] = q / m1;
    w[127] = dn / m1;
    f[0] = 1.0;
    f[127] = std::exp(-0.5 * dn * dn);
    for (int i = 126; i >= 1; --i) {
      dn = std::sqrt(-2.0 * std::log(vn / dn + std::exp(-0.5 * dn * dn)));
      k[i + 1] = std::uint32_t(dn / tn * m1);
      tn = dn;
      f[i] = std::exp(-0.5 * dn * dn);
      w[i] = dn / m1;
    }
  }
};

inline const Tables& tables() {
  static const Tables t;
  return t;
}

// Uniform in (0, 1), never 0 (it goes into a log).
inline double open_unit(std::mt19937_64& g) {
  return (double(g() >> 11) + 0.5) * 0x1.0p-53;
}

// One standard normal sample.
inline double standard(std::mt19937_64& g) {
  constexpr double kR = 3.442619855899;
  const Tables& t = tables();
  for (;;) {
    const std::uint64_t u = g();
    const int i = int(u & 127U);
    const auto hz = std::int32_t(std::uint32_t(u >> 32));
    const double x = double(hz) * t.w[i];
    const std::int64_t mag = hz < 0 ? -std::int64_t(hz) : std::int64_t(hz);
    if (mag < std::int64_t(t.k[i])) return x;  // inside the layer's rectangle
    if (i == 0) {
      // The tail beyond r (Marsaglia's 1964 method).
      double xt = 0.0, y = 0.0;
      do {
        xt = -std::log(open_unit(g)) / kR;
        y = -std::log(open_unit(g));
      } while (y + y < xt * xt);
      return hz > 0 ? kR + xt : -kR - xt;
    }
    // The wedge between the rectangle and the curve.
    if (t.f[i] + open_unit(g) * (t.f[i - 1] - t.f[i]) < std::exp(-0.5 * x * x)) return x;
  }
}

}  // namespace ziggurat

// Drop-in for std::normal_distribution<double> with a std::mt19937_64.
class Normal {
 public:
  explicit Normal(double mean = 0.0, double stddev = 1.0) : mean_(mean), stddev_(stddev) {}
  double operator()(std::mt19937_64& g) const { return mean_ + stddev_ * ziggurat::standard(g); }

 private:
  double mean_, stddev_;
};

}  // namespace carril::sim
