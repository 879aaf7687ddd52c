#include "algorithms/external_estimator.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace grapebench {

namespace fs = std::filesystem;

namespace {

constexpr const char* kProtocol = "grapebench-estimator-1";

std::string ply_bytes(const PointCloud& c) {
  std::ostringstream s;
  s << "ply\nformat binary_little_endian 1.0\ncomment grapebench registered bunch, metres\nelement vertex " << c.rows()
    << "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  std::string out = s.str();
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = c(i, k);
      out.append(reinterpret_cast<const char*>(&v), sizeof v);  // x86-64 is little-endian
    }
  }
  return out;
}

std::string tail_of(const fs::path& p, std::size_t n) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  std::string t = s.str();
  if (t.size() > n) t = "..." + t.substr(t.size() - n);
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  return t;
}

struct TempDir {
  fs::path path;
  TempDir() {
    static std::atomic<unsigned> counter{0};
    path = fs::temp_directory_path() /
           ("grapebench-ext-" + std::to_string(getpid()) + "-" + std::to_string(counter.fetch_add(1)));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

Estimate external_estimate(const PointCloud& cloud, const ExternalParams& p) {
  if (p.command.empty()) throw InputError("external estimator: empty command");
  require_points(cloud, 1, "external estimator");
  const TempDir dir;
  {
    std::ofstream(dir.path / "cloud.ply", std::ios::binary) << ply_bytes(cloud);
    nlohmann::ordered_json req;
    req["protocol"] = kProtocol;
    req["cloud"] = (dir.path / "cloud.ply").string();
    req["points"] = cloud.rows();
    req["units"] = "m";
    nlohmann::ordered_json q = nlohmann::ordered_json::array();
    for (Quantity x : p.quantities) q.push_back(quantity_name(x));
    req["quantities"] = q;
    req["answer"] = (dir.path / "answer.json").string();
    req["params"] = p.params;
    std::ofstream(dir.path / "request.json", std::ios::binary) << req.dump(1) << "\n";
  }
  std::vector<std::string> args = p.command;
  args.push_back((dir.path / "request.json").string());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  const std::string out_path = (dir.path / "stdout.txt").string(), err_path = (dir.path / "stderr.txt").string();
  posix_spawn_file_actions_addopen(&fa, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw InputError("external estimator: cannot start '" + p.command[0] + "': " + std::strerror(rc));
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0) throw InputError("external estimator: waitpid failed: " + std::string(std::strerror(errno)));
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > p.timeout) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      throw InputError("external estimator '" + p.command[0] + "': killed after the timeout of " +
                       std::to_string(p.timeout) + " s");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string why = WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                              : "signal " + std::to_string(WTERMSIG(status));
    throw InputError("external estimator '" + p.command[0] + "' failed (" + why + "): " + tail_of(err_path, 400));
  }
  std::ifstream in(dir.path / "answer.json", std::ios::binary);
  if (!in) throw InputError("external estimator '" + p.command[0] + "' wrote no answer.json");
  nlohmann::json a;
  try {
    a = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError("external estimator '" + p.command[0] + "': answer.json is not JSON: " + e.what());
  }
  Estimate e;
  for (Quantity q : p.quantities) {
    const auto it = a.find(quantity_name(q));
    if (it == a.end() || !it->is_number() || !std::isfinite(it->get<double>())) {
      throw InputError("external estimator '" + p.command[0] + "': answer.json lacks a finite number '" +
                       quantity_name(q) + "'");
    }
    e.values.emplace_back(q, it->get<double>());
  }
  e.watertight = a.value("watertight", false);
  e.notes = a.value("notes", "");
  return e;
}

const ParamTable<ExternalParams>& external_param_table() {
  using P = ExternalParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .strings("command", &P::command, 1, "the program and its arguments, e.g. [python3, \"{scene_dir}/my.py\"]")
          .required()
          .choice_list("quantities", &P::quantities, quantity_choices(), 1, "what the program's answer holds")
          .real("timeout", "s", &P::timeout, 0.1, 86400, "the program is killed after it");
  return table;
}

void substitute_scene_dir(std::vector<std::string>& command, const std::string& scene_dir) {
  const std::string placeholder = "{scene_dir}", with = scene_dir.empty() ? "." : scene_dir;
  for (auto& a : command) {
    // Search on after each replacement: a folder whose name holds the placeholder
    // must not be expanded again.
    for (auto at = a.find(placeholder); at != std::string::npos; at = a.find(placeholder, at + with.size())) {
      a.replace(at, placeholder.size(), with);
    }
  }
}

}  // namespace grapebench
