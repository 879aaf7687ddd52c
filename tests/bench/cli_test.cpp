// The command-line program: help documents every parameter; errors are clear.
#include "synth/params.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <memory>
#include <string>

namespace grapebench {
namespace {

struct CommandResult {
  std::string out;
  int status;
};

CommandResult run_cli(const std::string& args) {
  const std::string cmd = std::string(GRAPEBENCH_EXE) + " " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), pipe.get())) out += buf.data();
  const int status = pclose(pipe.release());
  return {out, WEXITSTATUS(status)};
}

TEST(Cli, SynthHelpDocumentsEveryParameterWithUnitDefaultAndRange) {
  const CommandResult r = run_cli("synth --help");
  EXPECT_EQ(r.status, 0);
  const BunchParams def = preset("table-red");
  for (const auto& k : bunch_param_table().keys(def)) {
    const auto at = r.out.find("  " + k.key + " ");
    ASSERT_NE(at, std::string::npos) << k.key;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    EXPECT_NE(line.find(k.unit), std::string::npos) << line;
    EXPECT_NE(line.find(k.range), std::string::npos) << line;
    EXPECT_NE(line.find(k.default_value), std::string::npos) << line;
  }
  for (const auto& p : preset_names()) EXPECT_NE(r.out.find(p), std::string::npos);
}

// Reproducer: CLI11's own usage errors exited 105-109, not the 2 of every other input error.
TEST(Cli, UsageErrorsExitTwoAndHelpZero) {
  for (const char* args : {"run --bogus", "frobnicate", "synth --count 0", "check", "merge scenes/default.yaml"}) {
    const CommandResult r = run_cli(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.out;
    EXPECT_FALSE(r.out.empty()) << args;
  }
  EXPECT_NE(run_cli("frobnicate").out.find("frobnicate"), std::string::npos);
  EXPECT_EQ(run_cli("--help").status, 0);
  EXPECT_EQ(run_cli("run --help").status, 0);
}

TEST(Cli, BadInputGivesAClearErrorAndExitCode) {
  CommandResult r = run_cli("synth --set compactness=3 --no-mesh --out /tmp/grapebench_cli_test");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("compactness"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[0, 1]"), std::string::npos) << r.out;
  r = run_cli("synth --set nonsense=1 --no-mesh --out /tmp/grapebench_cli_test");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("unknown parameter 'nonsense'"), std::string::npos) << r.out;
  r = run_cli("synth " GRAPEBENCH_SOURCE_DIR "/CMakeLists.txt --out /tmp/grapebench_cli_test");
  EXPECT_NE(r.status, 0) << r.out;
}

TEST(Cli, ScanWritesEveryFileOfEveryView) {
  const std::string out = "/tmp/grapebench_cli_scan";
  std::filesystem::remove_all(out);
  const CommandResult r = run_cli("scan " GRAPEBENCH_SOURCE_DIR "/scenes/seed002_kinect_bottom.yaml --bunch 1 --out " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string dir = out + "/seed002_kinect_bottom/bunch_0001/";
  EXPECT_TRUE(std::filesystem::exists(dir + "ground_truth.json"));
  EXPECT_TRUE(std::filesystem::exists(dir + "bunch_0001_scan.json"));
  for (const char* view : {"view_00", "view_07", "bottom"}) {
    for (const char* ext : {".pcd", ".ply", "_depth.png", "_rgb.png", "_label.png"}) {
      EXPECT_TRUE(std::filesystem::exists(dir + "bunch_0001_" + view + ext)) << view << ext;
    }
  }
  EXPECT_EQ(run_cli("scan --help").out.find("kinect_v2") != std::string::npos, true);
}

TEST(Cli, RunOnTheDefaultSuiteSummarises) {
  const CommandResult r = run_cli("run " GRAPEBENCH_SOURCE_DIR "/scenes/default.yaml --out /tmp/grapebench_cli_run");
  EXPECT_EQ(r.status, 0) << r.out;
  // The leaderboard names every estimator of the suite, and the files are there.
  for (const char* name : {"GM", "CH", "AS", "VB_10mm", "VB_5mm", "PCA_box", "report.html"}) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name << "\n" << r.out;
  }
  EXPECT_NE(r.out.find("7/7"), std::string::npos) << r.out;
}

TEST(Cli, AKilledRunResumesToTheResultsOfAnUninterruptedOne) {
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/scenes/default.yaml";
  ASSERT_EQ(run_cli("run " + scene + " --out /tmp/grapebench_cli_whole --no-resume --quiet").status, 0);
  std::system("rm -rf /tmp/grapebench_cli_killed");
  // SIGKILL part-way: no chance to clean up; finished cases are on disk.
  std::system(("timeout -s KILL 1.5 " GRAPEBENCH_EXE " run " + scene + " --out /tmp/grapebench_cli_killed --quiet "
               ">/dev/null 2>&1").c_str());
  const CommandResult resumed = run_cli("run " + scene + " --out /tmp/grapebench_cli_killed --quiet");
  ASSERT_EQ(resumed.status, 0) << resumed.out;
  const auto slurp = [](const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_EQ(slurp("/tmp/grapebench_cli_killed/default/results.csv"), slurp("/tmp/grapebench_cli_whole/default/results.csv"));
  EXPECT_EQ(slurp("/tmp/grapebench_cli_killed/default/summary.json"), slurp("/tmp/grapebench_cli_whole/default/summary.json"));
}

TEST(Cli, CheckExitsOneOnARegressionAndZeroOtherwise) {
  const CommandResult run = run_cli("run " GRAPEBENCH_SOURCE_DIR "/scenes/default.yaml --out /tmp/grapebench_cli_run --quiet");
  ASSERT_EQ(run.status, 0) << run.out;
  const std::string summary = "/tmp/grapebench_cli_run/default/summary.json";
  EXPECT_EQ(run_cli("check " + summary + " --baseline " + summary).status, 0);
  EXPECT_EQ(run_cli("check /tmp/grapebench_cli_run/default --baseline " GRAPEBENCH_SOURCE_DIR
                    "/tests/bench/data/perturbed_baseline.json").status, 1);
}

}  // namespace
}  // namespace grapebench
