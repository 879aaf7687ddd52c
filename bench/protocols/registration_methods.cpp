#include "bench/protocols/registration_methods.h"

#include "synth/rng.h"

#include <cmath>

namespace grapebench {

namespace {

struct TruePosesParams {};

struct PlainIcpParams {
  IcpParams icp;
};

struct Seed000Params {
  IcpParams icp;
  int group_size = 3;                  // views per group (seed 000: 3)
  PcaSign pca_sign = PcaSign::nearest;  // seed 000 does not say how the axes get their signs
};

struct KnownAngleParams {
  IcpParams icp;
  double bottom_band = 0.03;       // m, the lowest band the bottom view is aligned on (seed 002: 30 mm)
  double angle_error_sd_deg = 0;   // deg, the turntable's positioning error, seeded
};

template <class P>
ParamTable<P> with_icp() {
  return ParamTable<P>().section("icp", &P::icp, icp_param_table(), "ICP settings");
}

Eigen::Isometry3d rotation_about_vertical(const Vec3& centre, double angle_rad) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle_rad, Vec3::UnitZ()).toRotationMatrix();
  t.translation() = centre - t.linear() * centre;
  return t;
}

template <class P, class Run>
RegistryEntry<RegistrationMethod> method(std::string type, std::string summary, ParamTable<P> table, Run run) {
  return entry<RegistrationMethod>(std::move(type), std::move(summary), std::move(table), P{},
                                   [run](const P& p, const ConfigNode&) {
                                     return RegistrationMethod(
                                         [p, run](std::vector<RegistrationView>& views, const RegistrationContext& c) {
                                           return run(p, views, c);
                                         });
                                   });
}

RegistrationOutcome estimated(RegistrationResult r) { return {std::move(r.poses), true}; }

}  // namespace

const Registry<RegistrationMethod>& registration_registry() {
  static const Registry<RegistrationMethod> registry(
      "registration method",
      {
          method("true_poses", "the rig's calibrated poses: no registration error, the estimators scored alone",
                 ParamTable<TruePosesParams>(),
                 [](const TruePosesParams&, std::vector<RegistrationView>&, const RegistrationContext& c) {
                   return RegistrationOutcome{c.rig_poses, false};
                 }),
          method("seed000_pca_icp", "views in groups, PCA coarse alignment then ICP (seed 000)",
                 with_icp<Seed000Params>()
                     .integer("group_size", "count", &Seed000Params::group_size, 1, 360, "views per group (seed 000: 3)")
                     .choice("pca_sign", &Seed000Params::pca_sign, {{"nearest", PcaSign::nearest}, {"skew", PcaSign::skew}},
                             "the axes' signs, which seed 000 leaves open: nearest, the rotation closest to the "
                             "identity (never past 120 deg; a half turn about an axis comes back as none); skew, "
                             "towards the side holding more of the squared projections (Bro, Acar & Kolda 2008)"),
                 [](const Seed000Params& p, std::vector<RegistrationView>& views, const RegistrationContext&) {
                   return estimated(register_seed000(views, p.icp, p.group_size, p.pca_sign));
                 }),
          method("known_angle_icp", "known turntable angles then ICP; the bottom view on the lowest band (seed 002 Eqs. 1-4)",
                 with_icp<KnownAngleParams>()
                     .real("bottom_band", "m", &KnownAngleParams::bottom_band, 0.001, 0.5,
                           "lowest band the bottom view is aligned on (seed 002 Eqs. 3-4: 30 mm)")
                     .real("angle_error_sd_deg", "deg", &KnownAngleParams::angle_error_sd_deg, 0, 45,
                           "turntable positioning error, seeded"),
                 [](const KnownAngleParams& p, std::vector<RegistrationView>& views, const RegistrationContext& c) {
                   // Known turntable angles about a calibrated axis; a seeded angle error
                   // stands for the turntable's positioning error.
                   const Eigen::Isometry3d t0_inv = c.rig_poses.front().inverse();
                   Rng rng(derive_seed(c.seed, 0xa11e));
                   for (std::size_t k = 1; k < views.size(); ++k) {
                     const double err = p.angle_error_sd_deg * rng.normal() * M_PI / 180;
                     views[k].nominal = t0_inv * rotation_about_vertical(c.axis_point, err) * c.rig_poses[k];
                   }
                   return estimated(register_known_angle(views, t0_inv.linear() * Vec3::UnitZ(), p.icp, p.bottom_band));
                 }),
          method("plain_icp", "every view ICP'd from the identity onto the merged cloud so far (the papers' baseline)",
                 with_icp<PlainIcpParams>(),
                 [](const PlainIcpParams& p, std::vector<RegistrationView>& views, const RegistrationContext&) {
                   return estimated(register_plain_icp(views, p.icp));
                 }),
      });
  return registry;
}

}  // namespace grapebench
