#include "synth/stem_geometry.h"

#include "synth/config.h"

#include <boost/math/quadrature/gauss.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace grapebench {

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Closest points of two segments (Ericson, Real-Time Collision Detection, 5.1.9).
double segment_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 1e-300 && e <= 1e-300) return r.norm();
  if (a <= 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-300 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

bool inside_stem(const Stem& s, const Vec3& x) {
  const Vec3 ab = s.end - s.start;
  const double l2 = ab.squaredNorm();
  const double t = (x - s.start).dot(ab);
  if (t < 0 || t > l2) return false;
  const Vec3 perp = (x - s.start) - (t / l2) * ab;
  return perp.squaredNorm() <= s.radius * s.radius;
}

double exit_distance(const Stem& s, const Vec3& p, const Vec3& d) {
  const Vec3 axis = s.end - s.start;
  const double len = axis.norm();
  const Vec3 w = axis / len;
  const Vec3 rel = p - s.start;
  const double s0 = rel.dot(w), dw = d.dot(w);
  double t = std::numeric_limits<double>::infinity();
  if (dw > 1e-15) t = (len - s0) / dw;
  else if (dw < -1e-15) t = -s0 / dw;
  const Vec3 q0 = rel - s0 * w, dp = d - dw * w;
  const double A = dp.squaredNorm();
  if (A > 1e-30) {
    const double B = q0.dot(dp), C = q0.squaredNorm() - s.radius * s.radius;
    const double disc = std::max(0.0, B * B - A * C);
    t = std::min(t, (-B + std::sqrt(disc)) / A);
  }
  return std::max(0.0, t);
}

void perpendicular_basis(const Vec3& d, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(d.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = d.cross(helper).normalized();
  e2 = d.cross(e1);
}

double junction_overlap_volume(const Stem& child, const Stem& parent) {
  const Vec3 axis = child.end - child.start;
  const double len = axis.norm();
  const Vec3 d = axis / len;
  Vec3 e1, e2;
  perpendicular_basis(d, e1, e2);
  // Gauss-Legendre in the radius, the periodic trapezoid rule in the angle (spectrally
  // accurate for a smooth periodic integrand). The rule is fixed, so the result is
  // deterministic; tests compare it with a rule of twice the nodes.
  static const auto rule = boost::math::quadrature::gauss<double, 24>();
  const int n_phi = 96;
  double volume = 0;
  for (std::size_t k = 0; k < rule.abscissa().size(); ++k) {
    for (int sign : {-1, 1}) {
      const double x = sign * rule.abscissa()[k];
      if (k == 0 && sign == 1 && x == 0) continue;  // odd rule: the zero node once
      const double rho = 0.5 * child.radius * (1 + x);
      double ring = 0;
      for (int j = 0; j < n_phi; ++j) {
        const double phi = 2 * M_PI * j / n_phi;
        const Vec3 p = child.start + rho * (std::cos(phi) * e1 + std::sin(phi) * e2);
        ring += std::min(len, exit_distance(parent, p, d));
      }
      volume += rule.weights()[k] * rho * ring * (2 * M_PI / n_phi);
    }
  }
  return 0.5 * child.radius * volume;
}

double pedicel_entry_offset(const Stem& pedicel, const Berry& berry) {
  return -std::sqrt(berry.radius * berry.radius - pedicel.radius * pedicel.radius);
}

double pedicel_in_berry_volume(const Stem& pedicel, const Berry& berry) {
  const Vec3 d = (pedicel.end - pedicel.start).normalized();
  const double R = berry.radius, r = pedicel.radius;
  const Vec3 toc = berry.centre - pedicel.start;
  const double off_axis = (toc - toc.dot(d) * d).norm();
  const double sA = (pedicel.start - berry.centre).dot(d);
  const double sE = (pedicel.end - berry.centre).dot(d);
  if (off_axis > 1e-9 * R || r >= R || sA >= -R || sE <= pedicel_entry_offset(pedicel, berry) ||
      sE > std::sqrt(R * R - r * r)) {
    throw InputError("pedicel/berry configuration outside the closed-form volume's conditions");
  }
  return M_PI * r * r * sE + (2.0 * M_PI / 3.0) * (R * R * R - std::pow(R * R - r * r, 1.5));
}

}  // namespace grapebench
