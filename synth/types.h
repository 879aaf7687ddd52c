// Core geometric types of a synthetic grape bunch. All lengths in metres, world
// frame z up; the bunch hangs along -z from the top of its rachis at the origin.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace grapebench {

using Vec3 = Eigen::Vector3d;

// Ground-truth label of a surface or point. Values are stable: they are written to
// PLY/OBJ/PCD files and scene outputs.
enum class Part : std::uint8_t {
  Berry = 0,
  Pedicel = 1,
  Rachis = 2,
  Peduncle = 3,
  Background = 4,  // scene elements added by sensors/ (plane, plate)
  Leaf = 5,        // vine-row scenes (synth/foliage.h)
  Cane = 6,
  None = 255,      // no return
};
inline constexpr std::array<Part, 4> kAllParts{Part::Berry, Part::Pedicel, Part::Rachis,
                                               Part::Peduncle};
std::string_view part_name(Part p);

struct Rgb {
  float r = 0, g = 0, b = 0;  // linear 0..1
};

struct Berry {
  Vec3 centre = Vec3::Zero();  // m
  double radius = 0;           // m
  Rgb colour;
  int pedicel = -1;  // index into Bunch::stems of the pedicel carrying this berry
};

// A straight cylinder from `start` to `end` with flat ends. A stem with a parent
// starts on the parent's axis, strictly inside the parent (the generator guarantees
// it), so the union's volume only needs the pairwise parent/child overlap.
struct Stem {
  Vec3 start = Vec3::Zero();  // m
  Vec3 end = Vec3::Zero();    // m
  double radius = 0;          // m
  Part part = Part::Rachis;
  int parent = -1;  // index into Bunch::stems; -1 for none
  int berry = -1;   // pedicels: the berry it carries (it ends inside that berry)
  // Rachis segments are stacked coaxially: a segment whose `stacked_on` is set
  // starts exactly on the end face of that segment (no overlap, no parent).
  int stacked_on = -1;
};

struct Bunch {
  std::vector<Berry> berries;
  std::vector<Stem> stems;
  Vec3 top = Vec3::Zero();                       // rachis top, on the peduncle axis
  Vec3 peduncle_direction = Vec3::UnitZ();       // unit, from the bunch up to the cane
  Vec3 cutting_point = Vec3::Zero();             // on the peduncle axis (seed 001)
  int peduncle = -1;                             // index of the peduncle stem
  // A wing: a lateral arm from the peduncle, apart from the main body (Tarter & Poni
  // 2010), carrying its own branches and berries; index of its axis stem, -1 for none.
  int wing = -1;
  // A bent main axis: the rachis segment that leaves its predecessor at an angle (a
  // child starting inside it, not stacked coaxially); -1 for a straight axis.
  int bend = -1;
  // A flat side: a vertical wall (a cane's) the main body's berries were packed against,
  // at `flat_side_distance` m from the rachis axis along the horizontal unit
  // `flat_side_normal` (bunch frame); distance 0 for none.
  Vec3 flat_side_normal = Vec3::Zero();
  double flat_side_distance = 0;
  Rgb stem_colour{0.42f, 0.45f, 0.18f};          // peduncle, rachis and pedicels
};

}  // namespace grapebench
