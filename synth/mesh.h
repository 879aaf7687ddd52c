// Triangle mesh of a bunch with per-face labels, and its PLY / OBJ export.
//
// The solid is split into disjoint closed pieces: each berry clipped by its power
// cell and by the plane where its pedicel enters; each stem minus its parent (its
// start surface lies on the parent's surface); so the enclosed volume of the mesh
// (all pieces, internal faces included) converges to the analytic volume as the
// tessellation is refined. Faces that lie inside the solid (piece boundaries) are
// flagged and left out of the exported files.
#pragma once

#include "synth/types.h"

#include <array>
#include <string>
#include <vector>

namespace grapebench {

struct TriMesh {
  std::vector<Vec3> vertices;              // m
  std::vector<std::array<int, 3>> faces;   // counter-clockwise seen from outside
  std::vector<Part> face_part;
  std::vector<int> face_berry;             // berry id, -1 for stems
  std::vector<unsigned char> face_internal;  // 1: inside the solid, not exported
};

struct MeshOptions {
  int sphere_subdivisions = 2;  // icosphere level: 20 * 4^level triangles per berry, 0..6
  int tube_sides = 12;          // sides of a stem tube, 3..256
};

TriMesh bunch_mesh(const Bunch& bunch, const MeshOptions& options = {});
// The unit icosphere: 12 vertices of the icosahedron, each level splitting every
// triangle in four with midpoints pushed onto the sphere; faces counter-clockwise
// seen from outside.
void unit_icosphere(int level, std::vector<Vec3>& vertices, std::vector<std::array<int, 3>>& faces);
// Enclosed volume of the closed pieces (signed tetrahedra), m3.
double enclosed_volume(const TriMesh& mesh);
// Colour of a face label: berries a distinct hue per id, stems one per part.
Rgb label_colour(Part part, int berry);

// The faces the files export (internal ones dropped) and the vertices they use,
// renumbered densely in order of first use, as ply_bytes and obj_text write them.
struct Exported {
  std::vector<int> faces;        // indices into mesh.faces
  std::vector<int> vertex_map;   // old -> new, -1 unused
  std::vector<int> vertices;     // new -> old
  std::vector<Rgb> vertex_colour;  // new: the label colour of the first face using it
};
Exported exported(const TriMesh& mesh);

// Binary little-endian PLY: vertex x y z (double) + label colour; face indices,
// label colour, `part` (uchar) and `berry` (int). Exported faces only.
std::string ply_bytes(const TriMesh& mesh);
// Wavefront OBJ with one material per part (label colours) and a group per piece;
// `mtl_name` is the material library file written beside it by obj_material_library().
std::string obj_text(const TriMesh& mesh, const std::string& mtl_name);
std::string obj_material_library();

}  // namespace grapebench
