#pragma once
// A scalar function of time with its first two time derivatives (second-order forward-mode
// differentiation). The simulator builds every trajectory quantity from these so that the
// velocity, acceleration and angular rate the IMU synthesiser needs are exact, not finite
// differences (docs/SIMULATOR.md "Trajectory").
#include <cmath>

namespace luxloc::sim {

struct Jet {
  double v = 0.0;   // value
  double d = 0.0;   // d/dt
  double dd = 0.0;  // d^2/dt^2

  static constexpr Jet constant(double c) { return {c, 0.0, 0.0}; }
};

inline constexpr Jet operator+(Jet a, Jet b) { return {a.v + b.v, a.d + b.d, a.dd + b.dd}; }
inline constexpr Jet operator-(Jet a, Jet b) { return {a.v - b.v, a.d - b.d, a.dd - b.dd}; }
inline constexpr Jet operator-(Jet a) { return {-a.v, -a.d, -a.dd}; }
inline constexpr Jet operator+(Jet a, double c) { return {a.v + c, a.d, a.dd}; }
inline constexpr Jet operator+(double c, Jet a) { return a + c; }
inline constexpr Jet operator-(Jet a, double c) { return {a.v - c, a.d, a.dd}; }
inline constexpr Jet operator-(double c, Jet a) { return {c - a.v, -a.d, -a.dd}; }
inline constexpr Jet operator*(double c, Jet a) { return {c * a.v, c * a.d, c * a.dd}; }
inline constexpr Jet operator*(Jet a, double c) { return c * a; }
// Product rule: (ab)'' = a''b + 2a'b' + ab''.
inline constexpr Jet operator*(Jet a, Jet b) {
  return {a.v * b.v, a.d * b.v + a.v * b.d, a.dd * b.v + 2.0 * a.d * b.d + a.v * b.dd};
}

inline Jet sin(Jet a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return {s, c * a.d, c * a.dd - s * a.d * a.d};
}
inline Jet cos(Jet a) {
  const double s = std::sin(a.v), c = std::cos(a.v);
  return {c, -s * a.d, -s * a.dd - c * a.d * a.d};
}
// Angle of the vector (x, y); requires (x, y) != 0. With N = x y' - y x', D = x^2 + y^2:
// angle' = N / D and angle'' = (N' D - N D') / D^2, where N' = x y'' - y x''.
inline Jet atan2(Jet y, Jet x) {
  const double D = x.v * x.v + y.v * y.v;
  const double N = x.v * y.d - y.v * x.d;
  const double dN = x.v * y.dd - y.v * x.dd;
  const double dD = 2.0 * (x.v * x.d + y.v * y.d);
  return {std::atan2(y.v, x.v), N / D, (dN * D - N * dD) / (D * D)};
}

// A quintic smoothstep S(x) = 6x^5 - 15x^4 + 10x^3 of x = (t - t0) / duration, clamped to
// [0, 1]: a C2 step from 0 to 1 over [t0, t0 + duration] (S' and S'' vanish at both ends).
inline Jet smoothstep(double t, double t0, double duration) {
  const double x = (t - t0) / duration;
  if (x <= 0.0) return Jet::constant(0.0);
  if (x >= 1.0) return Jet::constant(1.0);
  return {x * x * x * (10.0 + x * (-15.0 + 6.0 * x)), 30.0 * x * x * (1.0 - x) * (1.0 - x) / duration,
          60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / (duration * duration)};
}

// A C2 plateau: 0 before t0, up over ramp, 1, down over the last ramp of [t0, t0 + duration].
inline Jet plateau(double t, double t0, double duration, double ramp) {
  return smoothstep(t, t0, ramp) - smoothstep(t, t0 + duration - ramp, ramp);
}

// f(G(t)) from f's derivatives in G and the Jet G(t): (f o G)' = f' G', (f o G)'' = f'' G'^2 + f' G''.
inline Jet compose(const Jet& f, const Jet& G) { return {f.v, f.d * G.d, f.dd * G.d * G.d + f.d * G.dd}; }

}  // namespace luxloc::sim
