#include "algorithms/colmap_sfm.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "algorithms/temp_folder.h"
#include "synth/png.h"

extern char** environ;

namespace grapebench {

namespace fs = std::filesystem;

const ParamTable<ColmapParams>& colmap_param_table() {
  using P = ColmapParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("timeout", "s", &P::timeout, 1, 86400, "the whole COLMAP run; then its process group is killed")
          .integer("overlap", "count", &P::overlap, 1, 100, "sequential matcher: images matched after each one");
  return table;
}

namespace {

// Runs args in its own process group with stdout and stderr appended to `log`; kills
// the group at the deadline.
void run(std::vector<std::string> args, const fs::path& log, std::chrono::steady_clock::time_point deadline) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  const std::string log_path = log.string();
  posix_spawn_file_actions_addopen(&fa, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &fa, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw InputError("colmap: cannot start '" + args[0] + "' (apt-get install colmap)");
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      throw InputError("colmap: " + args[1] + " timed out");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(-pid, SIGKILL);  // nothing of the group outlives its step
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError("colmap " + args[1] + " failed: " + file_tail(log, 400));
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
                 log = dir.path / "log.txt", db = dir.path / "db.sqlite";
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
  run({p.program, "feature_extractor", "--random_seed", s, "--database_path", db.string(), "--image_path", img.string(),
       "--ImageReader.camera_model", "PINHOLE", "--ImageReader.single_camera", "1", "--ImageReader.camera_params", params,
       "--SiftExtraction.use_gpu", "0", "--SiftExtraction.num_threads", "1"},
      log, deadline);
  run({p.program, "sequential_matcher", "--random_seed", s, "--database_path", db.string(), "--SiftMatching.use_gpu",
       "0", "--SiftMatching.num_threads", "1", "--SequentialMatching.overlap", std::to_string(p.overlap)},
      log, deadline);
  run({p.program, "mapper", "--random_seed", s, "--database_path", db.string(), "--image_path", img.string(),
       "--output_path", sparse.string(), "--Mapper.num_threads", "1", "--Mapper.multiple_models", "0",
       "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
       "--Mapper.ba_refine_extra_params", "0", "--Mapper.init_min_tri_angle", "4"},
      log, deadline);
  if (!fs::exists(sparse / "0")) throw InputError("colmap mapper made no model: " + file_tail(log, 400));
  run({p.program, "model_converter", "--input_path", (sparse / "0").string(), "--output_path", txt.string(),
       "--output_type", "TXT"},
      log, deadline);
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
  out.log_tail = file_tail(log, 400);
  return out;
}

}  // namespace grapebench
