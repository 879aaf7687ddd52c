#include "synth/params.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace grapebench {

namespace {

using P = BunchParams;

}  // namespace

const ParamTable<BunchParams>& bunch_param_table() {
  static const ParamTable<BunchParams> table = ParamTable<BunchParams>()
      .integer("berry_count_min", "count", &P::berry_count_min, 1, 1000,
               "fewest berries drawn for a bunch (uniform in [min, max]; packing may drop a few, reported in the JSON)")
      .integer("berry_count_max", "count", &P::berry_count_max, 1, 1000,
               "most berries drawn for a bunch")
      .real("berry_radius_mean", "m", &P::berry_radius_mean, 0.002, 0.02,
            "mean berry radius (normal draw)")
      .real("berry_radius_sd", "m", &P::berry_radius_sd, 0, 0.005,
            "berry radius standard deviation")
      .real("berry_radius_min", "m", &P::berry_radius_min, 0.002, 0.02,
            "berry radii clamped below")
      .real("berry_radius_max", "m", &P::berry_radius_max, 0.002, 0.02,
            "berry radii clamped above")
      .real("compactness", "-", &P::compactness, 0, 1,
            "0 loose (berries hang free) .. 1 compact (pulled to the axis and pressed)")
      .real("max_press_depth", "-", &P::max_press_depth, 0, 0.3,
            "largest overlap depth of two pressed berries over the smaller radius, at compactness 1")
      .real("pull_strength", "1/step", &P::pull_strength, 0, 0.1,
            "share of a berry's horizontal distance to the axis (a wing's berries: to the wing's axis) pulled in "
            "per packing step at compactness 1, fading to 0 (0.015 keeps every preset's drop rate at 0.2-5 %, "
            "docs/synth.md)")
      .integer("oiv_compactness", "class", &P::oiv_compactness, 0, 9,
               "OIV 204 bunch compactness class, 1 very loose .. 9 very dense (berries pressed flat); 0 = off. "
               "Overrides compactness, pull_strength, max_press_depth and pedicel_stretch given beside it, and "
               "scales the berry count, branch and pedicel lengths: the drivers of Tello et al. 2015 (docs/synth.md)")
      .real("rachis_length_min", "m", &P::rachis_length_min, 0.03, 0.4,
            "shortest main rachis (uniform in [min, max])")
      .real("rachis_length_max", "m", &P::rachis_length_max, 0.03, 0.4,
            "longest main rachis")
      .real("rachis_radius_top", "m", &P::rachis_radius_top, 0.0005, 0.008,
            "rachis radius at the top (tapers linearly)")
      .real("rachis_radius_bottom", "m", &P::rachis_radius_bottom, 0.0003, 0.008,
            "rachis radius at the tip")
      .real("rachis_bare_length", "m", &P::rachis_bare_length, 0.005, 0.15,
            "top part of the rachis without branches")
      .real("branch_spacing", "m", &P::branch_spacing, 0.003, 0.05,
            "distance between lateral branches along the rachis")
      .real("branch_length_top", "m", &P::branch_length_top, 0.002, 0.2,
            "length of the top lateral branch (shoulder)")
      .real("branch_length_bottom", "m", &P::branch_length_bottom, 0.002, 0.2,
            "length of the lowest lateral branch (linear in between)")
      .real("branch_angle", "deg", &P::branch_angle, 15, 85,
            "angle of the lateral branches from the downward vertical (the rachis axis, unless it is bent)")
      .real("branch_radius", "m", &P::branch_radius, 0.0002, 0.005,
            "lateral branch radius")
      .real("pedicel_length_mean", "m", &P::pedicel_length_mean, 0.001, 0.03,
            "mean pedicel length outside the berry")
      .real("pedicel_length_sd", "m", &P::pedicel_length_sd, 0, 0.01,
            "pedicel length sd")
      .real("pedicel_radius", "m", &P::pedicel_radius, 0.0001, 0.003,
            "pedicel radius")
      .real("pedicel_stretch", "-", &P::pedicel_stretch, 1, 5,
            "a crowded berry's pedicel may lengthen up to this factor of its drawn length")
      .real("peduncle_length", "m", &P::peduncle_length, 0.005, 0.15,
            "peduncle length from the rachis top to the cane")
      .real("peduncle_radius", "m", &P::peduncle_radius, 0.0005, 0.01,
            "peduncle radius")
      .real("peduncle_angle", "deg", &P::peduncle_angle, 0, 75,
            "peduncle angle from vertical (random azimuth)")
      .real("cutting_point_fraction", "-", &P::cutting_point_fraction, 0.05, 0.95,
            "cutting point along the peduncle from the bunch top (seed 001)")
      .real("wing_probability", "-", &P::wing_probability, 0, 1,
            "chance a bunch has a wing: a lateral arm from the peduncle, apart from the main body, with its own "
            "branches and berries (Tarter & Poni 2010, HortScience 45:1270); drawn from its own stream, so a "
            "bunch without a wing is the one its seed gives at 0")
      .real("wing_share", "-", &P::wing_share, 0.05, 0.5,
            "share of the bunch's berries on the wing (no published share was found; 0.15 is a choice)")
      .real("wing_length", "m", &P::wing_length, 0.02, 0.2,
            "length of the wing's axis, drawn within +-15 % (a choice: 0.1 m reaches past table-red's top "
            "branches, so the wing stands apart from the body)")
      .real("flat_side_probability", "-", &P::flat_side_probability, 0, 1,
            "chance a bunch has a flat side: it grew pressed against a cane or wire, a vertical wall its "
            "body's berries and branches stay behind (no published frequency was found: 0 by default); drawn "
            "from its own stream, so a bunch without one is the one its seed gives at 0")
      .real("flat_side_depth", "-", &P::flat_side_depth, 0.05, 0.6,
            "how much the flat side cuts off: at a random azimuth, the wall stands at (1 - depth) of the round "
            "bunch's reach that way (the same seed packed without the wall, which doubles the bunch's "
            "generation time) from the rachis axis (0.3 is a choice; no published measure was found)")
      .real("bend_probability", "-", &P::bend_probability, 0, 1,
            "chance a bunch's main axis bends once: the rachis below a segment boundary (halfway between two "
            "branches) in its lower two thirds leaves the part above at bend_angle, a knee joint, with the "
            "branches below starting on it (a rachis of one segment stays straight; no published frequency was "
            "found: 0 by default); drawn from its own stream, so a bunch without a bend is the one its seed "
            "gives at 0")
      .real("bend_angle", "deg", &P::bend_angle, 2, 45,
            "the bend's angle between the two parts of the main axis, drawn within +-25 % at a random "
            "azimuth (20 deg is a choice; no published measure was found)")
      .rgb("berry_colour", &P::berry_colour, "mean berry colour")
      .real("colour_variation", "-", &P::colour_variation, 0, 0.3,
            "sd of the per-berry colour jitter")
      .rgb("stem_colour", &P::stem_colour, "colour of peduncle, rachis and pedicels")
      .real("density", "g/cm3", &P::density, 0.5, 2,
            "bunch density for the mass")
      .integer("relax_iterations", "count", &P::relax_iterations, 0, 5000,
               "packing relaxation steps (0 = berries where first placed)")
      .validate([](const BunchParams& p, const ConfigNode& n) { validate_bunch_params(p, n.where()); });
  return table;
}

const std::vector<std::string>& preset_names() {
  // The first four keep the figures and baselines measured on them; the variety presets
  // after them are built from published descriptions (docs/synth.md, "Variety presets").
  static const std::vector<std::string> names = {"table-red", "wine-red", "summer-black", "green-table",
                                                 "red-globe", "cabernet-sauvignon", "summer-black-ga",
                                                 "italia"};
  return names;
}

BunchParams preset(const std::string& name) {
  BunchParams p;  // table-red: Red Globe-like, seed 000 (583-863 cm3)
  if (name == "table-red") return p;
  if (name == "wine-red") {
    // Wine grapes: berries 12-16 mm across, 60-150 per bunch, compact.
    p.berry_count_min = 60;
    p.berry_count_max = 150;
    p.berry_radius_mean = 0.007;
    p.berry_radius_sd = 0.0005;
    p.berry_radius_min = 0.006;
    p.berry_radius_max = 0.008;
    p.compactness = 0.8;
    p.max_press_depth = 0.15;
    p.rachis_length_min = 0.09;
    p.rachis_length_max = 0.17;
    p.rachis_radius_top = 0.002;
    p.rachis_radius_bottom = 0.001;
    p.rachis_bare_length = 0.015;
    p.branch_spacing = 0.008;
    p.branch_length_top = 0.045;
    p.branch_length_bottom = 0.010;
    p.branch_radius = 0.0008;
    p.pedicel_length_mean = 0.005;
    p.pedicel_length_sd = 0.001;
    p.pedicel_radius = 0.0005;
    p.peduncle_length = 0.03;
    p.peduncle_radius = 0.0025;
    p.berry_colour = {0.10f, 0.04f, 0.14f};
    p.colour_variation = 0.05;
    return p;
  }
  if (name == "summer-black") {
    // Summer Black: large near-black berries (20-24 mm), loose to medium bunches.
    p.berry_count_min = 60;
    p.berry_count_max = 100;
    p.berry_radius_mean = 0.0105;
    p.berry_radius_sd = 0.0007;
    p.berry_radius_min = 0.009;
    p.berry_radius_max = 0.012;
    p.compactness = 0.5;
    p.rachis_length_min = 0.15;
    p.rachis_length_max = 0.21;
    p.branch_length_top = 0.08;
    p.berry_colour = {0.07f, 0.04f, 0.09f};
    p.colour_variation = 0.04;
    return p;
  }
  if (name == "green-table") {
    // Green table grape (Italia / Thompson-like): 16-20 mm berries, 80-140 per bunch.
    p.berry_count_min = 80;
    p.berry_count_max = 140;
    p.berry_radius_mean = 0.009;
    p.berry_radius_sd = 0.0006;
    p.berry_radius_min = 0.0078;
    p.berry_radius_max = 0.0102;
    p.compactness = 0.5;
    p.rachis_length_min = 0.16;
    p.rachis_length_max = 0.24;
    p.branch_length_top = 0.075;
    p.pedicel_length_mean = 0.009;
    p.berry_colour = {0.55f, 0.68f, 0.28f};
    p.colour_variation = 0.06;
    return p;
  }
  // Variety presets: each legacy preset's skeleton with the sourced berry size, berry count
  // (the bunch mass over the berry mass, at `density`), OIV 204 class and wings. The sources
  // are nursery, trade and encyclopedia pages unless marked; docs/synth.md lists them with
  // quotes and the generated bunches measured against them. Wings: 1 where the variety's
  // descriptions call it winged, 0.5 where "often" or where they disagree, 0 where none do.
  if (name == "red-globe") {
    p = preset("table-red");
    p.berry_radius_mean = 0.01175;  // 22-25 mm across (kisansuvidha.com): 7.5 g
    p.berry_radius_sd = 0.0004;
    p.berry_radius_min = 0.011;
    p.berry_radius_max = 0.0125;
    p.berry_count_min = 85;  // 650-850 g a bunch (zk71.com, hotelwarning.com; 700-800 g salepepe.com)
    p.berry_count_max = 115;
    p.oiv_compactness = 5;     // "medium compactness" (queenfrut.cl), "neither loose nor tight"
    p.wing_probability = 0.5;  // "coniques, ailees" (3perf.fr); no wing in three trade descriptions
    return p;
  }
  if (name == "cabernet-sauvignon") {
    p = preset("wine-red");
    p.berry_radius_mean = 0.0064;  // 1.2 g (0.8-1.4 g in four descriptions)
    p.berry_radius_sd = 0.0005;
    p.berry_radius_min = 0.0051;  // 0.6-1.8 g, measured (Calderon-Orellana et al. 2014, AJEV 65:81)
    p.berry_radius_max = 0.0073;
    p.berry_count_min = 60;  // 73-157 g a bunch (denovaagro.com; AJEV yield / clusters)
    p.berry_count_max = 120;
    p.oiv_compactness = 5;     // OIV 204 = 5 (Barre et al. 2018, arXiv:1807.07343)
    p.wing_probability = 0.5;  // "often winged" (bestwine.bg), "one to three wings" (OeWM)
    p.wing_length = 0.06;      // the bunch is 7-8 cm wide (denovaagro.com)
    p.rachis_length_min = 0.09;  // the bunch 12-15 cm long (denovaagro.com)
    p.rachis_length_max = 0.13;
    return p;
  }
  if (name == "summer-black-ga") {
    p = preset("summer-black");
    p.berry_radius_mean = 0.01176;  // 7.5 g after gibberellin (7-8 g, MAFF 1997 breeder's record)
    p.berry_radius_sd = 0.0005;
    p.berry_radius_min = 0.0109;  // 6-10 g
    p.berry_radius_max = 0.01295;
    p.berry_count_min = 65;  // 608 g a bunch after gibberellin, at most 940 (Chinese encyclopedia)
    p.berry_count_max = 100;
    p.oiv_compactness = 7;    // gibberellin-grown: berries "set tight or very tight" (victorzhang.cn)
    p.wing_probability = 0;   // "mostly conical, some double-shouldered, no secondary bunch"
    return p;
  }
  if (name == "italia") {
    p = preset("green-table");
    p.berry_radius_mean = 0.0115;  // 7 g (5-7 g; 8 g de.wikipedia); oval 18-24 x 28-36 mm, as a sphere
    p.berry_radius_sd = 0.0006;
    p.berry_radius_min = 0.0103;  // 5 g
    p.berry_radius_max = 0.013;
    p.berry_count_min = 70;  // 400-700 g a bunch, 627 g mean (de.wikipedia)
    p.berry_count_max = 105;
    p.oiv_compactness = 3;     // "loose" (de.wikipedia), "giustamente spargolo" (vivaisommadossi.it)
    p.wing_probability = 1;    // "alato con una o due ali" (vivaisommadossi.it, gliorticelli.com)
    p.rachis_length_min = 0.12;  // the bunch 20-22 cm long (gardengrove), 20 cm (gliorticelli.com)
    p.rachis_length_max = 0.18;
    return p;
  }
  std::string list;
  for (const auto& n : preset_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown preset '" + name + "'; allowed: " + list);
}

BunchParams oiv_compactness_params(const BunchParams& p) {
  if (p.oiv_compactness == 0) return p;
  // s runs 0 (class 1) .. 1 (class 9). Compactness grows with the berries per bunch
  // and falls with the first ramification's length, its two main drivers, pedicel
  // length secondary (Tello et al. 2015, Aust. J. Grape Wine Res. 21:277; Tello &
  // Ibanez 2014, Vitis 53:9, indexes CI-18/19). No per-class figures were found
  // published, so the factors are chosen to span the generator's range and the result
  // is measured per class (docs/synth.md). Above class 5 the skeleton stays the
  // variety's: 30 % shorter branches or 15 % more berries made the packing drop 19-33 %
  // of table-red's berries (measured, docs/synth.md), so classes 6-9 tighten by pull,
  // pressing and pedicel stretch alone; class 9's are the densest it places (5 % dropped).
  const double s = (p.oiv_compactness - 1) / 8.0, loose = std::max(0.0, 0.5 - s);
  BunchParams q = p;
  q.compactness = s;
  q.pull_strength = 0.015 + 0.025 * s * s;
  q.max_press_depth = 0.3 * s;  // class 9: contacts flattened to 0.3 of the smaller radius
  q.pedicel_stretch = 2.5 + 1.5 * s;
  const double count = 1 - 0.3 * loose, branch = 1 + 0.6 * loose, pedicel = 1 + 0.4 * loose;
  const auto scaled_count = [&](int n) { return std::clamp(static_cast<int>(std::lround(n * count)), 1, 1000); };
  q.berry_count_min = scaled_count(p.berry_count_min);
  q.berry_count_max = scaled_count(p.berry_count_max);
  q.branch_length_top = std::clamp(p.branch_length_top * branch, 0.002, 0.2);
  q.branch_length_bottom = std::clamp(p.branch_length_bottom * branch, 0.002, 0.2);
  q.pedicel_length_mean = std::clamp(p.pedicel_length_mean * pedicel, 0.001, 0.03);
  q.pedicel_length_sd = std::min(p.pedicel_length_sd * pedicel, 0.01);
  return q;
}

void read_bunch_params(const ConfigNode& node, BunchParams& p) { bunch_param_table().read(node, p); }

void validate_bunch_params(const BunchParams& p, const std::string& where) {
  auto need = [&](bool ok, const std::string& msg) {
    if (!ok) throw InputError(where + ": " + msg);
  };
  // Ranges too: the generator is also called with parameters set in code.
  for (const auto& k : bunch_param_table().keys(p)) {
    need(k.default_in_range, "'" + k.key + "' = " + k.default_value + " is outside the allowed range " + k.range);
  }
  need(p.berry_count_min <= p.berry_count_max,
       "berry_count_min must not exceed berry_count_max");
  need(p.berry_radius_min <= p.berry_radius_max,
       "berry_radius_min must not exceed berry_radius_max");
  need(p.rachis_length_min <= p.rachis_length_max,
       "rachis_length_min must not exceed rachis_length_max");
  need(p.rachis_radius_bottom <= p.rachis_radius_top,
       "rachis_radius_bottom must not exceed rachis_radius_top");
  need(p.rachis_radius_top < p.peduncle_radius,
       "rachis_radius_top must be below peduncle_radius (the rachis starts inside the peduncle)");
  need(p.branch_radius < p.rachis_radius_bottom,
       "branch_radius must be below rachis_radius_bottom (branches start inside the rachis)");
  need(p.pedicel_radius < p.branch_radius,
       "pedicel_radius must be below branch_radius (pedicels start inside their branch)");
  need(p.pedicel_radius < 0.4 * p.berry_radius_min,
       "pedicel_radius must be below 0.4 * berry_radius_min (a pedicel enters one berry only)");
  need(p.rachis_bare_length + p.branch_spacing < p.rachis_length_min,
       "rachis_bare_length + branch_spacing must be below rachis_length_min");
  need(p.peduncle_length > 2 * p.peduncle_radius,
       "peduncle_length must exceed twice peduncle_radius");
  need(p.bend_probability == 0 || p.rachis_radius_bottom < p.rachis_radius_top,
       "bend_probability above 0 needs rachis_radius_bottom below rachis_radius_top (the bent part starts inside "
       "the part above it, so it must be thinner)");
}

void set_bunch_param(BunchParams& p, const std::string& key, const std::string& value) {
  const auto node = ConfigNode::load_string(key + ": " + value, "--set " + key);
  bool known = false;
  for (const auto& k : bunch_param_table().keys(p)) known = known || k.key == key;
  if (!known) throw InputError("--set: unknown parameter '" + key + "' (see grapebench synth --help)");
  read_bunch_params(node, p);
}

}  // namespace grapebench
