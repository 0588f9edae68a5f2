// Polynomial stand-ins for libm transcendentals in per-pixel kernels (docs/design.md §11: no libm per
// pixel where the result must match across targets). Each is written with +, -, *, sqrt and a select
// in a fixed order, so the scalar function, its Highway twin (core/math-inl.h) and a GPU port that
// marks the expression `precise` give the same bits: IEEE addition, multiplication and sqrt are
// correctly rounded everywhere, and -ffp-contract=off keeps a * b + c two roundings.
#pragma once

#include <cmath>

namespace ssgi {

// acos of |x| for |x| in [0, 1] is sqrt(1 - |x|) (a0 + a1 |x| + a2 |x|^2 + a3 |x|^3): Hastings'
// cubic (Approximations for Digital Computers, 1955), Abramowitz & Stegun 4.4.45 (there as
// arcsin x = pi/2 - that). A&S state |error| <= 5e-5; the coefficients as printed give 6.75e-5 rad
// at |x| = 0 in exact arithmetic; with float32's roundings the maximum is 6.77e-5 rad
// (tests/core/fast_math_test.cpp, every 256th float of [-1, 1]).
// The same four numbers are NVIDIA Cg's reference acos.
inline constexpr float kAcosA0 = 1.5707288f;
inline constexpr float kAcosA1 = -0.2121144f;
inline constexpr float kAcosA2 = 0.0742610f;
inline constexpr float kAcosA3 = -0.0187293f;
inline constexpr float kPiFloat = 3.14159265f;  // the float nearest pi

// acos(x) for x in [-1, 1] (the caller clamps; outside, sqrt of a negative gives NaN), in [0, pi]:
// with a = |x|, p = ((a3 a + a2) a + a1) a + a0 (Horner, each product and sum rounded), r = p *
// sqrt(1 - a); x < 0 gives pi - r. Max error 6.77e-5 rad.
inline float AcosPoly(float x) {
  const float a = std::fabs(x);
  float p = kAcosA3 * a + kAcosA2;
  p = p * a + kAcosA1;
  p = p * a + kAcosA0;
  const float r = p * std::sqrt(1.0f - a);
  return x < 0.0f ? kPiFloat - r : r;
}

}  // namespace ssgi
