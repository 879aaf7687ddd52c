#include "algorithms/external/external_estimator.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>

#include "synth/confined_program.h"
#include "synth/temp_folder.h"
#include "synth/io.h"
#include "synth/utf8.h"
#include "synth/png.h"

extern char** environ;

namespace grapebench {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kMaxAnswerBytes = std::size_t{256} << 20;  // an answer line or file
constexpr double kMaxQuantity = 1000;                            // m3 or m: no bunch is larger

// Binary little-endian PLY: x y z, then the attributes the input has (doubles, and
// uchar colours). x86-64 is little-endian.
std::string ply_bytes(const PointCloud& c, const PointCloud* normals, const PointCloud* viewpoints,
                      const std::vector<Rgb8>* colours) {
  std::ostringstream s;
  s << "ply\nformat binary_little_endian 1.0\ncomment grapebench, metres\nelement vertex " << c.rows()
    << "\nproperty double x\nproperty double y\nproperty double z\n";
  if (normals) s << "property double nx\nproperty double ny\nproperty double nz\n";
  if (viewpoints) s << "property double vx\nproperty double vy\nproperty double vz\n";
  if (colours) s << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  s << "end_header\n";
  std::string out = s.str();
  const auto put = [&](const PointCloud& m, Eigen::Index i) {
    for (int k = 0; k < 3; ++k) {
      const double v = m(i, k);
      out.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
  };
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    put(c, i);
    if (normals) put(*normals, i);
    if (viewpoints) put(*viewpoints, i);
    if (colours) out.append(reinterpret_cast<const char*>((*colours)[static_cast<std::size_t>(i)].data()), 3);
  }
  return out;
}

nlohmann::ordered_json matrix_json(const Eigen::Isometry3d& t) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  const Eigen::Matrix4d m = t.matrix();
  for (int r = 0; r < 4; ++r) a.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return a;
}

// Writes the request's files into `dir` and returns the request.
nlohmann::ordered_json write_request(const fs::path& dir, const EstimatorInput& in, const ExternalParams& p) {
  const PointCloud& c = in.points;
  const auto n = c.rows();
  const bool v2 = p.version == 2;
  const bool normals = v2 && in.normals.rows() == n && n > 0, viewpoints = v2 && in.viewpoints.rows() == n && n > 0;
  const bool colours = v2 && static_cast<Eigen::Index>(in.colours.size()) == n && n > 0;
  std::ofstream(dir / "cloud.ply", std::ios::binary) << ply_bytes(
      c, normals ? &in.normals : nullptr, viewpoints ? &in.viewpoints : nullptr, colours ? &in.colours : nullptr);
  nlohmann::ordered_json req;
  req["protocol"] = v2 ? "grapebench-estimator-2" : "grapebench-estimator-1";
  if (v2)
    req["kind"] = p.input == ExternalParams::Input::Image ? "image"
                  : in.stereo                 ? "stereo_pair"
                  : !in.train_labels.empty() ? "classification"
                  : in.frame                 ? "single_frame"
                  : !in.views.empty()        ? "multi_view"
                                             : "cloud";
  req["cloud"] = (dir / "cloud.ply").string();
  req["points"] = n;
  req["units"] = "m";
  nlohmann::ordered_json q = nlohmann::ordered_json::array();
  for (Quantity x : p.quantities) q.push_back(quantity_name(x));
  req["quantities"] = q;
  if (!p.persistent) req["answer"] = (dir / "answer.json").string();
  req["params"] = p.params;
  if (!v2) return req;
  nlohmann::ordered_json attributes = nlohmann::ordered_json::array();
  if (normals) attributes.push_back("normals");
  if (viewpoints) attributes.push_back("viewpoints");
  if (colours) attributes.push_back("colours");
  req["attributes"] = attributes;
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < in.views.size(); ++k) {
    const fs::path file = dir / ("view_" + std::to_string(k) + ".ply");
    std::ofstream(file, std::ios::binary) << ply_bytes(in.views[k].points, nullptr, nullptr, nullptr);
    views.push_back({{"name", in.views[k].name},
                     {"pose", matrix_json(in.views[k].pose)},
                     {"cloud", file.string()},
                     {"points", in.views[k].points.rows()}});
  }
  req["views"] = views;
  if (!in.train_labels.empty()) {
    req["classes"] = in.classes;
    req["train_labels"] = in.train_labels;  // per point: class index, or -1 where to score
  }
  if (in.stereo) {
    // stereo_pair: the rectified pair; image (protocol detection): the left image, the
    // right one only when the sensor rendered it (else null).
    const StereoPair& s = *in.stereo;
    const bool image = p.input == ExternalParams::Input::Image, right = !s.right.data.empty();
    std::ofstream(dir / "left.png", std::ios::binary) << rgb_image_png(s.left.width, s.left.height, s.left.data);
    if (right) std::ofstream(dir / "right.png", std::ios::binary) << rgb_image_png(s.right.width, s.right.height, s.right.data);
    req[image ? "image" : "stereo"] = {
        {"left", (dir / "left.png").string()},
        {"right", right ? nlohmann::ordered_json((dir / "right.png").string()) : nlohmann::ordered_json()},
        {"width", s.left.width},
        {"height", s.left.height},
        {"fx", s.fx},
        {"fy", s.fy},
        {"cx", s.cx},
        {"cy", s.cy},
        {"baseline", s.baseline}};
    return req;  // the images are the whole hand-over: no frame, no ROI
  }
  if (in.frame) {
    const InputFrame& f = *in.frame;
    req["frame"] = {{"index", f.index}, {"roi", f.roi}, {"region", f.region}, {"width", f.width}, {"height", f.height},
                    {"fx", f.fx},       {"fy", f.fy},   {"cx", f.cx},         {"cy", f.cy}};
  }
  return req;
}

std::string who_of(const ExternalParams& p) {
  if (!p.who.empty()) return p.who;
  return p.command.empty() ? "external estimator" : "external estimator '" + p.command[0] + "'";
}

[[noreturn]] void fail(const ExternalParams& p, const std::string& why) {
  throw InputError(escape_invalid_utf8(who_of(p) + ": " + why));
}

ProgramLimits limits_of(const ExternalParams& p) {
  ProgramLimits l;
  l.sandbox = p.sandbox;
  l.readable.assign(p.readable.begin(), p.readable.end());
  l.cpu_seconds = p.cpu_limit;
  l.memory_mb = p.memory_limit;
  l.file_mb = p.file_limit;
  return l;
}

// `inbox`: a folder it may read and not write, or "".
std::unique_ptr<ConfinedProgram> start(const ExternalParams& p, const std::vector<std::string>& args,
                                       const fs::path& work, int stdio, const fs::path& inbox = {}) {
  try {
    ProgramLimits limits = limits_of(p);
    if (!inbox.empty()) limits.harness_readable.push_back(inbox);
    return std::make_unique<ConfinedProgram>(args, work, limits, stdio);
  } catch (const std::runtime_error& e) {
    fail(p, e.what());
  }
}

// Why a stopped or failed program failed, with the tail of its stderr.
[[noreturn]] void fail_ended(const ExternalParams& p, ConfinedProgram::End end, const ConfinedProgram& prog,
                             const std::string& what) {
  if (end == ConfinedProgram::End::TimedOut)
    fail(p, "killed after the timeout of " + std::to_string(p.timeout) + " s" + what);
  if (end == ConfinedProgram::End::TooMuchOutput) fail(p, "stopped: more than 16 MiB on stdout and stderr" + what);
  const std::string why = prog.failure();
  std::string text = "failed (" + (why.empty() ? std::string("exited") : why) + ")" + what;
  const std::string tail = prog.error_tail();
  if (!tail.empty()) text += ": " + tail;
  if (p.sandbox == ProgramLimits::Sandbox::Bwrap && tail.rfind("bwrap:", 0) == 0)
    text += " (bubblewrap cannot run here: set `sandbox: none` to run the program without it)";
  fail(p, text);
}

// The answer file, read within its size cap: a regular file only (a FIFO or device
// left at its path would block), not followed through a symbolic link.
std::string read_answer_file(const ExternalParams& p, const fs::path& path) {
  const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) fail(p, errno == ENOENT ? "wrote no answer.json" : "answer.json cannot be opened: " + std::string(std::strerror(errno)));
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(fd);
    fail(p, "answer.json is not a regular file");
  }
  if (static_cast<std::size_t>(st.st_size) > kMaxAnswerBytes) {
    close(fd);
    fail(p, "answer.json is larger than 256 MiB");
  }
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t got = 0;
  while (got < text.size()) {
    const ssize_t k = read(fd, text.data() + got, text.size() - got);
    if (k <= 0) break;
    got += static_cast<std::size_t>(k);
  }
  close(fd);
  text.resize(got);
  return text;
}

// Per-request mode: the program gets the request file's path and writes answer.json
// in its work folder (the only one it may write).
nlohmann::json run_once(const fs::path& dir, const ExternalParams& p) {
  std::vector<std::string> args = p.command;
  args.push_back((dir / "request.json").string());
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(p.timeout));
  auto prog = start(p, args, dir, -1);
  const ConfinedProgram::End end = prog->wait(deadline);
  if (end != ConfinedProgram::End::Exited || !prog->failure().empty()) fail_ended(p, end, *prog, "");
  const std::string text = read_answer_file(p, dir / "answer.json");
  try {
    return parse_json_bounded(text);
  } catch (const std::exception& e) {
    fail(p, std::string("answer.json is not JSON: ") + e.what());
  }
}

}  // namespace

// A pool of long-lived programs: each answers one request at a time; a request takes
// an idle one or starts another, so parallel cases never share a process.
class PersistentPrograms {
 public:
  explicit PersistentPrograms(ExternalParams p) : p_(std::move(p)) { p_.programs.reset(); }
  ~PersistentPrograms() {
    for (auto& proc : idle_) {
      shutdown(proc->fd, SHUT_WR);  // end of stdin: a well-behaved program exits
      proc->program->wait(Clock::now() + std::chrono::seconds(2));  // then it is stopped
      close(proc->fd);
    }
  }
  PersistentPrograms(const PersistentPrograms&) = delete;
  PersistentPrograms& operator=(const PersistentPrograms&) = delete;

  // `write` puts the request's files in the folder it is given and returns the request.
  nlohmann::json ask(const std::function<nlohmann::ordered_json(const fs::path&)>& write) {
    std::unique_ptr<Process> proc = take();
    const auto deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(p_.timeout));
    nlohmann::ordered_json request;
    try {
      const fs::path dir = proc->inbox->path / "request";
      fs::remove_all(dir);
      fs::create_directory(dir);
      request = write(dir);
    } catch (...) {
      discard(*proc);
      throw;
    }
    try {
      send_line(*proc, request.dump() + "\n", deadline);
      nlohmann::json answer = parse_json_bounded(read_line(*proc, deadline));
      give_back(std::move(proc));
      return answer;
    } catch (const InputError&) {
      discard(*proc);
      throw;
    } catch (const std::exception& e) {
      discard(*proc);
      fail(p_, std::string("its answer line is not JSON: ") + e.what());
    } catch (...) {
      discard(*proc);
      throw;
    }
  }

 private:
  struct Process {
    std::unique_ptr<TempFolder> dir;  // its work folder
    // Where the harness writes each request's files: the program reads them and
    // cannot write there (in its own folder, a link it put in place of a request's
    // folder would send the harness's writes anywhere).
    std::unique_ptr<TempFolder> inbox;
    std::unique_ptr<ConfinedProgram> program;
    int fd = -1;         // our end of the socket that is the program's stdin and stdout
    std::string buffer;  // bytes read past the last answer line
  };

  std::unique_ptr<Process> take() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!idle_.empty()) {
        auto proc = std::move(idle_.back());
        idle_.pop_back();
        return proc;
      }
    }
    auto proc = std::make_unique<Process>();
    proc->dir = std::make_unique<TempFolder>("grapebench-ext");
    proc->inbox = std::make_unique<TempFolder>("grapebench-in");
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) fail(p_, "socketpair failed");
    try {
      proc->program = start(p_, p_.command, proc->dir->path, sv[1], proc->inbox->path);
    } catch (...) {
      close(sv[0]);
      close(sv[1]);
      throw;
    }
    close(sv[1]);
    proc->fd = sv[0];
    return proc;
  }
  void give_back(std::unique_ptr<Process> proc) {
    std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(std::move(proc));
  }
  void discard(Process& proc) {
    proc.program->stop();
    close(proc.fd);
    proc.fd = -1;
  }
  // Waits for `events` on the socket within the request's time; fails when the program
  // ends, is stopped or runs out of time (the caller discards the process on any
  // failure).
  void wait_for(Process& proc, short events, Clock::time_point deadline, const char* what) {
    const ConfinedProgram::End end = proc.program->wait_fd(proc.fd, events, deadline);
    if (end != ConfinedProgram::End::Ready) fail_ended(p_, end, *proc.program, std::string(" (persistent) ") + what);
  }
  void send_line(Process& proc, const std::string& line, Clock::time_point deadline) {
    for (std::size_t sent = 0; sent < line.size();) {
      wait_for(proc, POLLOUT, deadline, "before reading its request");
      const ssize_t k = ::send(proc.fd, line.data() + sent, line.size() - sent, MSG_NOSIGNAL);
      if (k <= 0) ended(proc, deadline, "stopped reading requests");
      sent += static_cast<std::size_t>(k);
    }
  }
  std::string read_line(Process& proc, Clock::time_point deadline) {
    for (;;) {
      const auto nl = proc.buffer.find('\n');
      if (nl != std::string::npos) {
        std::string line = proc.buffer.substr(0, nl);
        proc.buffer.erase(0, nl + 1);
        return line;
      }
      if (proc.buffer.size() > kMaxAnswerBytes) fail(p_, "an answer line longer than 256 MiB");
      wait_for(proc, POLLIN, deadline, "before answering");
      char chunk[65536];
      const ssize_t k = ::read(proc.fd, chunk, sizeof chunk);
      if (k <= 0) ended(proc, deadline, "exited before answering");
      proc.buffer.append(chunk, static_cast<std::size_t>(k));
    }
  }
  // The program closed its end: waits (briefly) for its end to say why.
  [[noreturn]] void ended(Process& proc, Clock::time_point deadline, const std::string& what) {
    const auto end = proc.program->wait(std::min(deadline, Clock::now() + std::chrono::seconds(2)));
    const std::string why = proc.program->failure(), tail = proc.program->error_tail();
    if (end != ConfinedProgram::End::Exited) fail_ended(p_, end, *proc.program, " (persistent) " + what);
    fail(p_, what + (why.empty() ? "" : " (" + why + ")") + (tail.empty() ? "" : ": " + tail));
  }

  ExternalParams p_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Process>> idle_;
};

std::shared_ptr<PersistentPrograms> start_persistent_programs(const ExternalParams& params) {
  return std::make_shared<PersistentPrograms>(params);
}

Estimate parse_external_answer(const nlohmann::json& a, const ExternalParams& p, long points, int input_width,
                               int input_height) {
  if (!a.is_object()) fail(p, "the answer is not a JSON object");
  if (a.contains("error"))
    fail(p, "answered an error: " + (a["error"].is_string() ? a["error"].get<std::string>().substr(0, 400)
                                                            : a["error"].dump().substr(0, 400)));
  Estimate e;
  for (Quantity q : p.quantities) {
    const auto it = a.find(quantity_name(q));
    if (it == a.end() || !it->is_number() || !std::isfinite(it->get<double>())) {
      fail(p, std::string("the answer lacks a finite number '") + quantity_name(q) + "'");
    }
    const double v = it->get<double>();
    if (!(v > 0 && v <= kMaxQuantity)) {
      fail(p, std::string("'") + quantity_name(q) + "' = " + it->dump() + " is outside (0, 1000] (m3 or m)");
    }
    e.values.emplace_back(q, v);
  }
  const auto finite_number = [](const nlohmann::json& x) { return x.is_number() && std::isfinite(x.get<double>()); };
  if (p.version == 2 && a.contains("points")) {
    if (!a["points"].is_object()) fail(p, "'points' must map names to [x, y, z]");
    for (const auto& [name, v] : a["points"].items()) {
      if (!v.is_array() || v.size() != 3 || !finite_number(v[0]) || !finite_number(v[1]) || !finite_number(v[2])) {
        fail(p, "'points." + name + "' must be [x, y, z], finite, m");
      }
      e.points.emplace_back(name, Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()));
    }
  }
  if (p.version == 2 && a.contains("detections")) {
    if (!a["detections"].is_array()) fail(p, "'detections' must be a list of {x, y, r, score}");
    for (const auto& d : a["detections"]) {
      if (!d.is_object() || !finite_number(d.value("x", nlohmann::json())) ||
          !finite_number(d.value("y", nlohmann::json())) || !finite_number(d.value("r", nlohmann::json())) ||
          d["r"].get<double>() <= 0) {
        fail(p, "each detection must be {x, y, r > 0, score}, finite, pixels");
      }
      const double score = d.contains("score") && finite_number(d["score"]) ? d["score"].get<double>() : 1.0;
      e.detections.push_back({{d["x"].get<double>(), d["y"].get<double>(), d["r"].get<double>()}, score});
    }
  }
  if (p.version == 2 && a.contains("instances")) {
    // COCO's results records: {category, score, bbox: [x, y, w, h], segmentation:
    // {size: [h, w], counts: "..."} (optional), volume (m3, optional)}. The mask's runs
    // are checked by the protocol, which knows the image.
    if (!a["instances"].is_array()) fail(p, "'instances' must be a list of {category, score, bbox, segmentation}");
    for (std::size_t i = 0; i < a["instances"].size(); ++i) {
      const auto& d = a["instances"][i];
      const std::string where = "instances[" + std::to_string(i) + "]";
      if (!d.is_object() || !d.contains("category") || !d["category"].is_string())
        fail(p, where + ": needs 'category', a name (bunch, berry, stalk, leaf, cane)");
      ImageDetection x;
      x.category = d["category"].get<std::string>().substr(0, 40);
      if (d.contains("score") && !finite_number(d["score"])) fail(p, where + ".score: must be a finite number");
      x.score = d.contains("score") ? d["score"].get<double>() : 1.0;
      const auto& b = d.value("bbox", nlohmann::json());
      if (!b.is_array() || b.size() != 4 || !finite_number(b[0]) || !finite_number(b[1]) || !finite_number(b[2]) ||
          !finite_number(b[3]) || b[2].get<double>() < 0 || b[3].get<double>() < 0)
        fail(p, where + ".bbox: must be [x, y, w, h], finite, w and h >= 0, pixels");
      x.x = b[0].get<double>(), x.y = b[1].get<double>(), x.w = b[2].get<double>(), x.h = b[3].get<double>();
      if (d.contains("segmentation")) {
        const auto& m = d["segmentation"];
        if (!m.is_object() || !m.contains("counts") || !m["counts"].is_string() || !m.contains("size") ||
            m["size"] != nlohmann::json::array({input_height, input_width}))
          fail(p, where + ".segmentation: must be {size: [" + std::to_string(input_height) + ", " +
                      std::to_string(input_width) + "], counts: a compressed RLE string}");
        x.rle = m["counts"].get<std::string>();
      }
      if (d.contains("volume")) {
        if (!finite_number(d["volume"]) || d["volume"].get<double>() < 0) fail(p, where + ".volume: must be >= 0, m3");
        x.volume = d["volume"].get<double>();
      }
      e.instances.push_back(std::move(x));
    }
  }
  if (p.version == 2 && a.contains("class_scores")) {
    const auto& s = a["class_scores"];
    if (!s.is_array() || static_cast<long>(s.size()) != points || s.empty() || !s[0].is_array() || s[0].empty()) {
      fail(p, "'class_scores' must hold one list of K scores per input point (" + std::to_string(points) + ")");
    }
    const auto k = static_cast<Eigen::Index>(s[0].size());
    e.class_scores.resize(points, k);
    for (Eigen::Index i = 0; i < points; ++i) {
      const auto& row = s[static_cast<std::size_t>(i)];
      if (!row.is_array() || static_cast<Eigen::Index>(row.size()) != k)
        fail(p, "'class_scores' rows differ in length");
      for (Eigen::Index j = 0; j < k; ++j) {
        if (!finite_number(row[static_cast<std::size_t>(j)])) fail(p, "'class_scores' holds a non-finite score");
        e.class_scores(i, j) = row[static_cast<std::size_t>(j)].get<double>();
      }
    }
  }
  // Wrong types refused (issue 39: "watertight": "yes" read as false).
  if (a.contains("watertight") && !a["watertight"].is_boolean()) fail(p, "'watertight' must be true or false");
  e.watertight = a.contains("watertight") && a["watertight"].get<bool>();
  if (a.contains("notes") && !a["notes"].is_string()) fail(p, "'notes' must be a string");
  if (a.contains("notes")) e.notes = escape_invalid_utf8(a["notes"].get<std::string>().substr(0, 400));
  return e;
}

const char* external_input_name(ExternalParams::Input input) {
  switch (input) {
    case ExternalParams::Input::StereoPair: return "stereo_pair";
    case ExternalParams::Input::LabelledCloud: return "labelled_cloud";
    case ExternalParams::Input::Image: return "image";
    case ExternalParams::Input::Cloud: break;
  }
  return "cloud";
}

void require_external_input(const EstimatorInput& input, const ExternalParams& p) {
  const std::string who = who_of(p);
  if (p.input == ExternalParams::Input::StereoPair) {
    if (!input.stereo) throw InputError(who + ": input: stereo_pair, and the protocol gives no stereo pair");
  } else if (p.input == ExternalParams::Input::Image) {
    if (!input.stereo) throw InputError(who + ": input: image, and the protocol gives no image");
  } else {
    require_points(input.points, 1, who);
  }
  if (p.input == ExternalParams::Input::LabelledCloud && input.train_labels.empty())
    throw InputError(who + ": input: labelled_cloud, and the protocol gives no training labels");
}

Estimate require_class_scores(Estimate e, const EstimatorInput& input, const ExternalParams& p) {
  if (p.input == ExternalParams::Input::LabelledCloud &&
      (e.class_scores.rows() != input.points.rows() ||
       e.class_scores.cols() != static_cast<Eigen::Index>(input.classes.size())))
    fail(p, "the answer needs 'class_scores': one list of " + std::to_string(input.classes.size()) +
                " scores per input point");
  return e;
}

Estimate external_estimate(const EstimatorInput& input, const ExternalParams& p) {
  if (p.command.empty()) throw InputError("external estimator: empty command");
  require_external_input(input, p);
  const int width = input.stereo ? input.stereo->left.width : 0, height = input.stereo ? input.stereo->left.height : 0;
  if (p.persistent) {
    if (!p.programs) throw std::logic_error("external estimator: persistent mode without its programs");
    const auto write = [&](const fs::path& dir) { return write_request(dir, input, p); };
    return require_class_scores(parse_external_answer(p.programs->ask(write), p, input.points.rows(), width, height),
                                input, p);
  }
  const TempFolder dir("grapebench-ext");
  const nlohmann::ordered_json req = write_request(dir.path, input, p);
  std::ofstream(dir.path / "request.json", std::ios::binary) << req.dump(1) << "\n";
  return require_class_scores(parse_external_answer(run_once(dir.path, p), p, input.points.rows(), width, height),
                              input, p);
}

const ParamTable<ExternalParams>& external_param_table() {
  using P = ExternalParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .strings("command", &P::command, 1, "the program and its arguments, e.g. [python3, \"{scene_dir}/my.py\"]")
          .required()
          .real("timeout", "s", &P::timeout, 0.1, 86400, "the whole exchange of one request; then the group is killed")
          .choice("sandbox", &P::sandbox, {{"bwrap", ProgramLimits::Sandbox::Bwrap}, {"none", ProgramLimits::Sandbox::None}},
                  "bwrap: bubblewrap, read-only file system but its work folder, no network, its own PIDs; none: "
                  "only the limits below and the cleanup (where user namespaces are not available)")
          .strings("readable", &P::readable, 0,
                   "bwrap: files or folders it may read besides the system's and the files its command names "
                   "(\"{scene_dir}\" allowed), e.g. its modules' folder; never the run's --out")
          .real("cpu_limit", "s", &P::cpu_limit, 1, 86400, "CPU time of each of its processes (RLIMIT_CPU)")
          .real("memory_limit", "MB", &P::memory_limit, 64, 1e7, "address space of each of its processes (RLIMIT_AS)")
          .real("file_limit", "MB", &P::file_limit, 1, 1e7, "largest file it may write (RLIMIT_FSIZE)")
          .integer("version", "-", &P::version, 1, 2,
                   "protocol version: 1 (x y z, scalars) or 2 (every attribute and output kind)")
          .boolean("persistent", &P::persistent, "one process answers many requests as JSON lines on stdin/stdout")
          .when("version: 2", [](const P& p) { return p.version == 2; })
          .choice("input", &P::input,
                  {{"cloud", P::Input::Cloud},
                   {"stereo_pair", P::Input::StereoPair},
                   {"labelled_cloud", P::Input::LabelledCloud},
                   {"image", P::Input::Image}},
                  "what the program measures: the protocol's cloud, a colour stereo pair (protocol stereo_pair), "
                  "a coloured cloud with training labels (protocol classification: class_scores answer) or a "
                  "colour image (protocol detection: instances answer)")
          .when("version: 2", [](const P& p) { return p.version == 2; })
          .choice_list("quantities", &P::quantities, quantity_choices(), 1, "what the program's answer holds")
          .when("input: cloud or stereo_pair",
                [](const P& p) { return p.input == P::Input::Cloud || p.input == P::Input::StereoPair; });
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
