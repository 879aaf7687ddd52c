#include "synth/confined_program.h"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string_view>

extern char** environ;

namespace grapebench {

namespace fs = std::filesystem;

namespace {

// Everything the warden needs, prepared before fork(): after it only
// async-signal-safe calls are made (the harness has other threads).
struct WardenPlan {
  const char* exec_path = nullptr;
  std::vector<char*> argv;
  char** envp = nullptr;
  const char* work_dir = nullptr;
  int in = -1, out = -1, err = -1, status = -1;  // become fds 0, 1, 2 and 3
  rlimit cpu{}, memory{}, file{};
  pid_t harness = -1;  // the warden's parent: once it is gone, so is the program
};

void write_text(int fd, const char* s) {
  const ssize_t ignored = write(fd, s, std::strlen(s));
  (void)ignored;
}

// Kills the warden's children until none is left: a subreaper inherits the orphans of
// what it started, so daemons come back to it as their parents die.
void kill_descendants() {
  for (;;) {
    char buf[4096];
    const int fd = open("/proc/thread-self/children", O_RDONLY | O_CLOEXEC);
    const ssize_t n = fd >= 0 ? read(fd, buf, sizeof buf - 1) : -1;
    if (fd >= 0) close(fd);
    for (ssize_t i = 0; i < n;) {
      pid_t pid = 0;
      while (i < n && buf[i] >= '0' && buf[i] <= '9') pid = pid * 10 + (buf[i++] - '0');
      if (pid > 0) kill(pid, SIGKILL);
      while (i < n && (buf[i] < '0' || buf[i] > '9')) ++i;
    }
    int st = 0;
    const pid_t r = waitpid(-1, &st, WNOHANG);
    if (r > 0) continue;
    if (r < 0 && errno == ECHILD) return;
    const timespec ms{0, 1000000};
    nanosleep(&ms, nullptr);
  }
}

// A warden that cannot answer (or could not be set up): killed with its process group.
void kill_warden(pid_t warden) {
  kill(-warden, SIGKILL);
  kill(warden, SIGKILL);
}

// A high descriptor copy of fd (so that moving it to 0..3 cannot overwrite another).
int lift(int fd) { return fd < 0 ? -1 : fcntl(fd, F_DUPFD, 10); }

[[noreturn]] void warden_main(const WardenPlan& p) {
  setsid();  // its own session and process group: nothing reaches the harness's terminal
  prctl(PR_SET_CHILD_SUBREAPER, 1);
  // SIGTERM (the harness's "stop") and SIGCHLD stay blocked and are waited for.
  sigset_t wake;
  sigemptyset(&wake);
  sigaddset(&wake, SIGTERM);
  sigaddset(&wake, SIGCHLD);
  sigprocmask(SIG_SETMASK, &wake, nullptr);
  int in = lift(p.in);
  if (in < 0) in = open("/dev/null", O_RDONLY);
  const int out = lift(p.out), err = lift(p.err), status = lift(p.status);
  if (in < 0 || out < 0 || err < 0 || status < 0) _exit(126);
  dup2(in, 0);
  dup2(out, 1);
  dup2(err, 2);
  dup2(status, 3);
  close_range(4, ~0U, 0);  // none of the harness's files (sockets of other programs) leak
  fcntl(3, F_SETFD, FD_CLOEXEC);
  const pid_t prog = fork();
  if (prog == 0) {
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    setrlimit(RLIMIT_CPU, &p.cpu);
    setrlimit(RLIMIT_AS, &p.memory);
    setrlimit(RLIMIT_FSIZE, &p.file);
    if (chdir(p.work_dir) != 0) _exit(126);
    execve(p.exec_path, p.argv.data(), p.envp);
    write_text(2, "grapebench: cannot execute ");
    write_text(2, p.exec_path);
    write_text(2, "\n");
    _exit(127);
  }
  int st = 126 << 8;  // exit status 126: the program could not be started
  if (prog > 0) {
    // Stopped when the harness says so, or when the harness is gone (killed, say, so
    // that it could not say so): checked every 200 ms.
    const timespec tick{0, 200000000};
    bool stop = false;
    for (;;) {
      const pid_t r = waitpid(prog, &st, WNOHANG);
      if (r == prog || (r < 0 && errno != EINTR)) break;
      if (stop) kill(prog, SIGKILL);
      const int sig = sigtimedwait(&wake, nullptr, &tick);
      stop = stop || sig == SIGTERM || getppid() != p.harness;
    }
  }
  kill_descendants();
  const ssize_t ignored = write(3, &st, sizeof st);
  (void)ignored;
  _exit(0);
}

// Soft limit v, hard limit a little above: the soft one sends SIGXCPU or fails the
// write with SIGXFSZ, so the reason can be told; the hard one is SIGKILL.
rlimit limit_of(double v, double slack) {
  const rlim_t r = static_cast<rlim_t>(std::ceil(v));
  return rlimit{r, static_cast<rlim_t>(std::ceil(v + slack))};
}

// Where `name` is found in PATH (a name holding '/' is taken as it is), when `usable`
// says yes; "" when not.
template <class Usable>
std::string find_program_where(const std::string& name, const Usable& usable) {
  if (name.empty()) return "";
  if (name.find('/') != std::string::npos) {
    std::error_code ec;
    const fs::path p = fs::absolute(name, ec);
    return !ec && access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p, ec) ? p.string() : "";
  }
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  for (std::size_t start = 0; start <= dirs.size();) {
    std::size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
    const fs::path p = fs::path(dir) / name;
    std::error_code ec;
    if (access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p, ec) && usable(p))
      return fs::absolute(p, ec).string();
    start = end + 1;
  }
  return "";
}

std::mutex g_hidden_mutex;
std::vector<fs::path> g_hidden;  // hide_from_programs

// The wardens running in this process and their pidfds (stop_every_program). A pidfd
// is closed only after its warden leaves this list, under the same mutex.
// Never destroyed: a signal's thread may still use them while main returns.
std::mutex& g_live_mutex = *new std::mutex;
std::vector<std::pair<pid_t, int>>& g_live = *new std::vector<std::pair<pid_t, int>>;

// Absolute, lexically normal, no trailing separator.
fs::path normal(const fs::path& p) {
  fs::path n = fs::absolute(p).lexically_normal();
  if (!n.has_filename() && n.has_parent_path() && n != n.root_path()) n = n.parent_path();
  return n;
}

// `p` is `root` or lies inside it (both normal).
bool inside(const fs::path& p, const fs::path& root) {
  auto q = p.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++q) {
    if (q == p.end() || *q != *r) return false;
  }
  return true;
}

// The system's folders a program needs (read-only): Debian's merged /usr keeps /bin,
// /sbin and /lib* as links into it.
constexpr const char* kSystemFolders[] = {"/usr", "/etc", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32"};

// `p` resolved through every link that exists (so a hidden folder reached through
// a link is still recognised).
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? normal(p) : normal(c);
}

// An argument that names a file by a path (absolute, or holding a '/'): a bare word
// such as COLMAP's "PINHOLE" is never taken for a file that happens to be here.
bool names_a_file(const std::string& a) {
  std::error_code ec;
  return !a.empty() && a.size() <= 4096 && a.find('/') != std::string::npos && fs::is_regular_file(a, ec);
}

// bubblewrap's arguments: what the program sees (ProgramLimits' comment says what).
// The file arguments of `argv` are rewritten to their normal paths (a path through a
// folder the program cannot see, "scenes/../x.py", would not resolve inside).
std::vector<std::string> sandbox_arguments(const std::string& bwrap, const ProgramLimits& limits,
                                           const std::string& work, std::vector<std::string>& argv,
                                           const std::string& program) {
  std::vector<std::string> args = {bwrap, "--unshare-all", "--die-with-parent", "--new-session", "--cap-drop", "ALL"};
  struct Shown {
    fs::path at, real;  // where the program sees it, and what it is
  };
  std::vector<Shown> roots;
  std::error_code ec;
  for (const char* f : kSystemFolders) {
    if (fs::is_symlink(f, ec)) {
      args.insert(args.end(), {"--symlink", fs::read_symlink(f, ec).string(), f});  // seen through /usr
    } else if (fs::is_directory(f, ec)) {
      args.insert(args.end(), {"--ro-bind", f, f});
      roots.push_back({f, resolved(f)});
    }
  }
  args.insert(args.end(), {"--dev", "/dev", "--proc", "/proc", "--tmpfs", "/tmp"});
  const fs::path work_dir = normal(work);
  std::vector<fs::path> hidden;
  {
    std::lock_guard<std::mutex> lock(g_hidden_mutex);
    hidden = g_hidden;
  }
  const auto show = [&](const fs::path& given, bool check) {
    const Shown s{normal(given), resolved(given)};
    for (const auto& r : roots)
      if (inside(s.at, r.at) && inside(s.real, r.real)) return;  // already seen there
    for (const auto& h : hidden) {
      if (check && inside(s.real, h))
        throw std::runtime_error("'" + given.string() + "' (in `readable`, or named by the command) lies inside the "
                                 "run's output folder '" + h.string() + "', which no program may see");
    }
    args.insert(args.end(), {"--ro-bind", s.real.string(), s.at.string()});
    roots.push_back(s);
  };
  for (const auto& r : limits.readable) {
    if (!fs::exists(r, ec))
      throw std::runtime_error("readable: '" + r.string() + "' does not exist (the program would not find it)");
    show(r, true);
  }
  for (const auto& r : limits.harness_readable)
    if (fs::exists(r, ec)) show(r, false);
  // The program and every argument that names a file by its path (a script, a model)
  // are shown alone; their folders only through `readable`.
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = i == 0 ? program : argv[i];
    if (!names_a_file(a)) continue;
    const fs::path f = normal(a);
    if (i > 0) argv[i] = f.string();
    if (!inside(f, work_dir)) show(f, true);
  }
  // The output folder, where a shown folder holds it, covered by an empty one (the
  // outermost only: bubblewrap would make a nested one's folder inside it).
  for (const auto& h : hidden) {
    bool nested = false;
    for (const auto& o : hidden) nested = nested || (o != h && inside(h, o));
    if (nested || !fs::is_directory(h, ec)) continue;
    for (const auto& r : roots) {
      if (!inside(h, r.real)) continue;
      const fs::path at = normal(r.at / h.lexically_relative(r.real));
      args.insert(args.end(), {"--tmpfs", at.string()});
    }
  }
  args.insert(args.end(), {"--bind", work, work, "--chdir", work, "--setenv", "TMPDIR", work, "--setenv", "HOME", work});
  for (const auto& [name, value] : limits.environment) args.insert(args.end(), {"--setenv", name, value});
  args.insert(args.end(), {"--", program});
  return args;
}

}  // namespace

std::string find_program(const std::string& name) {
  return find_program_where(name, [](const fs::path&) { return true; });
}

void hide_from_programs(const fs::path& folder) {
  const fs::path h = resolved(folder);
  std::lock_guard<std::mutex> lock(g_hidden_mutex);
  for (const auto& known : g_hidden)
    if (known == h) return;
  g_hidden.push_back(h);
}

ConfinedProgram::ConfinedProgram(const std::vector<std::string>& argv, const fs::path& work_dir,
                                 const ProgramLimits& limits, int stdio)
    : output_cap_(limits.output_bytes) {
  if (argv.empty()) throw std::runtime_error("empty command");
  const std::string work = fs::absolute(work_dir).string();
  std::vector<std::string> args;
  if (limits.sandbox == ProgramLimits::Sandbox::Bwrap) {
    const std::string bwrap = find_program("bwrap");
    if (bwrap.empty()) {
      throw std::runtime_error(
          "bubblewrap (bwrap) is not installed: run scripts/setup.sh, or set `sandbox: none` to run the program "
          "without the sandbox");
    }
    // A name looked up in PATH only where the sandbox shows it (a shim in the user's
    // home, say, would start and then miss its own files).
    std::vector<fs::path> visible;
    std::error_code ec;
    for (const char* f : kSystemFolders)
      if (fs::exists(f, ec)) visible.push_back(normal(fs::canonical(f, ec)));
    for (const auto* list : {&limits.readable, &limits.harness_readable})
      for (const auto& r : *list)
        if (fs::exists(r, ec)) visible.push_back(normal(fs::canonical(r, ec)));
    const std::string program = find_program_where(argv[0], [&](const fs::path& p) {
      std::error_code e;
      const fs::path real = fs::canonical(p, e);
      if (e) return false;
      for (const auto& v : visible)
        if (inside(real, v)) return true;
      return false;
    });
    if (program.empty()) {
      const std::string elsewhere = find_program(argv[0]);
      if (elsewhere.empty()) throw std::runtime_error("cannot start '" + argv[0] + "': not an executable file in PATH");
      throw std::runtime_error("cannot start '" + argv[0] + "': found only at " + elsewhere +
                               ", outside what the sandbox shows (the system's folders and `readable`): give the "
                               "program's path, or add its folder to `readable`");
    }
    std::vector<std::string> shown = argv;
    args = sandbox_arguments(bwrap, limits, work, shown, program);
    args.insert(args.end(), shown.begin() + 1, shown.end());
  } else {
    const std::string program = find_program(argv[0]);
    if (program.empty()) throw std::runtime_error("cannot start '" + argv[0] + "': not an executable file in PATH");
    args = {program};
    args.insert(args.end(), argv.begin() + 1, argv.end());
  }

  WardenPlan plan;
  plan.exec_path = args[0].c_str();
  for (auto& a : args) plan.argv.push_back(a.data());
  plan.argv.push_back(nullptr);
  // Without the sandbox, the extra variables replace the harness's of the same name.
  std::vector<std::string> env_text;
  std::vector<char*> envp;
  if (limits.sandbox == ProgramLimits::Sandbox::Bwrap || limits.environment.empty()) {
    plan.envp = environ;
  } else {
    for (char** e = environ; e && *e; ++e) {
      const std::string_view entry(*e);
      const std::string_view name = entry.substr(0, entry.find('='));
      bool replaced = false;
      for (const auto& kv : limits.environment) replaced = replaced || kv.first == name;
      if (!replaced) env_text.emplace_back(entry);
    }
    for (const auto& [name, value] : limits.environment) env_text.push_back(name + "=" + value);
    for (auto& e : env_text) envp.push_back(e.data());
    envp.push_back(nullptr);
    plan.envp = envp.data();
  }
  plan.work_dir = work.c_str();
  plan.cpu = limit_of(limits.cpu_seconds, 2);
  plan.memory = limit_of(limits.memory_mb * 1e6, 0);
  plan.file = limit_of(limits.file_mb * 1e6, 0);
  bwrap_ = limits.sandbox == ProgramLimits::Sandbox::Bwrap;
  int out_pipe[2] = {-1, -1}, err_pipe[2] = {-1, -1}, status_pipe[2] = {-1, -1};
  const auto close_all = [&] {
    for (int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1], status_pipe[0], status_pipe[1]})
      if (fd >= 0) close(fd);
  };
  if ((stdio < 0 && pipe2(out_pipe, O_CLOEXEC) != 0) || pipe2(err_pipe, O_CLOEXEC) != 0 ||
      pipe2(status_pipe, O_CLOEXEC) != 0) {
    close_all();
    throw std::runtime_error(std::string("cannot make pipes: ") + std::strerror(errno));
  }
  plan.in = stdio;
  plan.out = stdio >= 0 ? stdio : out_pipe[1];
  plan.err = err_pipe[1];
  plan.status = status_pipe[1];
  // SIGTERM is the harness's "stop" to the warden: blocked until its handler is set.
  sigset_t term, old;
  sigemptyset(&term);
  sigaddset(&term, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &term, &old);
  plan.harness = getpid();
  const pid_t pid = fork();
  if (pid == 0) warden_main(plan);
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  if (pid < 0) {
    close_all();
    throw std::runtime_error(std::string("cannot fork: ") + std::strerror(errno));
  }
  warden_ = pid;
  for (int fd : {out_pipe[1], err_pipe[1], status_pipe[1]})
    if (fd >= 0) close(fd);
  out_ = out_pipe[0];
  err_ = err_pipe[0];
  status_fd_ = status_pipe[0];
  pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));  // glibc 2.36's wrapper lacks C linkage
  if (pidfd_ < 0) {  // Linux >= 5.3; without it the warden's end cannot be polled
    kill_warden(pid);
    const int e = errno;
    reap();
    for (int fd : {out_, err_, status_fd_})
      if (fd >= 0) close(fd);
    throw std::runtime_error(std::string("pidfd_open failed: ") + std::strerror(e));
  }
  const std::lock_guard lock(g_live_mutex);
  g_live.emplace_back(warden_, pidfd_);
}

ConfinedProgram::~ConfinedProgram() {
  stop();
  for (int fd : {out_, err_, pidfd_, status_fd_})
    if (fd >= 0) close(fd);
}

bool ConfinedProgram::read_output(short out_events, short err_events) {
  for (int* fd : {&out_, &err_}) {
    if (*fd < 0 || !(fd == &out_ ? out_events : err_events)) continue;
    char chunk[65536];
    const ssize_t k = read(*fd, chunk, sizeof chunk);
    if (k <= 0) {
      close(*fd);
      *fd = -1;
      continue;
    }
    output_read_ += static_cast<std::size_t>(k);
    if (fd == &err_) {
      err_tail_.append(chunk, static_cast<std::size_t>(k));
      if (err_tail_.size() > 4096) err_tail_.erase(0, err_tail_.size() - 2048);
    }
  }
  return output_read_ <= output_cap_;
}

void ConfinedProgram::reap() {
  {
    const std::lock_guard lock(g_live_mutex);
    std::erase_if(g_live, [this](const auto& w) { return w.first == warden_; });
  }
  int ws = 0;
  while (waitpid(warden_, &ws, 0) < 0 && errno == EINTR) {
  }
  int st = 0;
  status_ = read(status_fd_, &st, sizeof st) == static_cast<ssize_t>(sizeof st) ? st : ws;
  ended_ = true;
}

ConfinedProgram::End ConfinedProgram::wait_fd(int fd, short events, Clock::time_point deadline) {
  if (ended_ && fd >= 0) {
    pollfd p{fd, events, 0};
    if (poll(&p, 1, 0) > 0) return End::Ready;
  }
  while (!ended_) {
    pollfd fds[4] = {{fd, events, 0}, {out_, POLLIN, 0}, {err_, POLLIN, 0}, {pidfd_, POLLIN, 0}};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) {
      stop();
      return End::TimedOut;
    }
    if (poll(fds, 4, static_cast<int>(std::min<long long>(left, 1000))) < 0 && errno != EINTR) {
      stop();
      return End::Exited;
    }
    if (fd >= 0 && fds[0].revents) return End::Ready;
    if ((fds[1].revents || fds[2].revents) && !read_output(fds[1].revents, fds[2].revents)) {
      stop();
      return End::TooMuchOutput;
    }
    if (fds[3].revents) reap();
  }
  // Everything it started is dead: its pipes end after what is in them. Never block
  // here: a descriptor nothing writes to any more but that is not at its end is left.
  while (out_ >= 0 || err_ >= 0) {
    pollfd fds[2] = {{out_, POLLIN, 0}, {err_, POLLIN, 0}};
    if (poll(fds, 2, 0) <= 0 || !read_output(fds[0].revents, fds[1].revents)) break;
  }
  return End::Exited;
}

ConfinedProgram::End ConfinedProgram::wait(Clock::time_point deadline) { return wait_fd(-1, 0, deadline); }

void ConfinedProgram::stop() {
  if (ended_ || warden_ < 0) return;
  kill(warden_, SIGTERM);
  pollfd p{pidfd_, POLLIN, 0};
  if (poll(&p, 1, 3000) <= 0) {  // a warden that does not answer: kill its group
    kill_warden(warden_);
  }
  reap();
}

std::string ConfinedProgram::failure() const {
  if (status_ < 0) return "still running";
  int sig = WIFSIGNALED(status_) ? WTERMSIG(status_) : 0;
  if (WIFEXITED(status_)) {
    const int code = WEXITSTATUS(status_);
    if (code == 0) return "";
    if (bwrap_ && code > 128 && code < 128 + 65) sig = code - 128;  // bwrap exits 128 + the signal that ended its child
  }
  if (WIFEXITED(status_) && sig == 0) {
    const int code = WEXITSTATUS(status_);
    if (code == 126 || code == 127) return "exit status " + std::to_string(code) + " (it could not be executed)";
    return "exit status " + std::to_string(code);
  }
  if (sig != 0) {
    std::string why = "killed by signal " + std::to_string(sig);
    if (sig == SIGXCPU) why += " (over its CPU time limit)";
    if (sig == SIGKILL) why += " (over its CPU time limit, or stopped)";
    if (sig == SIGXFSZ) why += " (a file over its size limit)";
    if (sig == SIGSEGV || sig == SIGABRT || sig == SIGBUS) why += " (a crash, or out of its memory limit)";
    return why;
  }
  return "wait status " + std::to_string(status_);
}

std::string ConfinedProgram::error_tail() const {
  std::string s = err_tail_;
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
  if (s.size() > 400) s = "..." + s.substr(s.size() - 400);
  return s;
}

void stop_every_program() {
  const std::lock_guard lock(g_live_mutex);  // held: no warden leaves the list (or closes its pidfd) meanwhile
  for (const auto& [warden, pidfd] : g_live) kill(warden, SIGTERM);
  const auto deadline = ConfinedProgram::Clock::now() + std::chrono::seconds(3);
  for (const auto& [warden, pidfd] : g_live) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - ConfinedProgram::Clock::now()).count();
    pollfd p{pidfd, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(std::max<long long>(left, 0))) <= 0) kill_warden(warden);  // as stop() does
  }
}

}  // namespace grapebench
