#include "synth/io.h"

#include <atomic>

#include "synth/utf8.h"

#include <unistd.h>

#include <fstream>
#include <set>
#include <stdexcept>
#include <vector>

#include "synth/config.h"
#include "synth/process_end.h"

namespace grapebench {

void write_file_atomic(const std::filesystem::path& path, std::string_view bytes) {
  wait_here_if_ending();  // what fails during a stop on a signal is not stored
  // Unique per call, not only per process: two threads writing one path (two cases
  // storing the same render in the cache) would share a pid-named temp file, and the
  // slower one's rename would fail (or the file hold the other's half-written bytes).
  static std::atomic<std::uint64_t> calls{0};
  const auto tmp = path.string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(++calls);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path.string() + ": cannot open for writing");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::filesystem::remove(tmp);
      throw InputError(path.string() + ": write failed (disk full?)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw InputError(path.string() + ": cannot move into place: " + ec.message());
  }
}

nlohmann::json parse_json_bounded(std::string_view text, int max_depth) {
  if (const std::size_t at = invalid_utf8_at(text); at != std::string_view::npos)
    throw std::runtime_error("not UTF-8 at byte " + std::to_string(at));
  // A cheap pre-pass: brackets outside strings (the parser's callback would build the
  // deep value before it could refuse it).
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) throw std::runtime_error("nested deeper than " + std::to_string(max_depth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  // Duplicate keys refused (nlohmann keeps the last: a baseline with a key twice
  // passed on the second's value).
  std::vector<std::set<std::string>> keys;
  const auto refuse_duplicates = [&keys](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if (event == E::object_start) keys.emplace_back();
    if (event == E::object_end && !keys.empty()) keys.pop_back();
    if (event == E::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
      throw std::runtime_error("the key '" + parsed.get<std::string>() + "' is given twice in one object");
    return true;
  };
  return nlohmann::json::parse(text, refuse_duplicates);
}

namespace {
nlohmann::json vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json rgb(const Rgb& c) { return {c.r, c.g, c.b}; }
}  // namespace

nlohmann::ordered_json params_json(const BunchParams& p) { return bunch_param_table().to_json(p); }

nlohmann::ordered_json ground_truth_json(const Bunch& b, const GroundTruth& g, const BunchRecord& r) {
  nlohmann::ordered_json j;
  j["format"] = "grapebench-ground-truth/1";
  j["units"] = {{"length", "m"},
                {"volume", "m3 (and cm3 where named)"},
                {"mass", "g"},
                {"frame", "world, z up; the rachis top at the origin"}};
  j["preset"] = r.preset;
  j["index"] = r.index;
  j["seed"] = r.seed;
  j["parameters"] = params_json(r.params);
  j["generation"] = {{"berries_requested", r.report.berries_requested},
                     {"berries_removed_by_packing", r.report.berries_removed},
                     {"rachis_length_m", r.report.rachis_length},
                     {"lateral_branches", r.report.branches}};
  if (r.params.oiv_compactness != 0) j["generation"]["parameters_of_the_oiv_class"] = params_json(oiv_compactness_params(r.params));
  j["solid_volume_m3"] = g.volume.solid;
  j["solid_volume_cm3"] = g.volume.solid * 1e6;
  j["volume_terms_m3"] = {{"berries_union", g.volume.berries_union},
                          {"berries_sum", g.volume.berries_sum},
                          {"stems", g.volume.stems},
                          {"junction_overlap", g.volume.junction_overlap},
                          {"pedicel_in_berry", g.volume.pedicel_in_berry},
                          {"formula", "berries_union + stems - junction_overlap - pedicel_in_berry"}};
  j["density_g_cm3"] = g.density;
  j["mass_g"] = g.mass;
  j["berry_count"] = g.berry_count;
  j["pca_frame"] = {
      {"definition", "principal axes of the berries as solid balls; extents of the bunch without peduncle"},
      {"centre_m", vec(g.pca_centre)},
      {"axes", {vec(g.pca_axes.col(0)), vec(g.pca_axes.col(1)), vec(g.pca_axes.col(2))}},
      {"extent_m", vec(g.pca_extent)},
      {"height_m", g.pca_extent[0]},
      {"length_m", g.pca_extent[1]},
      {"width_m", g.pca_extent[2]},
      {"section_perimeter_m",
       {{"definition", "convex outline of the exact section through the box centre normal to each axis"},
        {"height_axis", g.section_perimeter[0]},
        {"length_axis", g.section_perimeter[1]},
        {"width_axis", g.section_perimeter[2]}}}};
  j["hanging_frame"] = {{"height_m", g.height},
                        {"height_from_cutting_point_m", g.height_from_cutting_point},
                        {"max_diameter_m", g.max_diameter},
                        {"ring_diameter_m", g.ring_diameter},
                        {"row_width_m", g.row_width},
                        {"row_depth_m", g.row_depth}};
  j["envelope"] = {{"definition", "convex hull of the solid"},
                   {"volume_m3", g.envelope_volume},
                   {"lower_bound_m3", g.envelope_lower},
                   {"upper_bound_m3", g.envelope_upper}};
  j["compactness"] = g.compactness;
  if (g.alpha_wrap_alpha > 0) {
    j["alpha_wrap"] = {{"definition", "CGAL alpha wrap of the bunch's mesh, less its offset times its area"},
                       {"alpha_m", g.alpha_wrap_alpha},
                       {"volume_m3", g.alpha_wrap_volume},
                       {"solid_over_wrap", g.volume.solid / g.alpha_wrap_volume}};
  }
  j["berry_contacts"] = {{"definition", "pairs of overlapping berries; depth = overlap over the smaller radius"},
                         {"pairs", g.contact_pairs},
                         {"share_of_berries", g.berries_in_contact},
                         {"depth_mean", g.contact_depth_mean},
                         {"depth_max", g.contact_depth_max}};
  j["asymmetry"] = {{"horizontal_extent_ratio", g.horizontal_extent_ratio},
                    {"definition", "berries' extents along their two horizontal principal axes, minor / major"},
                    {"wing_stem", b.wing},
                    {"wing_berry_share", g.wing_berry_share},
                    {"bend_stem", b.bend},
                    {"bend_angle_deg", g.bend_angle},
                    {"flat_side_distance_m", b.flat_side_distance},
                    {"flat_side_normal", vec(b.flat_side_normal)}};
  j["cutting_point_m"] = vec(g.cutting_point);
  j["peduncle_direction"] = vec(g.peduncle_direction);
  j["bbox_m"] = {{"min", vec(g.bbox_min)}, {"max", vec(g.bbox_max)}};
  nlohmann::ordered_json berries = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < b.berries.size(); ++i) {
    const auto& x = b.berries[i];
    berries.push_back({{"id", i},
                       {"centre_m", vec(x.centre)},
                       {"radius_m", x.radius},
                       {"colour", rgb(x.colour)},
                       {"pedicel", x.pedicel}});
  }
  j["berries"] = berries;
  nlohmann::ordered_json stems = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < b.stems.size(); ++i) {
    const auto& s = b.stems[i];
    stems.push_back({{"id", i},
                     {"part", part_name(s.part)},
                     {"start_m", vec(s.start)},
                     {"end_m", vec(s.end)},
                     {"radius_m", s.radius},
                     {"parent", s.parent},
                     {"stacked_on", s.stacked_on},
                     {"berry", s.berry}});
  }
  j["stems"] = stems;
  return j;
}

}  // namespace grapebench
