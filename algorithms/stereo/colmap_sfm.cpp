#include "algorithms/stereo/colmap_sfm.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "synth/confined_program.h"
#include "synth/temp_folder.h"
#include "synth/png.h"

namespace grapebench {

namespace fs = std::filesystem;

const ParamTable<ColmapParams>& colmap_param_table() {
  using P = ColmapParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("timeout", "s", &P::timeout, 1, 86400, "the whole COLMAP run; then its process group is killed")
          .integer("overlap", "count", &P::overlap, 1, 100, "sequential matcher: images matched after each one")
          .choice("sandbox", &P::sandbox, {{"bwrap", ProgramLimits::Sandbox::Bwrap}, {"none", ProgramLimits::Sandbox::None}},
                  "bwrap: COLMAP runs in bubblewrap, its temporary folder the only one it can write; none: where "
                  "user namespaces are not available")
          .boolean("repeatable", &P::repeatable,
                   "preload grapebench's seed shim into COLMAP so its random draws (FLANN's kd-trees, RANSAC) "
                   "come from the seed alone; false: COLMAP as installed, whose matches differ slightly between runs");
  return table;
}

ProgramLimits colmap_program_limits(const ColmapParams& p) {
  ProgramLimits limits;
  limits.sandbox = p.sandbox;
  limits.cpu_seconds = p.timeout + 1;
  std::error_code ec;
  if (p.repeatable && fs::is_regular_file(GRAPEBENCH_COLMAP_SEED_SHIM, ec))
    limits.harness_readable.emplace_back(GRAPEBENCH_COLMAP_SEED_SHIM);  // preloaded: the sandbox must show it
  return limits;
}

namespace {

// Runs one COLMAP step confined to the run's folder (synth/confined_program.h:
// bubblewrap, the process tree killed when the step ends or at the deadline); returns
// the tail of what it logged (COLMAP logs to stderr).
std::string run(const std::vector<std::string>& args, const fs::path& dir, const ColmapParams& p,
                const std::vector<std::pair<std::string, std::string>>& environment,
                std::chrono::steady_clock::time_point deadline) {
  ProgramLimits limits = colmap_program_limits(p);
  limits.environment = environment;
  std::unique_ptr<ConfinedProgram> prog;
  try {
    prog = std::make_unique<ConfinedProgram>(args, dir, limits);
  } catch (const std::runtime_error& e) {
    throw InputError("colmap: cannot start '" + args[0] + "' (apt-get install colmap): " + e.what());
  }
  const ConfinedProgram::End end = prog->wait(deadline);
  if (end == ConfinedProgram::End::TimedOut) throw InputError("colmap: " + args[1] + " timed out");
  if (end == ConfinedProgram::End::TooMuchOutput) throw InputError("colmap " + args[1] + ": more than 16 MiB of log");
  if (!prog->failure().empty())
    throw InputError("colmap " + args[1] + " failed (" + prog->failure() + "): " + prog->error_tail());
  return prog->error_tail();
}

}  // namespace

std::vector<std::pair<std::string, Eigen::Isometry3d>> parse_colmap_images(const std::string& text) {
  std::vector<std::pair<std::string, Eigen::Isometry3d>> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool points_line = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    if (points_line) {  // the image's 2D points: not needed
      points_line = false;
      continue;
    }
    std::istringstream l(line);
    long id = 0, camera = 0;
    double qw, qx, qy, qz, tx, ty, tz;
    std::string name;
    if (!(l >> id >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> camera >> name))
      throw InputError("colmap images.txt line " + std::to_string(number) + ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    const Eigen::Quaterniond q(qw, qx, qy, qz);
    if (!std::isfinite(q.norm()) || std::abs(q.norm() - 1) > 1e-3 || !std::isfinite(tx) || !std::isfinite(ty) ||
        !std::isfinite(tz))
      throw InputError("colmap images.txt line " + std::to_string(number) + ": not a unit quaternion and finite translation");
    Eigen::Isometry3d world_to_camera = Eigen::Isometry3d::Identity();
    world_to_camera.linear() = q.normalized().toRotationMatrix();
    world_to_camera.translation() = Eigen::Vector3d(tx, ty, tz);
    out.emplace_back(name, world_to_camera.inverse());
    points_line = true;
  }
  return out;
}

ColmapPoses colmap_sfm(const std::vector<RgbImage>& images, double fx, double fy, double cx, double cy,
                       const ColmapParams& p, std::uint64_t seed) {
  if (images.size() < 2) throw InputError("colmap: needs at least two images");
  const TempFolder dir("grapebench-colmap");
  const fs::path img = dir.path / "images", sparse = dir.path / "sparse", txt = dir.path / "txt",
                 db = dir.path / "db.sqlite";
  fs::create_directories(img), fs::create_directories(sparse), fs::create_directories(txt);
  for (std::size_t k = 0; k < images.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "view_%04zu.png", k);
    std::ofstream(img / name, std::ios::binary) << rgb_image_png(images[k].width, images[k].height, images[k].data);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                               std::chrono::duration<double>(p.timeout));
  const std::string s = std::to_string(seed % 2147483647), params = [&] {
    std::ostringstream o;
    o.precision(17);
    o << fx << "," << fy << "," << cx << "," << cy;
    return o.str();
  }();
  std::vector<std::pair<std::string, std::string>> env;
  if (p.repeatable) {
    const fs::path shim = GRAPEBENCH_COLMAP_SEED_SHIM;
    std::error_code ec;
    if (!fs::is_regular_file(shim, ec))
      throw InputError("colmap: repeatable: the seed shim " + shim.string() +
                       " is missing (rebuild grapebench, or set repeatable: false)");
    env = {{"LD_PRELOAD", shim.string()}, {"GRAPEBENCH_COLMAP_SEED", s}};
  }
  run({p.program, "feature_extractor", "--random_seed", s, "--database_path", db.string(), "--image_path", img.string(),
       "--ImageReader.camera_model", "PINHOLE", "--ImageReader.single_camera", "1", "--ImageReader.camera_params", params,
       "--SiftExtraction.use_gpu", "0", "--SiftExtraction.num_threads", "1"},
      dir.path, p, env, deadline);
  run({p.program, "sequential_matcher", "--random_seed", s, "--database_path", db.string(), "--SiftMatching.use_gpu",
       "0", "--SiftMatching.num_threads", "1", "--SequentialMatching.overlap", std::to_string(p.overlap)},
      dir.path, p, env, deadline);
  const std::string mapper_log = run({p.program, "mapper", "--random_seed", s, "--database_path", db.string(), "--image_path", img.string(),
       "--output_path", sparse.string(), "--Mapper.num_threads", "1", "--Mapper.multiple_models", "0",
       "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
       "--Mapper.ba_refine_extra_params", "0", "--Mapper.init_min_tri_angle", "4"},
      dir.path, p, env, deadline);
  if (!fs::exists(sparse / "0")) throw InputError("colmap mapper made no model: " + mapper_log);
  run({p.program, "model_converter", "--input_path", (sparse / "0").string(), "--output_path", txt.string(),
       "--output_type", "TXT"},
      dir.path, p, env, deadline);
  std::ifstream in(txt / "images.txt");
  std::stringstream text;
  text << in.rdbuf();
  ColmapPoses out;
  out.poses.assign(images.size(), std::nullopt);
  for (const auto& [name, pose] : parse_colmap_images(text.str())) {
    unsigned k = 0;
    if (std::sscanf(name.c_str(), "view_%u.png", &k) != 1 || k >= images.size())
      throw InputError("colmap images.txt names an image it was not given: " + name);
    if (!out.poses[k]) ++out.registered;
    out.poses[k] = pose;
  }
  std::ifstream pts(txt / "points3D.txt");
  for (std::string line; std::getline(pts, line);) out.points3d += !line.empty() && line[0] != '#';
  out.log_tail = mapper_log;
  return out;
}

}  // namespace grapebench
