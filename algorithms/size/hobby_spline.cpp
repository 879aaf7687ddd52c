#include "algorithms/size/hobby_spline.h"

#include "synth/config.h"

#include <Eigen/LU>

#include <cmath>

namespace grapebench {

namespace {



Vec2 rotated(const Vec2& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// Hobby's velocity function (MetaPost's "velocity"): the control-arm length relative
// to the chord for departure angle theta and arrival angle phi at tension 1.
double velocity(double theta, double phi) {
  const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
  const double num = 2 + std::sqrt(2.0) * (st - sp / 16) * (sp - st / 16) * (ct - cp);
  const double den = 3 * (1 + 0.5 * (std::sqrt(5.0) - 1) * ct + 0.5 * (3 - std::sqrt(5.0)) * cp);
  return num / den;
}

}  // namespace

ClosedHobbySpline closed_hobby_spline(const std::vector<Vec2>& z, double tension) {
  const int n = static_cast<int>(z.size());
  if (n < 3) throw InputError("closed_hobby_spline: needs at least 3 knots, got " + std::to_string(n));
  if (!(tension >= 0.75 && tension <= 4)) throw InputError("closed_hobby_spline: tension must lie in [0.75, 4]");
  auto at = [n](int k) { return ((k % n) + n) % n; };
  std::vector<double> d(static_cast<std::size_t>(n)), psi(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const Vec2 chord = z[static_cast<std::size_t>(at(k + 1))] - z[static_cast<std::size_t>(k)];
    d[static_cast<std::size_t>(k)] = chord.norm();
    if (!(d[static_cast<std::size_t>(k)] > 0) || !std::isfinite(d[static_cast<std::size_t>(k)])) {
      throw InputError("closed_hobby_spline: knots " + std::to_string(k) + " and " + std::to_string(at(k + 1)) +
                       " coincide or are not finite");
    }
  }
  // psi_k: turning angle at knot k from chord k-1 to chord k, in (-pi, pi].
  for (int k = 0; k < n; ++k) {
    const Vec2 in = z[static_cast<std::size_t>(k)] - z[static_cast<std::size_t>(at(k - 1))];
    const Vec2 out = z[static_cast<std::size_t>(at(k + 1))] - z[static_cast<std::size_t>(k)];
    psi[static_cast<std::size_t>(k)] = std::atan2(in.x() * out.y() - in.y() * out.x(), in.dot(out));
  }
  // Equal mock curvature at every knot (Hobby 1986; Knuth, METAFONT §276) with the
  // reciprocal tensions a = b = 1/tension and phi_k = -psi_k - theta_k:
  //   A_k th_{k-1} + (B_k + C_k) th_k + D_k th_{k+1} = -B_k psi_k - D_k psi_{k+1},
  //   A = a/(b^2 d_{k-1}), B = (3 - a)/(b^2 d_{k-1}), C = (3 - b)/(a^2 d_k), D = b/(a^2 d_k).
  // The system is cyclic and small (one unknown per knot), so it is solved densely.
  const double t = tension, a = 1 / t, b = 1 / t;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs(n);
  for (int k = 0; k < n; ++k) {
    const double dp = d[static_cast<std::size_t>(at(k - 1))], dk = d[static_cast<std::size_t>(k)];
    const double A = a / (b * b * dp), B = (3 - a) / (b * b * dp), C = (3 - b) / (a * a * dk), D = b / (a * a * dk);
    m(k, at(k - 1)) += A;
    m(k, k) += B + C;
    m(k, at(k + 1)) += D;
    rhs(k) = -B * psi[static_cast<std::size_t>(k)] - D * psi[static_cast<std::size_t>(at(k + 1))];
  }
  const Eigen::VectorXd theta = m.fullPivLu().solve(rhs);
  ClosedHobbySpline s;
  s.segments.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int j = at(k + 1);
    const double th = theta(k), ph = -psi[static_cast<std::size_t>(j)] - theta(j);
    const Vec2 p0 = z[static_cast<std::size_t>(k)], p3 = z[static_cast<std::size_t>(j)];
    const Vec2 chord = p3 - p0;
    const Vec2 p1 = p0 + rotated(chord, th) * (velocity(th, ph) / t);
    const Vec2 p2 = p3 - rotated(chord, -ph) * (velocity(ph, th) / t);
    s.segments.push_back({p0, p1, p2, p3});
  }

  return s;
}

double spline_length(const ClosedHobbySpline& spline) {
  // 16-point Gauss-Legendre nodes and weights on [-1, 1] (positive half).
  static constexpr double x[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                                  0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
  static constexpr double w[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                                  0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};
  double total = 0;
  for (const auto& b : spline.segments) {
    // |B'(t)| with B'(t) = 3[(1-t)^2 (P1-P0) + 2t(1-t)(P2-P1) + t^2 (P3-P2)].
    auto speed = [&](double u) {
      const double v = 1 - u;
      return (3 * (v * v * (b[1] - b[0]) + 2 * u * v * (b[2] - b[1]) + u * u * (b[3] - b[2]))).norm();
    };
    for (int half = 0; half < 2; ++half) {
      const double a = 0.5 * half, h = 0.25;  // [a, a + 0.5], centre a + h
      for (int i = 0; i < 8; ++i) total += h * w[i] * (speed(a + h - h * x[i]) + speed(a + h + h * x[i]));
    }
  }
  return total;
}

}  // namespace grapebench
