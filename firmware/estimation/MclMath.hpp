#pragma once
// Elementary functions for the localiser built from IEEE basic arithmetic only, so they give the
// same bits on every IEEE-754 machine (libm's may differ in the last bit between x86_64 and
// aarch64) and cost less than libm's where less accuracy will do.
#include <bit>
#include <cmath>
#include <cstdint>

namespace carril::fw {

// Natural logarithm of x > 0 (finite), from the exponent bits and the atanh series: within 4 ulp
// of log(x), and the same bits on every IEEE-754 machine (libm's log may differ in the last bit).
inline double portable_log(double x) {
  std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  int e = int((bits >> 52) & 0x7FF) - 1022;
  if (e == -1022) {  // subnormal: scale into the normal range first
    bits = std::bit_cast<std::uint64_t>(x * 0x1.0p54);
    e = int((bits >> 52) & 0x7FF) - 1022 - 54;
  }
  // x = m 2^e with m in [0.5, 1), then m in [sqrt(1/2), sqrt(2)).
  double m = std::bit_cast<double>((bits & 0x000FFFFFFFFFFFFFULL) | 0x3FE0000000000000ULL);
  if (m < 0.70710678118654752440) {
    m *= 2.0;
    e -= 1;
  }
  // log(m) = 2 atanh(z), z = (m - 1) / (m + 1), |z| <= 0.1716: 11 terms reach 1e-17.
  const double z = (m - 1.0) / (m + 1.0);
  const double z2 = z * z;
  constexpr double kInvOdd[12] = {1.0,        1.0 / 3.0,  1.0 / 5.0,  1.0 / 7.0,
                                  1.0 / 9.0,  1.0 / 11.0, 1.0 / 13.0, 1.0 / 15.0,
                                  1.0 / 17.0, 1.0 / 19.0, 1.0 / 21.0, 1.0 / 23.0};
  // Estrin's scheme: a dependency chain of 5 multiply-adds instead of Horner's 11.
  const double z4 = z2 * z2, z8 = z4 * z4;
  const double p0 = kInvOdd[0] + kInvOdd[1] * z2, p1 = kInvOdd[2] + kInvOdd[3] * z2;
  const double p2 = kInvOdd[4] + kInvOdd[5] * z2, p3 = kInvOdd[6] + kInvOdd[7] * z2;
  const double p4 = kInvOdd[8] + kInvOdd[9] * z2, p5 = kInvOdd[10] + kInvOdd[11] * z2;
  const double q0 = p0 + p1 * z4, q1 = p2 + p3 * z4, q2 = p4 + p5 * z4;
  const double s = (q0 + q1 * z8) + q2 * (z8 * z8);
  constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln 2 split for an exact e * hi
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  const double de = double(e);
  return de * kLn2Hi + (de * kLn2Lo + 2.0 * z * s);
}

// sin and cos of a [rad], |a| < 1e6: within 2e-10 absolute (Cody-Waite reduction to
// [-pi/4, pi/4], then Taylor polynomials to degree 11 and 10). Enough for beam endpoints (float)
// and motion headings (2e-10 of a step), at about a third of libm's sincos.
inline void fast_sincos(double a, double& s, double& c) {
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kPiOver2Hi = 1.57079632673412561417;  // pi/2 split: k * hi is exact
  constexpr double kPiOver2Lo = 6.07710050650619224932e-11;
  const double kf = a * kTwoOverPi;
  const auto k = std::int64_t(kf < 0.0 ? kf - 0.5 : kf + 0.5);  // round to nearest
  const double dk = double(k);
  const double r = (a - dk * kPiOver2Hi) - dk * kPiOver2Lo;
  const double r2 = r * r;
  const double sr =
      r + r * r2 *
              (-1.0 / 6 + r2 * (1.0 / 120 +
                                r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 + r2 * (-1.0 / 39916800)))));
  const double cr =
      1.0 + r2 * (-0.5 +
                  r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (-1.0 / 3628800)))));
  switch (k & 3) {  // quadrant
    case 0:
      s = sr;
      c = cr;
      break;
    case 1:
      s = cr;
      c = -sr;
      break;
    case 2:
      s = -sr;
      c = -cr;
      break;
    default:
      s = -cr;
      c = sr;
      break;
  }
}

}  // namespace carril::fw
