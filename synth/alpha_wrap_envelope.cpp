#include "synth/alpha_wrap_envelope.h"

#include "synth/config.h"
#include "synth/mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include <array>
#include <string>
#include <vector>

namespace grapebench {

AlphaWrapEnvelope alpha_wrap_envelope(const Bunch& bunch, double alpha, double offset) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  if (!(alpha >= 5e-4 && alpha <= 0.05)) {
    throw InputError("alpha wrap: alpha " + std::to_string(alpha) + " m is outside [0.0005, 0.05]");
  }
  if (!(offset >= alpha / 1000 && offset <= alpha / 5)) {
    throw InputError("alpha wrap: offset " + std::to_string(offset) + " m is outside [alpha / 1000, alpha / 5]");
  }
  if (bunch.berries.empty()) throw InputError("alpha wrap: the bunch has no berries");
  MeshOptions options;
  options.sphere_subdivisions = 3;
  options.tube_sides = 24;
  const TriMesh mesh = bunch_mesh(bunch, options);
  std::vector<Kernel::Point_3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::array<std::size_t, 3>> faces;
  faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    faces.push_back({static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]), static_cast<std::size_t>(f[2])});
  }
  CGAL::Surface_mesh<Kernel::Point_3> wrap;
  CGAL::alpha_wrap_3(points, faces, alpha, offset, wrap);
  AlphaWrapEnvelope e;
  e.alpha = alpha;
  e.offset = offset;
  e.faces = static_cast<int>(wrap.number_of_faces());
  e.wrap_volume = CGAL::Polygon_mesh_processing::volume(wrap);
  e.area = CGAL::Polygon_mesh_processing::area(wrap);
  e.volume = e.wrap_volume - e.area * offset;
  return e;
}

}  // namespace grapebench
