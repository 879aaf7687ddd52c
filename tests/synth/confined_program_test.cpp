// Hostile programs against the confinement: daemons that leave their process group,
// floods of stderr, writes outside the work folder, a look at the harness through
// /proc, the network, and the resource limits; with bubblewrap and without.
#include "synth/confined_program.h"
#include "synth/processes_with.h"
#include "synth/temp_folder.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace grapebench {
namespace {

namespace fs = std::filesystem;
using Clock = ConfinedProgram::Clock;
using Sandbox = ProgramLimits::Sandbox;

// A fresh folder for one test, removed with it (they were left behind, 17 a run).
struct Dir {
  explicit Dir(const std::string& name) : folder("gb-confined-" + name) {}
  operator fs::path() const { return folder.path; }
  fs::path operator/(const std::string& p) const { return folder.path / p; }
  std::string string() const { return folder.path.string(); }
  TempFolder folder;
};

bool bwrap_runs() {
  return std::system("bwrap --ro-bind / / --dev /dev --proc /proc --unshare-all true >/dev/null 2>&1") == 0;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Confined : public ::testing::TestWithParam<Sandbox> {
 protected:
  void SetUp() override {
    if (GetParam() == Sandbox::Bwrap && !bwrap_runs())
      GTEST_SKIP() << "bwrap cannot make namespaces on this machine (the `sandbox: none` cases still run)";
    limits.sandbox = GetParam();
  }
  std::unique_ptr<ConfinedProgram> shell(const std::string& script, const fs::path& work) {
    return std::make_unique<ConfinedProgram>(std::vector<std::string>{"/bin/sh", "-c", script}, work, limits);
  }
  ProgramLimits limits;
};

TEST_P(Confined, NothingItStartedSurvivesItsEnd) {
  const Dir work("survive");
  const std::string marker = "gbdaemon" + std::to_string(getpid()) + "a";
  // A daemon in a session of its own (out of the program's group), then a plain exit.
  auto prog = shell("setsid sh -c 'while :; do sleep 0.05; done' " + marker + " & sleep 0.2; exit 0", work);
  ASSERT_EQ(prog->wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_EQ(prog->failure(), "");
  EXPECT_EQ(processes_with(marker), 0);
}

TEST_P(Confined, TimeoutStopsTheWholeTree) {
  const Dir work("timeout");
  const std::string marker = "gbdaemon" + std::to_string(getpid()) + "b";
  auto prog = shell("setsid sh -c 'while :; do sleep 0.05; done' " + marker + " & exec sleep 30", work);
  const auto t0 = Clock::now();
  EXPECT_EQ(prog->wait(Clock::now() + std::chrono::milliseconds(500)), ConfinedProgram::End::TimedOut);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 5);
  EXPECT_EQ(processes_with(marker), 0);
}

TEST_P(Confined, StderrFloodIsStoppedAtTheCapWithItsTail) {
  const Dir work("flood");
  limits.output_bytes = 1 << 20;
  auto prog = shell("yes flooding >&2", work);
  EXPECT_EQ(prog->wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::TooMuchOutput);
  EXPECT_NE(prog->error_tail().find("flooding"), std::string::npos);
  EXPECT_LE(prog->error_tail().size(), 403u);
}

// Extra variables reach the program and win over the harness's (COLMAP's seed shim
// comes in by LD_PRELOAD this way); the rest of the environment is kept.
TEST_P(Confined, ExtraEnvironmentReachesTheProgram) {
  const Dir work("environment");
  setenv("GB_CONFINED_KEPT", "kept", 1);
  setenv("GB_CONFINED_SET", "harness", 1);
  limits.environment = {{"GB_CONFINED_SET", "program"}, {"GB_CONFINED_NEW", "a b=c"}};
  auto prog = shell("echo \"$GB_CONFINED_KEPT|$GB_CONFINED_SET|$GB_CONFINED_NEW\" >&2", work);
  ASSERT_EQ(prog->wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_EQ(prog->error_tail(), "kept|program|a b=c");
  EXPECT_STREQ(std::getenv("GB_CONFINED_SET"), "harness");  // the harness's own is untouched
}

TEST_P(Confined, FileSizeAndCpuLimitsKillWithTheReason) {
  const Dir work("limits");
  limits.file_mb = 1;
  auto big = shell("exec head -c 3000000 /dev/zero > big", work);
  ASSERT_EQ(big->wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_NE(big->failure().find("size limit"), std::string::npos) << big->failure();
  EXPECT_LE(fs::file_size(work / "big"), 1000000u);
  limits.cpu_seconds = 1;
  auto spin = shell("while :; do :; done", work);
  ASSERT_EQ(spin->wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_NE(spin->failure().find("CPU time limit"), std::string::npos) << spin->failure();
}

std::string sandbox_name(const ::testing::TestParamInfo<Sandbox>& p) { return p.param == Sandbox::Bwrap ? "bwrap" : "none"; }
INSTANTIATE_TEST_SUITE_P(BothSandboxes, Confined, ::testing::Values(Sandbox::Bwrap, Sandbox::None), sandbox_name);

// Under bubblewrap: writes outside the work folder fail, the harness is not visible
// in /proc, and there is no network but loopback.
TEST(ConfinedBwrap, WritesStayInTheWorkFolderAndTheHarnessIsOutOfSight) {
  if (!bwrap_runs()) GTEST_SKIP() << "bwrap cannot make namespaces on this machine";
  const Dir work("bwrap-work"), outside("bwrap-outside");
  const std::string script = "echo forged > '" + (outside / "forged").string() + "'; echo forged > /tmp/gb-forged-" +
                             std::to_string(getpid()) +
                             "; cat /proc/$PPID/cmdline /proc/1/cmdline > seen.txt; "
                             "grep -c : /proc/net/dev > interfaces.txt; ls /proc | grep -c '^[0-9]' > pids.txt; "
                             "echo inside > ok";
  ProgramLimits limits;
  ConfinedProgram prog({"/bin/sh", "-c", script}, work, limits);
  ASSERT_EQ(prog.wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_EQ(read_text(work / "ok"), "inside\n");
  EXPECT_FALSE(fs::exists(outside / "forged"));
  EXPECT_FALSE(fs::exists("/tmp/gb-forged-" + std::to_string(getpid())));
  EXPECT_EQ(read_text(work / "seen.txt").find("algorithms_tests"), std::string::npos);  // the harness
  EXPECT_EQ(read_text(work / "interfaces.txt"), "1\n");                         // lo only
  EXPECT_LE(std::stoi(read_text(work / "pids.txt")), 4);                        // bwrap's init, sh, ls, grep
}

// Issue 39: the sandbox showed the whole file system. Now a program sees the system's
// folders, the files its command names, `readable` (less what hide_from_programs
// hides inside it) and its work folder, which is also its HOME; a program found in
// PATH only outside that view is refused with where it was found.
TEST(ConfinedBwrap, OnlyTheSystemItsFilesAndReadableAreSeen) {
  if (!bwrap_runs()) GTEST_SKIP() << "bwrap cannot make namespaces on this machine";
  const Dir work("view-work"), shown("view-shown"), unseen("view-unseen");
  fs::create_directories(shown / "out");
  std::ofstream(shown / "a.txt") << "shown\n";
  std::ofstream(shown / "out" / "truth.json") << "{}\n";
  std::ofstream(unseen / "b.txt") << "unseen\n";
  std::ofstream(unseen / "named.txt") << "named\n";
  hide_from_programs(shown / "out");
  ProgramLimits limits;
  limits.readable = {shown};
  const std::string script = "cat '" + (shown / "a.txt").string() + "' > a; ls -A '" + (shown / "out").string() +
                             "' > out; cat '" + (unseen / "b.txt").string() + "' > b 2>/dev/null; cat \"$1\" > named; "
                             "echo \"$HOME\" > home";
  ConfinedProgram prog({"/bin/sh", "-c", script, "sh", (unseen / "named.txt").string()}, work, limits);
  ASSERT_EQ(prog.wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_EQ(read_text(work / "a"), "shown\n");
  EXPECT_EQ(read_text(work / "out"), "");  // hidden: an empty folder
  EXPECT_EQ(read_text(work / "b"), "");    // not shown
  EXPECT_EQ(read_text(work / "named"), "named\n");
  EXPECT_EQ(read_text(work / "home"), work.string() + "\n");

  ProgramLimits inside = limits;
  inside.readable = {shown / "out"};
  EXPECT_THROW(
      {
        try {
          ConfinedProgram p({"/bin/true"}, work, inside);
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("output folder"), std::string::npos) << e.what();
          throw;
        }
      },
      std::runtime_error);

  // A program in PATH outside the view (a shim in a home, say).
  const Dir bin("view-bin");
  std::ofstream(bin / "gbprog") << "#!/bin/sh\necho ran > ran\n";
  fs::permissions(bin / "gbprog", fs::perms::owner_all);
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (bin.string() + ":" + saved).c_str(), 1);
  std::string error;
  try {
    ConfinedProgram p({"gbprog"}, work, ProgramLimits{});
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("found only at " + (bin / "gbprog").string()), std::string::npos) << error;
  ProgramLimits with_bin;
  with_bin.readable = {bin};
  ConfinedProgram ran({"gbprog"}, work, with_bin);
  setenv("PATH", saved.c_str(), 1);
  ASSERT_EQ(ran.wait(Clock::now() + std::chrono::seconds(20)), ConfinedProgram::End::Exited);
  EXPECT_EQ(read_text(work / "ran"), "ran\n");
}

TEST(ConfinedBwrap, WithoutBwrapTheErrorSaysHowToOptOut) {
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  setenv("PATH", "/nonexistent-gb", 1);
  std::string error;
  try {
    ConfinedProgram prog({"/bin/true"}, Dir("nobwrap"), ProgramLimits{});
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  setenv("PATH", saved.c_str(), 1);
  EXPECT_NE(error.find("sandbox: none"), std::string::npos) << error;
}

}  // namespace
}  // namespace grapebench
