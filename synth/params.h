// Parameters of the bunch generator and the variety presets. One table
// (bunch_param_table) documents every parameter with unit, range and meaning; it
// drives the scene-file reader, `grapebench synth --help` and the JSON manifest,
// so the three can never disagree.
#pragma once

#include "synth/config.h"
#include "synth/param_table.h"
#include "synth/types.h"

#include <string>
#include <string_view>
#include <vector>

namespace grapebench {

// Defaults are the table-red preset (seed 000's red table grapes). Lengths in metres.
struct BunchParams {
  // Berries. Seed 000: 16 red table-grape bunches of 583-863 cm3 true volume.
  int berry_count_min = 100;
  int berry_count_max = 135;
  double berry_radius_mean = 0.0115;  // m
  double berry_radius_sd = 0.0008;    // m
  double berry_radius_min = 0.0095;   // m, draws are clamped to [min, max]
  double berry_radius_max = 0.0135;   // m
  double compactness = 0.6;           // 0 loose .. 1 compact
  double max_press_depth = 0.12;      // overlap depth / smaller radius, at compactness 1
  double pull_strength = 0.015;       // share of the distance to the axis pulled per step, at compactness 1
  // OIV descriptor 204 class, 1 (very loose) .. 9 (very dense); 0 = off. A class sets
  // the drivers above and below from the variety's values (oiv_compactness_params).
  int oiv_compactness = 0;
  // Rachis: a tapering main axis hanging from the peduncle (straight unless bent).
  double rachis_length_min = 0.17;  // m
  double rachis_length_max = 0.25;  // m
  double rachis_radius_top = 0.0028;     // m
  double rachis_radius_bottom = 0.0013;  // m
  double rachis_bare_length = 0.025;     // m, top part without branches
  // Lateral branches (shoulders at the top), shorter down the bunch.
  double branch_spacing = 0.014;        // m along the rachis
  double branch_length_top = 0.085;     // m
  double branch_length_bottom = 0.015;  // m
  double branch_angle = 55;             // deg from the downward rachis axis
  double branch_radius = 0.0011;        // m
  // Pedicels.
  double pedicel_length_mean = 0.010;  // m, outside the berry
  double pedicel_length_sd = 0.002;    // m
  double pedicel_radius = 0.0008;      // m
  double pedicel_stretch = 2.5;        // longest pedicel / its drawn length, when packing needs room
  // Peduncle, from the rachis top up to the cane.
  double peduncle_length = 0.045;          // m
  double peduncle_radius = 0.0035;         // m
  double peduncle_angle = 20;              // deg from vertical
  double cutting_point_fraction = 0.5;     // along the peduncle from the bunch top
  // Wing: a lateral arm from the peduncle with its own berries (off by default).
  double wing_probability = 0;  // chance a bunch has a wing
  double wing_share = 0.15;     // share of the bunch's berries on the wing
  double wing_length = 0.10;    // m, the wing's axis
  // Flat side: the bunch grew against a cane or wire (off by default).
  double flat_side_probability = 0;  // chance a bunch has one
  double flat_side_depth = 0.3;      // share of the round bunch's reach towards the wall cut off
  // Bent main axis: the rachis turns once, at a segment boundary (off by default).
  double bend_probability = 0;  // chance a bunch's main axis bends
  double bend_angle = 20;       // deg, the turn between the two parts, drawn within +-25 %
  // Appearance and mass.
  Rgb berry_colour{0.45f, 0.06f, 0.10f};
  double colour_variation = 0.08;  // sd of per-berry colour jitter
  Rgb stem_colour{0.42f, 0.45f, 0.18f};
  double density = 1.1;  // g/cm3
  // Packing relaxation.
  int relax_iterations = 150;
};

// The key table of every bunch parameter (scene keys under `bunches:`).
const ParamTable<BunchParams>& bunch_param_table();

const std::vector<std::string>& preset_names();
// Throws InputError naming the allowed presets.
BunchParams preset(const std::string& name);

// The parameters a bunch is generated with: `p` itself when oiv_compactness is 0,
// else p with the class's drivers set (docs/synth.md, "Compactness classes"):
// compactness, pull_strength, max_press_depth and pedicel_stretch, and the variety's
// berry count, first-ramification (branch) and pedicel lengths scaled.
BunchParams oiv_compactness_params(const BunchParams& p);

// Reads overrides of any parameter from `node` (keys as in the spec table); range
// errors name file:line and key. Then checks the cross-field rules.
void read_bunch_params(const ConfigNode& node, BunchParams& p);
// Cross-field rules (radius ordering, min <= max...); `where` prefixes messages.
void validate_bunch_params(const BunchParams& p, const std::string& where);
// Sets one parameter from text ("key=value" on the command line).
void set_bunch_param(BunchParams& p, const std::string& key, const std::string& value);

}  // namespace grapebench
