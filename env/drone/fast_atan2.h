// fast_atan2: a branch-free polynomial arctangent for the grid sensors' projection loop
// (grid_sensor.cpp), written so that a loop of it over arrays vectorizes (no calls, no branches:
// the selects compile to blends).
//
// Method: with a = min(|y|, |x|) / max(|y|, |x|) in [0, 1], atan(a) is an odd minimax polynomial of
// degree 11; then atan2 = pi/2 - atan(a) when |y| > |x|, pi - that when x < 0, and the sign of y.
// Max error against std::atan2 over all directions: 1.9e-6 rad measured (1e-4 degrees); tested in
// grid_sensor_test.cpp against the bound kFastAtan2MaxError = 2e-5 rad, which also covers latitude
// as fast_atan2(up, horizontal) against std::asin(up / distance) (1.6e-5 rad near the poles, from
// float rounding in asin). Both are far below a grid cell (degrees).
// atan2(0, 0) = 0. Units: radians in [-pi, pi].
#ifndef RLT_ENV_DRONE_FAST_ATAN2_H_
#define RLT_ENV_DRONE_FAST_ATAN2_H_

#include <cmath>

namespace rlt::drone {

inline constexpr float kFastAtan2MaxError = 2e-5f;  // radians, the tested bound

inline float fast_atan2(float y, float x) {
  constexpr float kHalfPi = 1.57079632679f;
  constexpr float kPi = 3.14159265359f;
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float big = ax > ay ? ax : ay;
  const float small = ax > ay ? ay : ax;
  const float a = small / (big > 1e-30f ? big : 1e-30f);
  const float s = a * a;
  float r = -0.01172120f;
  r = r * s + 0.05265332f;
  r = r * s - 0.11643287f;
  r = r * s + 0.19354346f;
  r = r * s - 0.33262347f;
  r = r * s + 0.99997726f;
  r = r * a;
  r = ay > ax ? kHalfPi - r : r;
  r = x < 0.0f ? kPi - r : r;
  return y < 0.0f ? -r : r;
}

}  // namespace rlt::drone

#endif  // RLT_ENV_DRONE_FAST_ATAN2_H_
