// The bunch's surface as one closed mesh: what a user loads into Open3D, MeshLab or
// a slicer and gets a watertight solid whose volume is the exact solid's.
//
// The boolean union (CGAL's corefinement, exact constructions) of every berry's
// icosphere and every stem's tube, a chain of coaxial rachis segments as one stepped
// tube. Each piece is scaled so its enclosed volume equals its solid's (icosphere
// radius x (4 pi / 3 / V_unit)^(1/3), tube radius x sqrt(2 pi / (n sin(2 pi / n)))),
// so the union's volume differs from the exact one only where pieces meet; that
// difference vanishes as the tessellation refines (measured: -0.001 % at the default,
// synth/README and tests/synth/union_mesh_test.cpp). Faces carry the part and berry of
// the nearest primitive surface.
#pragma once

#include "synth/mesh.h"

namespace grapebench {

// Closed, consistently oriented (outward), self-intersection-free; vertices in
// metres. Throws std::runtime_error if CGAL cannot build the union (not seen on any
// preset; the caller reports it).
TriMesh bunch_surface(const Bunch& bunch, const MeshOptions& options = {});

}  // namespace grapebench
