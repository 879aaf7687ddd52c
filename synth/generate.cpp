#include "synth/generate.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "synth/rng.h"
#include "synth/stem_geometry.h"

namespace grapebench {

namespace {

constexpr double kDeg = M_PI / 180.0;

// A berry during packing: attached at `anchor` on its carrier stem's axis.
struct Seedling {
  Vec3 anchor;
  int carrier;       // stem index
  double reach;      // nominal |centre - anchor| = pedicel length outside + radius
  double reach_max;  // the pedicel may stretch up to this to make room
  double radius;
  Vec3 centre;
  Rgb colour;
  bool alive = true;
  bool on_wing = false;  // pulled towards the wing's axis rather than the rachis
};

Vec3 pedicel_end(const Seedling& s) {
  const Vec3 d = (s.centre - s.anchor).normalized();
  return s.centre - 0.5 * s.radius * d;
}

// Keeps the pedicel at least `min_angle` away from its carrier's axis (a pedicel
// along its branch would run inside it) and its length within [nominal, maximum];
// `spring` in [0, 1] pulls a stretched pedicel back towards its nominal length.
void enforce_rod(Seedling& s, const Vec3& carrier_axis, double min_angle, double spring = 0) {
  Vec3 d = s.centre - s.anchor;
  double len = d.norm();
  if (len < 1e-12) {
    d = Vec3(0, 0, -1);
    len = s.reach;
  }
  d /= len;
  len = std::clamp(len, s.reach, s.reach_max);
  len -= spring * (len - s.reach);
  const double c = d.dot(carrier_axis), cmax = std::cos(min_angle);
  if (std::abs(c) > cmax) {
    Vec3 perp = d - c * carrier_axis;
    if (perp.squaredNorm() < 1e-20) {
      Vec3 e1, e2;
      perpendicular_basis(carrier_axis, e1, e2);
      perp = e1;
    }
    perp.normalize();
    d = (c > 0 ? 1.0 : -1.0) * cmax * carrier_axis + std::sin(min_angle) * perp;
  }
  s.centre = s.anchor + len * d;
}

float clamp01(double v) { return static_cast<float>(std::clamp(v, 0.0, 1.0)); }

// Builds one bunch in named steps; the steps draw from one generator in a fixed
// order (size, peduncle, rachis, branches, berries), so a seed gives one bunch.
class BunchBuilder {
 public:
  // `wall`: a flat side's outward unit normal (horizontal) and distance from the axis, m;
  // distance 0 for none.
  BunchBuilder(const BunchParams& params, std::uint64_t seed, const Vec3& wall_normal = Vec3::Zero(),
               double wall_distance = 0)
      : p(params), rng(seed), seed_(seed) {
    bunch.flat_side_normal = wall_normal;
    bunch.flat_side_distance = wall_distance;
  }

  Bunch build(GenerationReport* report) {
    bunch.stem_colour = p.stem_colour;
    draw_size();
    add_peduncle();
    add_rachis();
    add_branches();
    add_tip_carrier();
    add_wing();
    seed_berries();
    relax();
    remove_bad_contacts();
    attach_berries();
    const auto problems = check_bunch(bunch);
    if (!problems.empty()) {
      std::string msg = "bunch parameters give an invalid skeleton: ";
      msg.append(problems.front());
      msg.append(" (try a larger branch_spacing or rachis_bare_length, or thinner stems)");
      throw InputError(msg);
    }
    if (report) {
      report->berries_requested = requested;
      report->berries_removed = removed;
      report->rachis_length = L;
      report->branches = branches;
    }
    return bunch;
  }

 private:
  struct Carrier {
    int stem;
    double t0, t1;  // usable interval along the stem, m from its start
    bool wing = false;
  };
  static constexpr double min_pedicel_angle = 35 * kDeg;

  std::size_t n() const { return seeds.size(); }

  // Bunches with more berries are bigger: the rachis length follows the berry count's
  // quantile (with noise) and the branches scale with it.
  void draw_size() {
    requested = rng.uniform_int(p.berry_count_min, p.berry_count_max);
    const double count_quantile =
        p.berry_count_max > p.berry_count_min
            ? static_cast<double>(requested - p.berry_count_min) / (p.berry_count_max - p.berry_count_min)
            : 0.5;
    const double size = std::clamp(count_quantile + rng.uniform(-0.1, 0.1), 0.0, 1.0);
    L = p.rachis_length_min + size * (p.rachis_length_max - p.rachis_length_min);
    branch_scale = 0.85 + 0.3 * size;
  }

  bool flat() const { return bunch.flat_side_distance > 0; }
  // A branch growing towards a flat side's wall turns away from it about the rachis,
  // just enough that its end stays a berry's room short of the wall (along the wall at
  // most): the cane deflects it. Branches clear of the wall keep their azimuths
  // (squeezing all of them onto the free arc instead crowded the far side: 14.7 % of
  // the berries dropped against 8.7 % at depth 0.3, docs/synth.md). `horizontal` is the
  // branch's horizontal length, m; returns its azimuth, rad.
  double turned_from_wall(double phi, double horizontal) const {
    const Vec3& n = bunch.flat_side_normal;
    const double wall_phi = std::atan2(n.y(), n.x());
    const double rel = std::remainder(phi - wall_phi, 2 * M_PI);
    const double room = bunch.flat_side_distance - berry_room();
    if (horizontal <= 0 || horizontal * std::cos(rel) <= room) return phi;
    const double least = std::acos(std::clamp(room / horizontal, 0.0, 1.0));
    return wall_phi + (rel >= 0 ? least : -least);
  }
  // What a berry needs beyond its anchor: a pedicel and a diameter.
  double berry_room() const { return p.pedicel_length_mean + 2 * p.berry_radius_mean; }

  // The peduncle: the rachis top J = origin lies on its axis.
  void add_peduncle() {
    // Peduncle: the rachis top J = origin lies on its axis, `stub` above its lower end,
    // so the rachis's first segment starts strictly inside it.
    const double tilt = p.peduncle_angle * kDeg, azimuth = rng.uniform(0, 2 * M_PI);
    const Vec3 up(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    const double stub = p.rachis_radius_top;
    bunch.top = Vec3::Zero();
    bunch.peduncle_direction = up;
    bunch.cutting_point = p.cutting_point_fraction * p.peduncle_length * up;
    bunch.stems.push_back({-stub * up, p.peduncle_length * up, p.peduncle_radius, Part::Peduncle});
    bunch.peduncle = 0;
  }

  // Branch heights and the rachis segments.
  void add_rachis() {
    // Branch heights below J, jittered around a regular spacing.
    for (double h = p.rachis_bare_length; h <= L - p.branch_spacing; h += p.branch_spacing) {
      heights.push_back(h + rng.uniform(-0.1, 0.1) * p.branch_spacing);
    }
    if (heights.empty()) heights.push_back(0.5 * (p.rachis_bare_length + L));
    nb = static_cast<int>(heights.size());

    // Rachis: one segment per branch, boundaries halfway between branches, radius
    // tapering linearly with depth; segment 0 is the peduncle's child, the others are
    // stacked coaxially on their predecessor, but for a bend's: the child of the one
    // above it.
    const auto z0 = [&](int k) { return k == 0 ? 0.0 : 0.5 * (heights[k - 1] + heights[k]); };
    const auto z1 = [&](int k) { return k + 1 == nb ? L : 0.5 * (heights[k] + heights[k + 1]); };
    const auto radius = [&](int k) {
      const double frac = 0.5 * (z0(k) + z1(k)) / L;
      return p.rachis_radius_top + (p.rachis_radius_bottom - p.rachis_radius_top) * frac;
    };
    draw_bend(z0, radius);
    segment.assign(nb, 0);
    for (int k = 0; k < nb; ++k) {
      Stem s{axis_point(z0(k)), axis_point(z1(k)), radius(k), Part::Rachis};
      if (k == 0) {
        s.parent = bunch.peduncle;
      } else if (k == bend_segment) {
        s.start = bend_start;
        s.parent = segment[k - 1];
        bunch.bend = static_cast<int>(bunch.stems.size());
      } else {
        s.stacked_on = segment[k - 1];
      }
      segment[k] = static_cast<int>(bunch.stems.size());
      bunch.stems.push_back(s);
    }
  }

  // A bent main axis, from its own stream (so a bunch without one is the bunch its seed
  // gives at probability 0): at the node between segments k - 1 and k, k in the lower
  // two thirds, the rest of the axis turns by the drawn angle. The bent part starts on
  // the axis above, inside the segment above, just far enough from its end for its
  // base disc to stay inside (check_bunch's rule, r sin theta): a knee joint whose
  // volume is the exact junction overlap of any child stem.
  template <class Depth, class Radius>
  void draw_bend(const Depth& z0, const Radius& radius) {
    if (p.bend_probability <= 0 || nb < 2) return;
    Rng br(derive_seed(seed_, 0xbe4d));
    if (br.uniform(0, 1) >= p.bend_probability) return;
    const int k = br.uniform_int(std::max(1, static_cast<int>(std::ceil(nb / 3.0))), nb - 1);
    const double theta = p.bend_angle * br.uniform(0.75, 1.25) * kDeg, psi = br.uniform(0, 2 * M_PI);
    if (!(radius(k) < radius(k - 1))) return;  // a child must be thinner than its parent
    bend_segment = k;
    bend_depth = z0(k);
    bend_dir = Vec3(std::sin(theta) * std::cos(psi), std::sin(theta) * std::sin(psi), -std::cos(theta));
    bend_lift = 1.1 * radius(k) * std::sin(theta);
    bend_start = Vec3(0, 0, -bend_depth + bend_lift);
  }

  // The main axis at depth h below J (m along the straight axis): (0, 0, -h) above the
  // bend, below it on the bent part (the rest of the axis keeps its lengths).
  Vec3 axis_point(double h) const {
    if (bend_segment < 0 || h <= bend_depth) return Vec3(0, 0, -h);  // the node itself: the end of the part above
    return bend_start + (bend_lift + (h - bend_depth)) * bend_dir;
  }
  // Where the main axis is at height z, projected to z = 0: the origin above the bend,
  // the bent part's line below it (the berries' pull and outward directions).
  Vec3 axis_at_height(double z) const {
    if (bend_segment < 0 || z >= -bend_depth) return Vec3::Zero();
    const Vec3 q = bend_start + (z - bend_start.z()) / bend_dir.z() * bend_dir;
    return Vec3(q.x(), q.y(), 0);
  }

  // Lateral branches and their berry carriers.
  void add_branches() {
    // Lateral branches, phyllotactic azimuths, shorter down the bunch.
    const double phi0 = rng.uniform(0, 2 * M_PI);
    for (int k = 0; k < nb; ++k) {
      const double s = nb > 1 ? static_cast<double>(k) / (nb - 1) : 0.0;
      const double len = (p.branch_length_top + (p.branch_length_bottom - p.branch_length_top) * s) * branch_scale *
                         rng.uniform(0.9, 1.1);
      const Vec3 a = axis_point(heights[k]);
      // A branch that would touch another stem is drawn again, then left out.
      for (int attempt = 0; attempt < 8; ++attempt) {
        double phi = phi0 + k * 137.508 * kDeg + rng.uniform(-15, 15) * kDeg + attempt * 0.9;
        const double alpha = (p.branch_angle + rng.uniform(-5, 5) + 2 * attempt) * kDeg;
        if (flat()) phi = turned_from_wall(phi, len * std::sin(alpha));
        const Vec3 d(std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), -std::cos(alpha));
        Stem br{a, a + len * d, p.branch_radius, Part::Rachis};
        br.parent = segment[k];
        if (!clear_of_stems(br)) continue;
        const int idx = static_cast<int>(bunch.stems.size());
        bunch.stems.push_back(br);
        ++branches;
        // On a bent part the branch's angle to its own segment is not alpha (it is drawn
        // from the vertical: branches hang); the carrier needs the real one.
        const Stem& parent = bunch.stems[segment[k]];
        const double to_parent =
            bend_segment >= 0 && k >= bend_segment
                ? std::acos(std::clamp(d.dot((parent.end - parent.start).normalized()), -1.0, 1.0))
                : alpha;
        add_carrier(idx, len, parent.radius, to_parent, false);
        break;
      }
    }
  }

  // A side branch of length `len` leaving a parent of `parent_radius` at `angle` (rad)
  // carries berries on its outer part: from where a pedicel clears the parent (and at
  // least 0.3 of the way out) to its end.
  void add_carrier(int stem, double len, double parent_radius, double angle, bool wing) {
    const double reach_out = (parent_radius + p.pedicel_radius) / std::sin(angle) + 2 * p.pedicel_radius;
    const double t0 = std::max(0.3 * len, reach_out), t1 = len - 1.5 * p.pedicel_radius;
    if (t1 > t0) carriers.push_back({stem, t0, t1, wing});
  }

  // True when `st` keeps clear of every stem but its parent.
  bool clear_of_stems(const Stem& st) const {
    for (int j = 0; j < static_cast<int>(bunch.stems.size()); ++j) {
      const Stem& o = bunch.stems[j];
      if (j != st.parent && segment_segment_distance(st.start, st.end, o.start, o.end) < st.radius + o.radius) return false;
    }
    return true;
  }

  // A wing: an arm leaving the peduncle below the cutting point, 60-80 deg from the
  // downward vertical, with phyllotactic side branches on its outer 70 % (a small
  // bunch of its own). Drawn from its own stream, so a bunch without one is the bunch
  // its seed gives with wings off; a wing that cannot keep clear of the body in 12
  // tries is left out.
  void add_wing() {
    if (p.wing_probability <= 0) return;
    Rng wr(derive_seed(seed_, 0x717e));
    if (wr.uniform(0, 1) >= p.wing_probability) return;
    const Vec3 up = bunch.peduncle_direction;
    const double cut = p.cutting_point_fraction * p.peduncle_length;
    const double length = p.wing_length * wr.uniform(0.85, 1.15);
    for (int attempt = 0; attempt < 12; ++attempt) {
      const double at = wr.uniform(0.45, 0.85) * cut, phi = wr.uniform(0, 2 * M_PI);
      const double alpha = wr.uniform(60, 80) * kDeg;
      const Vec3 d(std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi), -std::cos(alpha));
      Stem arm{at * up, at * up + length * d, p.rachis_radius_bottom, Part::Rachis};
      arm.parent = bunch.peduncle;
      // check_bunch's rule: the base disc inside the peduncle, clear of its ends.
      const double base = arm.radius * std::sqrt(std::max(0.0, 1 - std::pow(d.dot(up), 2)));
      if (at + p.rachis_radius_top < base || at > p.peduncle_length - base || !clear_of_stems(arm)) continue;
      bunch.wing = static_cast<int>(bunch.stems.size());
      bunch.stems.push_back(arm);
      Vec3 e1, e2;
      perpendicular_basis(d, e1, e2);
      const double phi0 = wr.uniform(0, 2 * M_PI);
      int k = 0;
      for (double h = 0.3 * length; h <= length - 0.5 * p.branch_spacing - p.branch_radius; h += p.branch_spacing, ++k) {
        const double f = (h - 0.3 * length) / (0.7 * length);
        const double len = std::max(p.branch_length_bottom, (0.35 - 0.2 * f) * length) * wr.uniform(0.9, 1.1);
        const double beta = (p.branch_angle + wr.uniform(-5, 5)) * kDeg, psi = phi0 + k * 137.508 * kDeg;
        const Vec3 dir = std::sin(beta) * (std::cos(psi) * e1 + std::sin(psi) * e2) + std::cos(beta) * d;
        const Vec3 a = arm.start + h * d;
        Stem br{a, a + len * dir, p.branch_radius, Part::Rachis};
        br.parent = bunch.wing;
        if (!clear_of_stems(br)) continue;
        bunch.stems.push_back(br);
        add_carrier(static_cast<int>(bunch.stems.size()) - 1, len, arm.radius, beta, true);
      }
      const double t1 = length - 1.5 * p.pedicel_radius, t0 = std::max(0.8 * length, t1 - p.branch_spacing);
      if (t1 > t0) carriers.push_back({bunch.wing, t0, t1, true});
      return;
    }
  }

  // The rachis tip carries berries too.
  void add_tip_carrier() {
    const Stem& last = bunch.stems[segment[nb - 1]];
    const double seg_len = (last.end - last.start).norm();
    const double t1 = seg_len - 1.5 * p.pedicel_radius;
    const double t0 = std::max(0.55 * seg_len, t1 - p.branch_spacing);
    if (t1 > t0) carriers.push_back({segment[nb - 1], t0, t1});
  }

  // Berries per carrier, placed along it, with radius, pedicel and colour.
  void seed_berries() {
    // Berries per carrier in proportion to usable length (largest remainder), the
    // wing's share over the wing's carriers, the rest over the main body's.
    std::vector<int> count(carriers.size());
    const bool winged = bunch.wing >= 0;
    const int on_wing = winged ? static_cast<int>(std::lround(p.wing_share * requested)) : 0;
    for (const bool wing : {false, true}) {
      const int total = wing ? on_wing : requested - on_wing;
      std::vector<double> weight(carriers.size(), 0.0);
      for (std::size_t c = 0; c < carriers.size(); ++c) {
        if (carriers[c].wing == wing) weight[c] = carriers[c].t1 - carriers[c].t0;
      }
      const double wsum = std::accumulate(weight.begin(), weight.end(), 0.0);
      if (total > 0 && wsum <= 0) removed += total;  // no carrier to take them: reported as dropped
      if (total == 0 || wsum <= 0) continue;
      std::vector<std::pair<double, int>> remainder;
      int assigned = 0;
      for (std::size_t c = 0; c < carriers.size(); ++c) {
        if (carriers[c].wing != wing) continue;
        const double exact = total * weight[c] / wsum;
        count[c] = static_cast<int>(std::floor(exact));
        assigned += count[c];
        remainder.emplace_back(-(exact - count[c]), static_cast<int>(c));
      }
      std::sort(remainder.begin(), remainder.end());
      for (int k = 0; assigned < total; ++k, ++assigned) ++count[remainder[k % remainder.size()].second];
    }

    for (std::size_t c = 0; c < carriers.size(); ++c) {
      const Stem& carrier = bunch.stems[carriers[c].stem];
      const Vec3 axis = (carrier.end - carrier.start).normalized();
      for (int k = 0; k < count[c]; ++k) {
        const double u = (k + 0.5 + rng.uniform(-0.1, 0.1)) / count[c];
        const double t = carriers[c].t0 + u * (carriers[c].t1 - carriers[c].t0);
        Seedling s;
        s.carrier = carriers[c].stem;
        s.on_wing = carriers[c].wing;
        s.anchor = carrier.start + t * axis;
        s.radius =
            std::clamp(rng.normal(p.berry_radius_mean, p.berry_radius_sd), p.berry_radius_min, p.berry_radius_max);
        const double ped =
            std::max(0.4 * p.pedicel_length_mean, rng.normal(p.pedicel_length_mean, p.pedicel_length_sd));
        s.reach = ped + s.radius;
        s.reach_max = p.pedicel_stretch * ped + s.radius;
        Vec3 radial = Vec3(s.anchor.x(), s.anchor.y(), 0) - axis_at_height(s.anchor.z());
        if (s.on_wing) {  // outwards from the wing's axis
          const Stem& w = bunch.stems[bunch.wing];
          const Vec3 wd = (w.end - w.start).normalized();
          radial = s.anchor - w.start - (s.anchor - w.start).dot(wd) * wd;
        }
        // An anchor on the main axis (the tip carrier) has no outward direction: none (a
        // bent tip's axis leans, and its lean would push every tip berry one way).
        const bool main_axis = std::find(segment.begin(), segment.end(), s.carrier) != segment.end();
        radial = radial.squaredNorm() > 1e-12 ? radial.normalized()
                 : main_axis                  ? Vec3::Zero()
                                              : Vec3(axis.x(), axis.y(), 0);
        // One draw per statement, z first: the order GCC gave the unspecified order of
        // a call's arguments, which clang reverses.
        const double jz = rng.normal(), jy = rng.normal(), jx = rng.normal();
        const Vec3 jitter(jx, jy, jz);
        Vec3 dir = radial + 0.4 * axis + 0.8 * jitter.normalized() + Vec3(0, 0, -0.3);
        if (dir.squaredNorm() < 1e-12) dir = Vec3(0, 0, -1);
        s.centre = s.anchor + s.reach * dir.normalized();
        enforce_rod(s, axis, min_pedicel_angle);
        const double shade = rng.normal(0, p.colour_variation);
        s.colour = {clamp01(p.berry_colour.r * (1 + shade) + rng.normal(0, 0.25 * p.colour_variation)),
                    clamp01(p.berry_colour.g * (1 + shade) + rng.normal(0, 0.25 * p.colour_variation)),
                    clamp01(p.berry_colour.b * (1 + shade) + rng.normal(0, 0.25 * p.colour_variation))};
        seeds.push_back(s);
      }
    }
  }

  // Packing relaxation (position-based dynamics, Gauss-Seidel, fixed order).
  void relax() {
    carrier_axis.resize(n());
    for (std::size_t i = 0; i < n(); ++i) {
      const Stem& c = bunch.stems[seeds[i].carrier];
      carrier_axis[i] = (c.end - c.start).normalized();
    }
    skeleton = bunch.stems.size();  // peduncle, rachis, branches
    const int total_iterations = p.relax_iterations + (p.relax_iterations > 0 ? 100 : 0);
    for (int it = 0; it < total_iterations; ++it) {
      const bool settle = it >= p.relax_iterations;  // last steps: constraints only
      for (std::size_t i = 0; i < n(); ++i) relax_berry(i, it, settle);
    }
  }

  // One berry's step of the relaxation: pull, berry contacts, stems, other pedicels,
  // then its own pedicel's rod constraint.
  void relax_berry(std::size_t i, int it, bool settle) {
    Seedling& s = seeds[i];
    if (!settle) {
      // Forces fade out so the packing ends in equilibrium.
      const double fade = 1.0 - static_cast<double>(it) / p.relax_iterations;
      const double pull = p.pull_strength * p.compactness * fade;
      if (s.on_wing) {
        // Towards the wing's axis, as the body's berries go towards the rachis.
        const Stem& w = bunch.stems[bunch.wing];
        const Vec3 ab = w.end - w.start;
        const Vec3 q = w.start + std::clamp((s.centre - w.start).dot(ab) / ab.squaredNorm(), 0.0, 1.0) * ab;
        s.centre -= pull * (s.centre - q);
      } else {  // towards the main axis at the berry's height (x - 0 is x: a straight axis as before)
        const Vec3 q = axis_at_height(s.centre.z());
        s.centre.x() -= pull * (s.centre.x() - q.x());
        s.centre.y() -= pull * (s.centre.y() - q.y());
      }
      s.centre.z() -= 0.03 * s.radius * (1.0 - 0.5 * p.compactness) * fade;
    }
    for (std::size_t j = i + 1; j < n(); ++j) {
      Seedling& o = seeds[j];
      const double dmin = s.radius + o.radius - press * std::min(s.radius, o.radius);
      Vec3 delta = o.centre - s.centre;
      const double d2 = delta.squaredNorm();
      if (d2 >= dmin * dmin) continue;
      double dist = std::sqrt(d2);
      if (dist < 1e-12) {
        delta = Vec3(0, 0, 1);
        dist = 1e-12;
      }
      const Vec3 shift = 0.5 * (dmin - dist) / dist * delta;
      s.centre -= shift;
      o.centre += shift;
    }
    for (std::size_t k = 0; k < skeleton; ++k) {
      const Stem& st = bunch.stems[k];
      push_from_segment(s, st.start, st.end, s.radius + st.radius + clearance);
    }
    // A berry against another berry's pedicel: both give way; the pedicel turns
    // about its anchor, so its berry moves by the push over the lever arm.
    for (std::size_t j = 0; j < n(); ++j) {
      if (j == i) continue;
      Seedling& o = seeds[j];
      if ((o.anchor - s.centre).norm() > o.reach_max + s.radius + p.pedicel_radius) continue;
      const Vec3 a = o.anchor, b = pedicel_end(o), ab = b - a;
      const double t = std::clamp((s.centre - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const Vec3 q = a + t * ab;
      const Vec3 off = s.centre - q;
      const double dist = off.norm(), need = s.radius + p.pedicel_radius + clearance;
      if (dist >= need || dist < 1e-12) continue;
      const Vec3 push = (need - dist) * off / dist;
      s.centre += 0.5 * push;
      if (t > 0.05) o.centre -= 0.5 * push / t;
    }
    // The main body stays behind a flat side's wall (a wing hangs apart from it).
    if (flat() && !s.on_wing) {
      const double beyond = s.centre.dot(bunch.flat_side_normal) + s.radius - bunch.flat_side_distance;
      if (beyond > 0) s.centre -= beyond * bunch.flat_side_normal;
    }
    enforce_rod(s, carrier_axis[i], min_pedicel_angle, settle ? 0.0 : 0.05);
  }

  void push_from_segment(Seedling& s, const Vec3& a, const Vec3& b, double need) const {
    const Vec3 ab = b - a;
    const double t = std::clamp((s.centre - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const Vec3 q = a + t * ab;
    Vec3 off = s.centre - q;
    const double dist = off.norm();
    if (dist >= need) return;
    if (dist < 1e-12) off = Vec3(0, 0, -1);
    s.centre = q + need * off.normalized();
  }

  // Remove what the packing left in a contact the exact volume does not allow.
  void remove_bad_contacts() {
    const auto pedicel_clear_of = [&](const Seedling& a, const Seedling& b) {
      return segment_segment_distance(a.anchor, pedicel_end(a), b.anchor, pedicel_end(b)) >= 2 * p.pedicel_radius;
    };
    for (std::size_t i = 0; i < n(); ++i) {
      Seedling& s = seeds[i];
      bool bad = false;
      for (std::size_t k = 0; k < skeleton && !bad; ++k) {
        const Stem& st = bunch.stems[k];
        bad = point_segment_distance(s.centre, st.start, st.end) < s.radius + st.radius;
        // The pedicel may only meet its carrier.
        if (!bad && static_cast<int>(k) != s.carrier) {
          bad = segment_segment_distance(s.anchor, pedicel_end(s), st.start, st.end) < p.pedicel_radius + st.radius;
        }
      }
      // Pressed further than allowed, or touching another kept berry's pedicel.
      for (std::size_t j = 0; j < i && !bad; ++j) {
        const Seedling& o = seeds[j];
        if (!o.alive) continue;
        const double depth = s.radius + o.radius - (s.centre - o.centre).norm();
        bad = depth > press * std::min(s.radius, o.radius) * (1 + 1e-6) + 1e-12 ||
              point_segment_distance(s.centre, o.anchor, pedicel_end(o)) < s.radius + p.pedicel_radius ||
              point_segment_distance(o.centre, s.anchor, pedicel_end(s)) < o.radius + p.pedicel_radius ||
              !pedicel_clear_of(s, o);
      }
      if (bad) {
        s.alive = false;
        ++removed;
      }
    }
  }

  // The kept berries, each on its pedicel.
  void attach_berries() {
    for (const auto& s : seeds) {
      if (!s.alive) continue;
      Berry b;
      b.centre = s.centre;
      b.radius = s.radius;
      b.colour = s.colour;
      b.pedicel = static_cast<int>(bunch.stems.size());
      Stem ped{s.anchor, pedicel_end(s), p.pedicel_radius, Part::Pedicel};
      ped.parent = s.carrier;
      ped.berry = static_cast<int>(bunch.berries.size());
      bunch.stems.push_back(ped);
      bunch.berries.push_back(b);
    }
  }

  const BunchParams& p;
  Rng rng;
  std::uint64_t seed_;
  Bunch bunch;
  int requested = 0, nb = 0, branches = 0, removed = 0;
  double L = 0, branch_scale = 1;
  const double press = p.compactness * p.max_press_depth;
  const double clearance = 0.1 * p.pedicel_radius;
  std::vector<double> heights;
  std::vector<int> segment;  // rachis segment per branch
  // The bend (draw_bend): its segment (-1: none), the node's depth, the bent part's
  // start and unit direction, and how far above the node it starts, m.
  int bend_segment = -1;
  double bend_depth = 0, bend_lift = 0;
  Vec3 bend_start = Vec3::Zero(), bend_dir = Vec3(0, 0, -1);
  std::vector<Carrier> carriers;
  std::vector<Seedling> seeds;
  std::vector<Vec3> carrier_axis;  // per seed, its carrier's unit axis
  std::size_t skeleton = 0;        // stems before the pedicels: peduncle, rachis, branches
};

}  // namespace

Bunch generate_bunch(const BunchParams& p, std::uint64_t seed, GenerationReport* report) {
  validate_bunch_params(p, "bunch parameters");
  const BunchParams q = oiv_compactness_params(p);
  if (p.oiv_compactness != 0) validate_bunch_params(q, "bunch parameters of oiv_compactness " + std::to_string(p.oiv_compactness));
  // A flat side, drawn from its own stream (as the wing), so a bunch without one is the
  // bunch its seed gives at probability 0. Its wall cuts `flat_side_depth` off the
  // round bunch's reach towards it: the same bunch packed without the wall first.
  if (q.flat_side_probability > 0) {
    Rng fr(derive_seed(seed, 0xf1a7));
    if (fr.uniform(0, 1) < q.flat_side_probability) {
      const double phi = fr.uniform(0, 2 * M_PI);
      const Vec3 normal(std::cos(phi), std::sin(phi), 0);
      Bunch round = BunchBuilder(q, seed).build(report);  // a flat build below overwrites the report
      double reach = 0;
      for (const Berry& b : round.berries) {
        if (!on_wing(round, b.pedicel)) reach = std::max(reach, b.centre.dot(normal) + b.radius);
      }
      if (reach > 0) return BunchBuilder(q, seed, normal, (1 - q.flat_side_depth) * reach).build(report);
      return round;  // no body to flatten: the round bunch is the bunch
    }
  }
  return BunchBuilder(q, seed).build(report);
}

std::vector<std::string> check_bunch(const Bunch& b) {
  std::vector<std::string> out;
  const int ns = static_cast<int>(b.stems.size());
  auto name = [&](int i) { return std::string(part_name(b.stems[i].part)) + " stem " + std::to_string(i); };
  for (int j = 0; j < ns; ++j) {
    const Stem& c = b.stems[j];
    if (c.parent >= 0) {
      const Stem& par = b.stems[c.parent];
      const Vec3 w = (par.end - par.start).normalized();
      const double plen = (par.end - par.start).norm();
      const Vec3 rel = c.start - par.start;
      const double axial = rel.dot(w), off = (rel - axial * w).norm();
      const Vec3 d = (c.end - c.start).normalized();
      const double reach = c.radius * std::sqrt(std::max(0.0, 1 - std::pow(d.dot(w), 2)));
      if (off > 1e-9 || c.radius >= par.radius || axial < reach || axial > plen - reach) {
        out.push_back(name(j) + " does not start inside its parent " + name(c.parent));
      }
    }
    if (c.stacked_on >= 0) {
      const Stem& below = b.stems[c.stacked_on];
      const Vec3 w0 = (below.end - below.start).normalized(), w1 = (c.end - c.start).normalized();
      if ((c.start - below.end).norm() > 1e-12 || w0.dot(w1) < 1 - 1e-12 || c.radius > below.radius) {
        out.push_back(name(j) + " is not stacked coaxially on " + name(c.stacked_on));
      }
    }
    for (int i = 0; i < j; ++i) {
      const Stem& a = b.stems[i];
      if (c.parent == i || a.parent == j || c.stacked_on == i || a.stacked_on == j) continue;
      if (segment_segment_distance(a.start, a.end, c.start, c.end) < a.radius + c.radius) {
        out.push_back(name(i) + " touches " + name(j));
      }
    }
  }
  for (int k = 0; k < static_cast<int>(b.berries.size()); ++k) {
    const Berry& be = b.berries[k];
    for (int i = 0; i < ns; ++i) {
      const Stem& s = b.stems[i];
      if (i == be.pedicel) {
        try {
          if (s.berry != k) throw InputError("pedicel does not name its berry");
          pedicel_in_berry_volume(s, be);
        } catch (const InputError&) {
          out.push_back("pedicel " + std::to_string(i) + " does not enter berry " + std::to_string(k) +
                        " as the volume formula requires");
        }
        continue;
      }
      if (point_segment_distance(be.centre, s.start, s.end) < be.radius + s.radius) {
        out.push_back(name(i) + " touches berry " + std::to_string(k));
      }
    }
  }
  return out;
}

bool on_wing(const Bunch& b, int index) {
  if (b.wing < 0) return false;
  // Parents come before their children, so the walk ends within stems.size() steps.
  for (std::size_t steps = 0; index >= 0 && steps <= b.stems.size(); ++steps) {
    if (index == b.wing) return true;
    index = b.stems[static_cast<std::size_t>(index)].parent;
  }
  return false;
}

std::string_view part_name(Part p) {
  switch (p) {
    case Part::Berry:
      return "berry";
    case Part::Pedicel:
      return "pedicel";
    case Part::Rachis:
      return "rachis";
    case Part::Peduncle:
      return "peduncle";
    case Part::Background:
      return "background";
    case Part::Leaf:
      return "leaf";
    case Part::Cane:
      return "cane";
    case Part::None:
      return "none";
  }
  return "unknown";
}

}  // namespace grapebench
