// The command-line program: help documents every parameter; errors are clear.
#include "algorithms/stereo/colmap_sfm.h"
#include "bench/heap_meter.h"
#include "file_text.h"
#include "scratch.h"
#include "sensors/render/cycles_render.h"
#include "synth/confined_program.h"
#include "synth/params.h"
#include "synth/processes_with.h"
#include "synth/temp_folder.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <signal.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <memory>
#include <string>
#include <thread>
#include <unistd.h>

namespace grapebench {
namespace {

struct CommandResult {
  std::string out;
  int status;
};

// `limit_s` > 0: killed after that many seconds (exit 124, as timeout(1) says); `env`:
// assignments before the command ("NAME=value ").
CommandResult run_cli(const std::string& args, int limit_s = 0, const std::string& env = "") {
  const std::string cmd = env + (limit_s > 0 ? "timeout -k 5 " + std::to_string(limit_s) + " " : std::string()) +
                          std::string(GRAPEBENCH_EXE) + " " + args + " 2>&1";
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
  const std::string out = " --out " + scratch("cli_test").string();
  CommandResult r = run_cli("synth --set compactness=3 --no-mesh" + out);
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("compactness"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[0, 1]"), std::string::npos) << r.out;
  r = run_cli("synth --set nonsense=1 --no-mesh" + out);
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("unknown parameter 'nonsense'"), std::string::npos) << r.out;
  r = run_cli("synth " GRAPEBENCH_SOURCE_DIR "/CMakeLists.txt" + out);
  EXPECT_NE(r.status, 0) << r.out;
  // Before any bunch is generated, naming the option and its range (NaN included).
  for (const char* alpha : {"0.0001", "nan", "0.2", "-1"}) {
    r = run_cli(std::string("synth --alpha-wrap ") + alpha + " --no-mesh" + out);
    EXPECT_EQ(r.status, 2) << alpha << "\n" << r.out;
    EXPECT_NE(r.out.find("--alpha-wrap: 0 (off) or a carving radius in [0.0005, 0.05] m"), std::string::npos) << r.out;
  }
}

TEST(Cli, ScanWritesEveryFileOfEveryView) {
  const std::string out = scratch("cli_scan").string();
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
  const CommandResult r = run_cli("run " GRAPEBENCH_SOURCE_DIR "/scenes/default.yaml --out " + scratch("cli_run").string());
  EXPECT_EQ(r.status, 0) << r.out;
  // The leaderboard names every estimator of the suite, and the files are there.
  for (const char* name : {"GM", "CH", "AS", "VB_10mm", "VB_5mm", "PCA_box", "report.html"}) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name << "\n" << r.out;
  }
  EXPECT_NE(r.out.find("7/7"), std::string::npos) << r.out;
}

TEST(Cli, AKilledRunResumesToTheResultsOfAnUninterruptedOne) {
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/scenes/default.yaml";
  const std::string whole = scratch("cli_whole").string(), killed = scratch("cli_killed").string();
  ASSERT_EQ(run_cli("run " + scene + " --out " + whole + " --no-resume --quiet").status, 0);
  // SIGKILL part-way: no chance to clean up; finished cases are on disk.
  std::system(("timeout -s KILL 1.5 " GRAPEBENCH_EXE " run " + scene + " --out " + killed + " --quiet "
               ">/dev/null 2>&1").c_str());
  const CommandResult resumed = run_cli("run " + scene + " --out " + killed + " --quiet");
  ASSERT_EQ(resumed.status, 0) << resumed.out;
  EXPECT_EQ(slurp(killed + "/default/results.csv"), slurp(whole + "/default/results.csv"));
  EXPECT_EQ(slurp(killed + "/default/summary.json"), slurp(whole + "/default/summary.json"));
}

// Reproducer: a run stopped by SIGTERM or Ctrl-C left its external program running to
// its own end and its temporary folders (147 MB for a Cycles pair) in TMPDIR; one
// killed outright left the program running too. Now the program ends with the run, and
// the folders with it where the signal can be caught; the case its stop failed is not
// stored (a resumed run would reuse it); a SIGHUP ignored on entry (nohup) stays ignored.
TEST(Cli, AStoppedRunLeavesNoProgramAndNoTemporaryFolder) {
  for (const int sig : {SIGTERM, SIGINT, SIGHUP, SIGKILL}) {
    const TempFolder dir("gb-cli-stop");
    const std::filesystem::path tmp = dir.path / "tmp", scene = dir.path / "stop.yaml", out = dir.path / "out";
    std::filesystem::create_directories(tmp);
    // A sleep of a unique length (the marker, fixed width so that no marker is a
    // prefix of another) that outlives any test: only the run's end stops it.
    char marker[32];
    std::snprintf(marker, sizeof marker, "600.%07d%02d", static_cast<int>(getpid()), sig);
    std::ofstream(scene) << "name: stop\nseed: 5\nbunches:\n  - preset: summer-black\n    count: 1\n"
                            "sensor:\n  type: kinect_v2\n  width: 256\n  height: 212\n"
                            "rig:\n  type: turntable\n  views: 2\n  step_deg: 90\n"
                            "estimators:\n  - type: external\n    name: sleeper\n    sandbox: none\n"
                            "    command: [/bin/sh, -c, 'sleep "
                         << marker << "; exit 3', sh]\n";
    // Everything exec needs, made before fork (the test process may have threads).
    std::vector<std::string> env_text = {"TMPDIR=" + tmp.string()};
    for (char** e = environ; *e; ++e)
      if (std::string(*e).rfind("TMPDIR=", 0) != 0) env_text.emplace_back(*e);
    std::vector<char*> envp;
    for (auto& e : env_text) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::vector<std::string> arg_text = {GRAPEBENCH_EXE, "run", scene.string(), "--out", out.string(), "--quiet"};
    std::vector<char*> argv;
    for (auto& a : arg_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
      for (int s : {SIGINT, SIGTERM, SIGHUP}) signal(s, SIG_DFL);
      if (sig == SIGTERM) signal(SIGHUP, SIG_IGN);  // as nohup starts it
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, 1);
      dup2(null, 2);
      execve(argv[0], argv.data(), envp.data());
      _exit(127);
    }
    ASSERT_GT(pid, 0);
    // On a failed assertion: nothing of this iteration is left running.
    const std::shared_ptr<void> cleanup(nullptr, [&](void*) {
      if (waitpid(pid, nullptr, WNOHANG) == 0) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
      }
      const int ignored = std::system(("pkill -KILL -f " + std::string(marker)).c_str());
      (void)ignored;
    });
    for (int i = 0; i < 600 && processes_with(marker) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_GT(processes_with(marker), 0) << "the external program never started";
    ASSERT_FALSE(std::filesystem::is_empty(tmp));  // its request and answer folders
    if (sig == SIGTERM) {
      kill(pid, SIGHUP);
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      EXPECT_EQ(waitpid(pid, nullptr, WNOHANG), 0) << "an ignored SIGHUP ended the run";
    }
    kill(pid, sig);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << sig << ": status " << status;
    if (sig == SIGKILL) {  // nothing ran in the run to stop it: its warden does, within 200 ms
      for (int i = 0; i < 60 && processes_with(marker) > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      EXPECT_EQ(processes_with(marker), 0) << "the program outlived the killed run";
      continue;
    }
    EXPECT_EQ(processes_with(marker), 0) << sig << ": the program outlived the stopped run";
    EXPECT_TRUE(std::filesystem::is_empty(tmp)) << sig << ": " << std::filesystem::directory_iterator(tmp)->path();
    for (const auto& e : std::filesystem::recursive_directory_iterator(out))
      EXPECT_FALSE(e.path().parent_path().filename() == "cases" && e.path().extension() == ".json")
          << sig << ": the case its stop failed was stored: " << e.path();
  }
}

// A case computed by another build is recomputed, not reused, unless the user asks;
// the "other build" is this binary with a byte appended (nothing rebuilt).
TEST(Cli, CasesOfAnotherBuildAreRecomputedUnlessReuseIsAsked) {
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml";
  const std::string out = scratch("cli_build_id").string(), other = scratch("cli_other_build").string();
  std::filesystem::copy_file(GRAPEBENCH_EXE, other, std::filesystem::copy_options::overwrite_existing);
  std::ofstream(other, std::ios::app | std::ios::binary) << '\n';
  const CommandResult first = run_cli("run " + scene + " --out " + out + " --quiet");
  ASSERT_EQ(first.status, 0) << first.out;
  EXPECT_NE(first.out.find("2 cases: 2 computed, 0 reused"), std::string::npos) << first.out;
  const CommandResult same = run_cli("run " + scene + " --out " + out + " --quiet");
  EXPECT_NE(same.out.find("2 cases: 0 computed, 2 reused"), std::string::npos) << same.out;
  const auto run_other = [&](const std::string& flags) {
    const std::string cmd = other + " run " + scene + " --out " + out + " --quiet" + flags + " 2>&1";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    std::string text;
    std::array<char, 4096> buf;
    while (std::fgets(buf.data(), buf.size(), pipe.get())) text += buf.data();
    return text;
  };
  const std::string reused = run_other(" --reuse-other-builds");
  EXPECT_NE(reused.find("2 cases: 0 computed, 2 reused"), std::string::npos) << reused;
  EXPECT_NE(reused.find("computed by another build"), std::string::npos) << reused;
  const std::string recomputed = run_other("");
  EXPECT_NE(recomputed.find("2 cases: 2 computed, 0 reused"), std::string::npos) << recomputed;
  // Now the original binary is the other build.
  const CommandResult back = run_cli("run " + scene + " --out " + out + " --quiet");
  EXPECT_NE(back.out.find("2 cases: 2 computed, 0 reused"), std::string::npos) << back.out;
  std::ifstream manifest(out + "/two_bunches_hull/manifest.json");
  std::stringstream text;
  text << manifest.rdbuf();
  for (const char* key : {"\"build_identity\"", "\"git_describe\"", "\"compiler\"", "\"pcl\"", "\"embree\"", "\"cpu\""}) {
    EXPECT_NE(text.str().find(key), std::string::npos) << key;
  }
}

// Issue 23's reproducer: a case file whose `condition` is out of range (the key still
// matching) made a resumed run index the conditions unchecked and crash.
TEST(Cli, ACaseFileWithForeignIndicesIsRecomputedNotTrusted) {
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml";
  const std::string out = scratch("cli_condition").string();
  ASSERT_EQ(run_cli("run " + scene + " --out " + out + " -q").status, 0);
  for (const char* value : {"999", "2147483647", "-1"}) {
    const std::string file = out + "/two_bunches_hull/cases/c0000_b0000.json";
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    in.close();
    std::string json = text.str();
    const auto at = json.find("\"condition\": 0");
    ASSERT_NE(at, std::string::npos) << json.substr(0, 200);
    json.replace(at, std::string("\"condition\": 0").size(), std::string("\"condition\": ") + value);
    std::ofstream(file) << json;
    const CommandResult again = run_cli("run " + scene + " --out " + out + " -q");
    EXPECT_EQ(again.status, 0) << value << "\n" << again.out;
    EXPECT_NE(again.out.find("2 cases: 1 computed, 1 reused"), std::string::npos) << value << "\n" << again.out;
  }
}

// Issue 43: a shard whose task was cancelled or failed (its folder absent) is named
// by the merge, with the shard count the finished shard wrote, so it can be rerun alone.
TEST(Cli, MergeNamesTheShardWhoseFolderIsAbsent) {
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml";
  const std::string dir = scratch("cli_missing_shard").string();
  const std::string from = " --from " + dir + "/0/two_bunches_hull --from " + dir + "/1/two_bunches_hull";
  ASSERT_EQ(run_cli("run " + scene + " --shard 0/2 --out " + dir + "/0 -q").status, 0);
  CommandResult r = run_cli("merge " + scene + from + " --out " + dir + "/merged");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("1 of 2 cases are in none of the shard folders"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("missing shards: 1/2\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("without a finished shard: " + dir + "/1/two_bunches_hull (absent)"), std::string::npos) << r.out;
  // No finished shard to read the count from: the missing cases' indices.
  r = run_cli("merge " + scene + " --from " + dir + "/1/two_bunches_hull --out " + dir + "/merged_none");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("missing case indices (of 0-1): 0 1"), std::string::npos) << r.out;
  // Shard 1 alone, run again, completes the merge.
  ASSERT_EQ(run_cli("run " + scene + " --shard 1/2 --out " + dir + "/1 -q").status, 0);
  r = run_cli("merge " + scene + from + " --out " + dir + "/merged");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("merged 2 cases"), std::string::npos) << r.out;
}

// Issue 23's reproducer: a hostile external program writes outside its folder, edits
// the run's case files and results (it knows --out), leaves a daemon that appends to
// results.csv after the run, and floods stderr. Under bubblewrap none of it lands and
// nothing of it survives the run.
TEST(Cli, AHostileExternalProgramChangesNothingAndLeavesNothingRunning) {
  if (std::system("bwrap --ro-bind / / --dev /dev --proc /proc --unshare-all true >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "bwrap cannot make namespaces on this machine";
  namespace fs = std::filesystem;
  const fs::path dir = scratch("cli_hostile"), out = dir / "out", outside = dir / "outside";
  fs::create_directories(outside);
  const std::string marker = "gbhostile" + std::to_string(getpid());
  const std::string attack =
      "echo forged > " + (outside / "forged.txt").string() + "; " +
      "for f in " + out.string() + "/hostile/cases/*.json " + out.string() + "/hostile/results.csv; do "
      "echo forged >> $f; done; tr '\\\\0' ' ' < /proc/$PPID/cmdline > /dev/null; "
      "setsid sh -c 'sleep 0.5; while :; do echo forged >> " + out.string() + "/hostile/results.csv; sleep 0.1; done' " +
      marker + " & ";
  std::ofstream(dir / "hostile.yaml")
      << "name: hostile\nseed: 3\nbunches:\n  - preset: table-red\n    count: 2\n"
         "sensor:\n  type: ideal\n  width: 160\n  height: 120\n"
         "rig:\n  type: turntable\n  views: 4\n  step_deg: 90\n  distance: 0.6\n"
         "pipeline:\n  registration: true_poses\nestimators:\n  - type: convex_hull\n    name: CH\n"
         "  - type: external\n    name: sly\n    command: [/bin/sh, -c, \""
      << attack << "echo '{\\\"volume\\\": 0.001}' > $(dirname $0)/answer.json\"]\n"
      << "  - type: external\n    name: loud\n    command: [/bin/sh, -c, \"" << attack
      << "head -c 40000000 /dev/zero | tr '\\\\0' x >&2\"]\n";
  // A first run leaves case files; the second (a new estimator order would not
  // matter) runs the programs again with those files present.
  const CommandResult first = run_cli("run " + (dir / "hostile.yaml").string() + " --out " + out.string() + " -q");
  ASSERT_EQ(first.status, 0) << first.out;
  fs::remove_all(out / "hostile" / "cases" / "c0000_b0001.json");
  const CommandResult second = run_cli("run " + (dir / "hostile.yaml").string() + " --out " + out.string() + " -q");
  ASSERT_EQ(second.status, 0) << second.out;
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // a surviving daemon would append by now
  EXPECT_FALSE(fs::exists(outside / "forged.txt"));
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path());
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str().find("forged\n"), std::string::npos) << e.path();  // the manifest quotes the scene
  }
  std::ifstream csv(out / "hostile" / "results.csv");
  std::stringstream rows;
  rows << csv.rdbuf();
  EXPECT_NE(rows.str().find("more than 16 MiB on stdout and stderr"), std::string::npos) << rows.str();
  EXPECT_NE(rows.str().find(",sly,external,volume,cm3,1000,"), std::string::npos) << rows.str();
  int survivors = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    std::ifstream in(e.path() / "cmdline", std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    if (s.str().find(marker) != std::string::npos) ++survivors;
  }
  EXPECT_EQ(survivors, 0);
}

// Issue 39's reproducer: bubblewrap showed the whole file system read-only, and an
// external program found another case's files of the same run and answered the exact
// volumes. A program that hunts for the truth (tests/bench/data/truth_search.sh: the
// run's --out, another run's truth, the user's home, the scene, other programs'
// folders, the harness in /proc, files named like cases or truth anywhere) now finds
// none of it, per case and persistent, even with `readable` holding the --out folder;
// the same program without the sandbox finds them all (so the search can fail).
TEST(Cli, ASandboxedProgramFindsNoTruth) {
  if (std::system("bwrap --ro-bind / / --dev /dev --proc /proc --unshare-all true >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "bwrap cannot make namespaces on this machine";
  namespace fs = std::filesystem;
  // `shared` (readable by the programs) holds --out; the other run's folder is elsewhere.
  const fs::path shared = fs::absolute("grapebench_truth_search"), out = shared / "out",
                 other = scratch("truth_other");
  fs::remove_all(shared);
  fs::remove_all(other);
  fs::create_directories(other);
  fs::create_directories(shared);
  const fs::path scene = fs::absolute("grapebench_truth_scene.yaml");
  struct Cleanup {  // the working folder is left as it was found, whatever fails
    fs::path a, b, c;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(a, ec), fs::remove_all(b, ec), fs::remove(c, ec);
    }
  } cleanup{shared, other, scene};
  std::ofstream(other / "ground_truth.json") << "{\"volume_m3\": 0.0004}\n";
  std::ofstream(shared / "module.py") << "# a module the program may read\n";
  const char* home = std::getenv("HOME");
  const std::string script = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/truth_search.sh";
  // Places to look, as "@path" (a path argument would be shown to it as a named file).
  const std::string targets = "\"@" + out.string() + "\", \"@" + other.string() + "\", \"@" + scene.string() + "\"" +
                              (home && *home ? ", \"@" + std::string(home) + "\"" : std::string());
  std::ofstream(scene) << "name: truth\nseed: 5\nbunches:\n  - preset: table-red\n    count: 2\n"
                          "sensor:\n  type: ideal\n  width: 120\n  height: 90\n"
                          "rig:\n  type: turntable\n  views: 2\n  step_deg: 180\n  distance: 0.6\n"
                          "pipeline:\n  registration: true_poses\nestimators:\n"
                          "  - type: external\n    name: percase\n    readable: [\""
                       << shared.string() << "\"]\n    command: [/bin/sh, " << script << ", --find, \"--own="
                       << shared.string() << "\", " << targets
                       << "]\n  - type: external\n    name: persistent\n    version: 2\n    persistent: true\n"
                          "    command: [/bin/sh, "
                       << script << ", --find, --persistent, " << targets
                       << "]\n  - type: external\n    name: open\n    sandbox: none\n    command: [/bin/sh, " << script
                       << ", " << targets << "]\n";
  const CommandResult r = run_cli("run " + scene.string() + " --out " + out.string() + " --threads 2 -q");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string csv = slurp((out / "truth" / "results.csv").string());
  const auto notes_of = [&](const std::string& name) {
    std::vector<std::string> all;
    std::istringstream lines(csv);
    for (std::string line; std::getline(lines, line);)
      if (line.find("," + name + ",external,") != std::string::npos) all.push_back(line.substr(line.rfind(',') + 1));
    return all;
  };
  for (const char* name : {"percase", "persistent"}) {
    const auto notes = notes_of(name);
    ASSERT_EQ(notes.size(), 2u) << name << "\n" << csv;
    for (const auto& n : notes) EXPECT_EQ(n, "found: none") << name;
  }
  const auto open = notes_of("open");
  ASSERT_EQ(open.size(), 2u) << csv;
  for (const std::string& seen : {out.string(), other.string(), scene.string(), std::string("/cmdline")})
    EXPECT_NE(open[0].find(seen), std::string::npos) << seen << " in " << open[0];
}

// Issue 39: every other program the harness starts (COLMAP's steps, Blender) runs
// under the same sandbox, built by the limits its own code uses: the hunter run with
// those limits finds no planted truth, the user's home nor the harness; without the
// sandbox it finds them.
TEST(Cli, ColmapAndBlenderSeeNoTruthEither) {
  if (std::system("bwrap --ro-bind / / --dev /dev --proc /proc --unshare-all true >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "bwrap cannot make namespaces on this machine";
  namespace fs = std::filesystem;
  const fs::path planted = scratch("truth_planted");
  fs::create_directories(planted / "cases");
  std::ofstream(planted / "cases" / "c0000_b0000.json") << "{}\n";
  const char* home = std::getenv("HOME");
  const auto hunt = [&](ProgramLimits limits) {
    const TempFolder work("grapebench-hunt");
    std::vector<std::string> argv = {"/bin/sh", GRAPEBENCH_SOURCE_DIR "/tests/bench/data/truth_search.sh", "--find",
                                     "@" + planted.string(), "@" + fs::current_path().string()};
    if (home && *home) argv.push_back("@" + std::string(home));
    for (const auto& f : limits.harness_readable) argv.push_back("--own=" + f.string());  // the shim, Blender's files
    if (limits.sandbox == ProgramLimits::Sandbox::None) argv.erase(argv.begin() + 2);  // no walk of the whole disk
    ConfinedProgram prog(argv, work.path, limits);
    EXPECT_EQ(prog.wait(ConfinedProgram::Clock::now() + std::chrono::seconds(60)), ConfinedProgram::End::Exited);
    return slurp((work.path / "answer.json").string());
  };
  ColmapParams colmap;
  CyclesParams cycles;
  const std::string blender = find_program("blender").empty() ? "/usr/bin/blender" : find_program("blender");
  for (const ProgramLimits& limits : {colmap_program_limits(colmap), cycles_program_limits(cycles, blender)}) {
    EXPECT_NE(hunt(limits).find("\"found: none\""), std::string::npos) << hunt(limits);
    ProgramLimits open = limits;
    open.sandbox = ProgramLimits::Sandbox::None;
    EXPECT_NE(hunt(open).find(planted.string()), std::string::npos);
  }
  fs::remove_all(planted);
}

// Issue 39, item 4: exit 3 never comes from input. Every subcommand meets a corpus of
// hostile inputs (special files, text that is not UTF-8, an alias bomb, duplicate keys,
// numbers past their ranges, clouds with trailing data or coordinates no float holds)
// and answers 0, 1 (a gate's verdict) or 2 (a clear error) within 30 s.
TEST(Cli, EverySubcommandAnswersHostileInputWithExitTwoNotACrashOrHang) {
  namespace fs = std::filesystem;
  const fs::path dir = scratch("hostile"), out = dir / "out";
  fs::create_directories(dir / "folder.yaml");
  const auto put = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return (dir / name).string();
  };
  std::vector<std::string> yaml, json, cloud;
  for (const char* ext : {"yaml", "json", "ply"}) {
    const fs::path fifo = dir / (std::string("fifo.") + ext), zero = dir / (std::string("zero.") + ext);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", zero);
    auto& list = ext == std::string("yaml") ? yaml : ext == std::string("json") ? json : cloud;
    list.insert(list.end(), {fifo.string(), zero.string(), put(std::string("empty.") + ext, "")});
  }
  yaml.push_back((dir / "folder.yaml").string());
  const std::string body = "seed: 5\nbunches:\n  - preset: table-red\nestimators:\n  - type: convex_hull\n";
  yaml.push_back(put("latin1.yaml", "# caf\xE9\n" + body));
  yaml.push_back(put("utf16.yaml", std::string("\xFF\xFE", 2) + std::string("s\0e\0", 4)));
  std::string bomb = "l0: &l0 [x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 10; ++i) {
    bomb += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [";
    for (int k = 0; k < 9; ++k) bomb += (k ? ", *l" : "*l") + std::to_string(i - 1);
    bomb += "]\n";
  }
  yaml.push_back(put("bomb.yaml", bomb + body));
  yaml.push_back(put("nul.yaml", "name: \"a\\0b\"\n" + body));
  std::string many = "seed: 5\nbunches:\n  - preset: table-red\nestimators:\n";
  for (int i = 0; i < 300; ++i) many += "  - {type: convex_hull, name: e" + std::to_string(i) + "}\n";
  yaml.push_back(put("many.yaml", many));
  const std::string baseline = slurp(GRAPEBENCH_SOURCE_DIR "/results/baseline/default.json");
  std::string huge = baseline, twice = baseline;
  huge.replace(huge.find("\"rmse_rel\": 0.05"), 16, "\"rmse_rel\": 1e308");
  twice.replace(twice.find("\"scene\""), 7, "\"scene\": \"x\", \"scene\"");
  json.insert(json.end(), {put("latin1.json", "{\"scene\": \"caf\xE9\"}"), put("huge.json", huge),
                           put("twice.json", twice), put("deep.json", std::string(100000, '[')),
                           put("notime.json", "{\"benchmarks\": [{\"name\": \"a\", \"real_time\": 5}]}")});
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                          "end_header\n0 0 0\n0.1 0 0\n0 0.1 0\n";
  cloud.insert(cloud.end(), {put("huge.ply", ply + "1e39 0 0.1\n"), put("far.ply", ply + "1e308 0 0.1\n"),
                             put("trailing.ply", ply + "0 0 0.1\n0.1 0.1 0.1\n"),
                             put("latin1.ply", ply + "0 0 0.1 caf\xE9\n")});
  const std::string good_bench = GRAPEBENCH_SOURCE_DIR "/tests/fuzz/corpus/bench_json/bench.json",
                    good_base = GRAPEBENCH_SOURCE_DIR "/results/baseline/default.json",
                    gate = GRAPEBENCH_SOURCE_DIR "/results/baseline/speed_gate.json",
                    coco = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/coco_tiny.json";
  // Each file through one subcommand of its reader (`run`: the scene reader `synth`,
  // `scan` and `merge` share; `check`: the JSON reader of every JSON input), and
  // every subcommand and input position meets the special files and the alias bomb
  // (a process start is 0.4 s, most of it the dynamic loader: the matrix is kept small).
  std::vector<std::string> commands;
  for (const auto& f : yaml) commands.push_back("run " + f + " --out " + out.string() + " -q");
  for (const auto& f : json) commands.push_back("check " + f + " --baseline " + good_base);
  for (const auto& f : cloud) commands.push_back("estimate " + f + " -e convex_hull");
  for (const std::string& f : {yaml[0], yaml[1], (dir / "bomb.yaml").string()})
    for (const std::string& c : {"synth " + f + " --out " + out.string(), "scan " + f + " --out " + out.string(),
                                 "dataset " + f + " --out " + (dir / "dataset").string(),
                                 "merge " + f + " --from " + out.string() + " --out " + (dir / "merged").string()})
      commands.push_back(c);
  for (const std::string& f : {json[0], json[1]})
    for (const std::string& c : {"check " + good_base + " --baseline " + f, "compare-bench " + f + " " + good_bench,
                                 "compare-bench " + good_bench + " " + f, "speed-gate " + f + " " + good_bench,
                                 "speed-gate " + gate + " " + f, "coco-eval " + f + " " + coco,
                                 "coco-eval " + coco + " " + f})
      commands.push_back(c);
  for (const std::string& f : {json[2], (dir / "twice.json").string(), (dir / "latin1.json").string(),
                               (dir / "notime.json").string()})
    commands.push_back("compare-bench " + good_bench + " " + f);
  std::vector<CommandResult> results(commands.size());
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < commands.size();) results[i] = run_cli(commands[i], 30);
  };
  std::thread a(worker), b(worker);
  a.join();
  b.join();
  for (std::size_t i = 0; i < commands.size(); ++i) {
    const int st = results[i].status;
    EXPECT_TRUE(st == 0 || st == 1 || st == 2) << commands[i] << " -> exit " << st << "\n" << results[i].out;
    if (st == 2) {
      EXPECT_NE(results[i].out.find(dir.string()), std::string::npos) << commands[i] << "\n" << results[i].out;
    }
  }
  fs::remove_all(dir);
}

// Issue 39's reproducer: two scene files with the same `name` on one --out both exited
// 0, the second's results replacing the first's. The second is refused while the
// first's run is there; the first (edited, even) runs on; another `name` is fine.
TEST(Cli, ASecondSceneOfTheSameNameIsRefusedOnOneOut) {
  namespace fs = std::filesystem;
  const fs::path dir = scratch("cli_twins"), out = dir / "out";
  fs::create_directories(dir / "a");
  fs::create_directories(dir / "b");
  const std::string scene = "name: twin\nseed: 3\nbunches:\n  - preset: table-red\n    count: 1\n"
                            "sensor:\n  type: ideal\n  width: 80\n  height: 60\n"
                            "rig:\n  type: turntable\n  views: 2\n  step_deg: 180\n  distance: 0.6\n"
                            "pipeline:\n  registration: true_poses\nestimators:\n  - type: convex_hull\n";
  std::ofstream(dir / "a" / "twin.yaml") << scene;
  std::ofstream(dir / "b" / "twin.yaml") << scene << "  - type: pca_box\n";
  ASSERT_EQ(run_cli("run " + (dir / "a" / "twin.yaml").string() + " --out " + out.string() + " -q").status, 0);
  const CommandResult second = run_cli("run " + (dir / "b" / "twin.yaml").string() + " --out " + out.string() + " -q");
  EXPECT_EQ(second.status, 2) << second.out;
  EXPECT_NE(second.out.find("holds the run of " + (dir / "a" / "twin.yaml").string()), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("another `name`, or another --out"), std::string::npos) << second.out;
  std::ofstream(dir / "a" / "twin.yaml", std::ios::app) << "  - type: pca_box\n";  // the same file, edited
  EXPECT_EQ(run_cli("run " + (dir / "a" / "twin.yaml").string() + " --out " + out.string() + " -q").status, 0);
  EXPECT_EQ(run_cli("run " + (dir / "b" / "twin.yaml").string() + " --out " + (dir / "other").string() + " -q").status, 0);
  fs::remove_all(dir);
}

// Issue 23's reproducer: resume checked only a case file's key, so edited estimates,
// truths, `ok` flags or rows were reused silently. Each edit now fails the digest:
// the case is recomputed and the run says so.
TEST(Cli, AnEditedCaseFileIsRecomputedAndTheRunSaysSo) {
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml";
  const std::string out = scratch("cli_tampered").string(), file = out + "/two_bunches_hull/cases/c0000_b0001.json";
  ASSERT_EQ(run_cli("run " + scene + " --out " + out + " -q").status, 0);
  const std::string results = slurp(out + "/two_bunches_hull/results.csv"), original = slurp(file);
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"\"ok\": true", "\"ok\": false"}, {"\"estimate\": ", "\"estimate\": 1"}, {"\"truth\": ", "\"truth\": 2"},
      {"\"points\": ", "\"points\": 9"}, {"\"digest\": \"", "\"digest\": \"0"}};
  for (const auto& [from, to] : edits) {
    std::string json = original;
    const auto at = json.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    json.replace(at, from.size(), to);
    std::ofstream(file, std::ios::binary) << json;
    const CommandResult again = run_cli("run " + scene + " --out " + out + " -q");
    EXPECT_EQ(again.status, 0) << again.out;
    EXPECT_NE(again.out.find("2 cases: 1 computed, 1 reused"), std::string::npos) << from << "\n" << again.out;
    EXPECT_NE(again.out.find("1 case file(s) did not match their digest"), std::string::npos) << from << "\n" << again.out;
    EXPECT_TRUE(slurp(out + "/two_bunches_hull/results.csv") == results) << from;
  }
}

// Two runs on one --out at the same time: each case is computed once (a claim per
// case), and the files are those of one run.
TEST(Cli, TwoConcurrentRunsOnOneOutComputeEachCaseOnce) {
  namespace fs = std::filesystem;
  const fs::path dir = scratch("cli_concurrent");
  fs::create_directories(dir);
  std::ofstream(dir / "six.yaml") << "name: six\nseed: 5\nbunches:\n  - preset: table-red\n    count: 6\n"
                                     "sensor:\n  type: ideal\n  width: 160\n  height: 120\n"
                                     "rig:\n  type: turntable\n  views: 4\n  step_deg: 90\n  distance: 0.6\n"
                                     "pipeline:\n  registration: true_poses\nestimators:\n  - type: convex_hull\n"
                                     "    name: CH\n  - type: alpha_shape\n    name: AS\n";
  const std::string scene = (dir / "six.yaml").string();
  ASSERT_EQ(run_cli("run " + scene + " --out " + (dir / "alone").string() + " -q").status, 0);
  const std::string cmd = std::string(GRAPEBENCH_EXE) + " run " + scene + " --out " + (dir / "shared").string() +
                          " -q --threads 1 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> a(popen(cmd.c_str(), "r"), pclose), b(popen(cmd.c_str(), "r"), pclose);
  const auto read_all = [](FILE* f) {
    std::string text;
    std::array<char, 4096> buf;
    while (std::fgets(buf.data(), buf.size(), f)) text += buf.data();
    return text;
  };
  const std::string out_a = read_all(a.get()), out_b = read_all(b.get());
  EXPECT_EQ(WEXITSTATUS(pclose(a.release())), 0) << out_a;
  EXPECT_EQ(WEXITSTATUS(pclose(b.release())), 0) << out_b;
  const auto computed = [](const std::string& text) {
    const auto at = text.find("6 cases: ");
    return at == std::string::npos ? -1 : std::stoi(text.substr(at + 9));
  };
  ASSERT_GE(computed(out_a), 0) << out_a;
  ASSERT_GE(computed(out_b), 0) << out_b;
  EXPECT_EQ(computed(out_a) + computed(out_b), 6) << out_a << "\n" << out_b;
  const auto slurp = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  for (const char* f : {"results.csv", "summary.json"})
    EXPECT_TRUE(slurp(dir / "shared" / "six" / f) == slurp(dir / "alone" / "six" / f)) << f;
  for (int k = 0; k < 6; ++k) {
    const std::string name = "cases/c0000_b000" + std::to_string(k) + ".json";
    const auto shared = nlohmann::json::parse(slurp(dir / "shared" / "six" / name));
    auto alone = nlohmann::json::parse(slurp(dir / "alone" / "six" / name));
    EXPECT_EQ(shared["rows"].size(), alone["rows"].size()) << name;
    for (std::size_t r = 0; r < alone["rows"].size(); ++r)
      EXPECT_EQ(shared["rows"][r]["estimate"], alone["rows"][r]["estimate"]) << name;
  }
}

// Issue 23's reproducers: a baseline nested a million deep overflowed the stack; one
// of `{"scores": []}` passed; structurally wrong ones were internal errors (exit 3);
// the scene name was never compared. A case file nested as deep is recomputed.
TEST(Cli, MalformedBaselinesAndCaseFilesAreErrorsNotCrashes) {
  namespace fs = std::filesystem;
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml";
  const fs::path dir = scratch("cli_baselines");
  ASSERT_EQ(run_cli("run " + scene + " --out " + (dir / "out").string() + " -q").status, 0);
  const std::string run = (dir / "out" / "two_bunches_hull").string();
  const std::string deep = "{\"scores\": " + std::string(1000000, '[') + std::string(1000000, ']') + "}";
  const std::vector<std::pair<std::string, std::string>> baselines = {
      {deep, "nested deeper than 64 levels"},
      {"{\"scene\": \"two_bunches_hull\", \"scores\": []}", "'scores' is empty"},
      {"{\"scene\": \"two_bunches_hull\", \"scores\": 5}", "'scores' must be a list"},
      {"[1, 2]", "not a summary"},
      {"{\"scene\": \"two_bunches_hull\", \"scores\": [{\"estimator\": 5}]}", "'scores[0].condition' must be a string"},
      {"{\"scene\": \"other\", \"scores\": [{\"condition\": \"\", \"estimator\": \"CH\", \"quantity\": \"volume\"}]}",
       "a baseline of 'other'"},
      {"{\"scene\": \"two_bunches_hull\", \"tolerances\": {\"rmse_rel\": -1}, \"scores\": [{\"condition\": \"\", "
       "\"estimator\": \"CH\", \"quantity\": \"volume\"}]}",
       "'tolerances.rmse_rel' must be a number in [0, 10]"}};
  for (const auto& [text, message] : baselines) {
    std::ofstream(dir / "baseline.json") << text;
    const CommandResult r = run_cli("check " + run + " --baseline " + (dir / "baseline.json").string());
    EXPECT_EQ(r.status, 2) << message << "\n" << r.out.substr(0, 300);
    EXPECT_NE(r.out.find(message), std::string::npos) << r.out.substr(0, 300);
  }
  std::ofstream(dir / "bench.json") << "{\"benchmarks\": [{\"name\": 5}]}";
  const CommandResult bench = run_cli("compare-bench " + (dir / "bench.json").string() + " " + (dir / "bench.json").string());
  EXPECT_EQ(bench.status, 2) << bench.out;
  EXPECT_NE(bench.out.find("a benchmark entry is malformed"), std::string::npos) << bench.out;
  // A deep case file: recomputed, not a crash.
  std::ofstream(run + "/cases/c0000_b0000.json") << deep;
  const CommandResult again = run_cli("run " + scene + " --out " + (dir / "out").string() + " -q");
  EXPECT_EQ(again.status, 0) << again.out.substr(0, 300);
  EXPECT_NE(again.out.find("2 cases: 1 computed, 1 reused"), std::string::npos) << again.out.substr(0, 300);
  // An --out that cannot be a folder: a clear error, exit 2 (was an internal error, 3).
  std::ofstream(dir / "a_file") << "x";
  for (const char* sub : {"run", "scan"}) {
    const CommandResult out = run_cli(std::string(sub) + " " + scene + " --out " + (dir / "a_file").string() + " -q");
    EXPECT_EQ(out.status, 2) << sub << ": " << out.out;
    EXPECT_NE(out.out.find("a_file"), std::string::npos) << out.out;
  }
}

// The peak resident memory (KB) of `grapebench <args>` (getrusage of the child).
long max_rss_kb(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {GRAPEBENCH_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c;
  for (auto& a : argv) c.push_back(a.data());
  c.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execv(c[0], c.data());
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? usage.ru_maxrss : -1;
}

// Issue 23's reproducer: a D435 pass of 1,000 frames kept every frame in memory
// (bad_alloc). Frames now go to their consumer (the single-frame protocol, the scan
// files) as they are captured: ten times the frames, the same peak memory (before:
// +430 MB from 20 to 200 frames in `run`).
TEST(Cli, LongPassesStreamTheirFramesInsteadOfHoldingThem) {
  // AddressSanitizer's quarantine keeps freed frames resident: no figure to compare.
  if (!heap_meter_available()) GTEST_SKIP() << "sanitizer build";
  namespace fs = std::filesystem;
  const fs::path dir = scratch("cli_stream");
  fs::create_directories(dir);
  const auto scene = [&](int frames) {
    const fs::path f = dir / ("pass" + std::to_string(frames) + ".yaml");
    std::ofstream(f) << "name: pass\nseed: 3\nbunches:\n  - preset: table-red\nsensor:\n  type: d435\n"
                        "rig:\n  type: robot_pass\n  frames: "
                     << frames << "\n  spacing: 0.001\nprotocol: single_frame\npipeline:\n  rois: [manual_r]\n"
                     << "estimators:\n  - type: pca_box\n";
    return f.string();
  };
  const long run_few = max_rss_kb({"run", scene(20), "--out", (dir / "a").string(), "-q", "--threads", "1"});
  const long run_many = max_rss_kb({"run", scene(200), "--out", (dir / "b").string(), "-q", "--threads", "1"});
  ASSERT_GT(run_few, 0);
  ASSERT_GT(run_many, 0);
  EXPECT_LT(run_many, run_few + 40'000) << "run: " << run_few << " KB at 20 frames, " << run_many << " KB at 200";
  const long scan_few = max_rss_kb({"scan", scene(4), "--out", (dir / "c").string(), "-q", "--threads", "1", "--merged"});
  const long scan_many = max_rss_kb({"scan", scene(40), "--out", (dir / "d").string(), "-q", "--threads", "1", "--merged"});
  ASSERT_GT(scan_few, 0);
  ASSERT_GT(scan_many, 0);
  EXPECT_LT(scan_many, scan_few + 40'000) << "scan: " << scan_few << " KB at 4 frames, " << scan_many << " KB at 40";
  EXPECT_TRUE(fs::exists(dir / "d" / "pass" / "bunch_0000" / "bunch_0000_merged.ply"));
  EXPECT_TRUE(fs::exists(dir / "d" / "pass" / "bunch_0000" / "bunch_0000_frame_39.pcd"));
}

// Issue 23's reproducers: `--threshold nan` turned the gate off and negative times
// were compared.
TEST(Cli, CompareBenchRejectsNanThresholdsAndNonPositiveTimes) {
  const std::string good = scratch("cli_bench_good.json").string(), bad = scratch("cli_bench_bad.json").string();
  const auto write = [](const std::string& path, const char* time) {
    std::ofstream(path) << "{\"context\":{},\"benchmarks\":[{\"name\":\"a\",\"run_type\":\"iteration\",\"real_time\":"
                        << time << ",\"cpu_time\":1.0,\"time_unit\":\"ns\",\"iterations\":1}]}";
  };
  write(good, "1.0");
  EXPECT_EQ(run_cli("compare-bench " + good + " " + good).status, 0);
  const CommandResult nan = run_cli("compare-bench " + good + " " + good + " --threshold nan");
  EXPECT_EQ(nan.status, 2) << nan.out;
  for (const char* time : {"-1.0", "0", "1e400"}) {
    write(bad, time);
    const CommandResult r = run_cli("compare-bench " + good + " " + bad);
    EXPECT_EQ(r.status, 2) << time << "\n" << r.out;
    // 1e400 fails in the JSON parser (overflow); the others name the field.
    EXPECT_NE(r.out.find(std::string(time) == "1e400" ? "overflow" : "real_time"), std::string::npos) << r.out;
  }
}

TEST(Cli, VersionQuietAndVerboseWorkEverywhere) {
  const CommandResult v = run_cli("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_NE(v.out.find("grapebench 0."), std::string::npos) << v.out;
  EXPECT_NE(v.out.find("build "), std::string::npos) << v.out;
  const std::string scene = GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml";
  const std::string out = " --out " + scratch("cli_quiet").string();
  // -q before or after the subcommand: no progress lines.
  for (const std::string& args : {"-q scan " + scene, "scan " + scene + " -q"}) {
    const CommandResult r = run_cli(args + out);
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(r.out.find("ETA"), std::string::npos) << r.out;
  }
  const CommandResult verbose = run_cli("scan " + scene + " -v" + out);
  EXPECT_NE(verbose.out.find("bunch 2/2"), std::string::npos) << verbose.out;
  const CommandResult synth = run_cli("synth --count 2 --no-mesh -v" + out);
  EXPECT_NE(synth.out.find("ETA"), std::string::npos) << synth.out;
  // A bunch the scene does not have is an input error, not an empty success.
  const CommandResult missing = run_cli("scan " + scene + " --bunch 5" + out);
  EXPECT_EQ(missing.status, 2) << missing.out;
  EXPECT_NE(missing.out.find("--bunch 5"), std::string::npos) << missing.out;
}

// Issue 38, item 9: Blender missing is the run's bad input, exit 2 naming the package
// (it was a failed case each, the run exiting 0).
TEST(Cli, ARunOnCyclesWithoutBlenderExitsTwoNamingThePackage) {
  const CommandResult r = run_cli("run " GRAPEBENCH_SOURCE_DIR "/tests/bench/data/cycles_pair_tiny.yaml -q --out " +
                                  scratch("cli_no_blender").string(), 0, "GRAPEBENCH_BLENDER=/nonexistent/blender ");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("needs Blender (Debian package `blender`"), std::string::npos) << r.out;
}

TEST(Cli, EstimateRejectsWhatItCannotReadWithExitTwo) {
  const std::string ply = scratch("cli_estimate.ply").string(), json = scratch("cli_estimate.json").string();
  std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                        "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const CommandResult ok = run_cli("estimate " + ply + " -e convex_hull --json " + json);
  EXPECT_EQ(ok.status, 0) << ok.out;
  EXPECT_NE(ok.out.find("166666.667 cm3"), std::string::npos) << ok.out;  // the unit tetrahedron: 1/6 m3
  const struct {
    std::string args, message;
  } bad[] = {{"estimate /tmp/grapebench_no_such.ply -e convex_hull", "no such file"},
             {"estimate " + ply + " -e nonsense", "unknown value 'nonsense'"},
             {"estimate " + ply + " -e luo2016_stereo", "not a point cloud"},
             {"estimate " + ply + " -e '{type: alpha_shape, alpha: -1}'", "alpha"},
             {"estimate " GRAPEBENCH_SOURCE_DIR "/CMakeLists.txt -e convex_hull", "not a .ply or .pcd"}};
  for (const auto& b : bad) {
    const CommandResult r = run_cli(b.args);
    EXPECT_EQ(r.status, 2) << b.args << "\n" << r.out;
    EXPECT_NE(r.out.find(b.message), std::string::npos) << b.args << "\n" << r.out;
  }
}

// On two_bunches_hull (2 cases, under a second) rather than the default suite, which
// took 261 s of the sanitizer stage for the same property: check's exit codes on a
// whole run's folder. The default suite's own gate is scripts/regression_gate.sh.
TEST(Cli, CheckExitsOneOnARegressionAndZeroOtherwise) {
  const std::string out = scratch("cli_check").string();
  const CommandResult run =
      run_cli("run " GRAPEBENCH_SOURCE_DIR "/tests/bench/data/two_bunches_hull.yaml --out " + out + " --quiet");
  ASSERT_EQ(run.status, 0) << run.out;
  const std::string summary = out + "/two_bunches_hull/summary.json";
  EXPECT_EQ(run_cli("check " + summary + " --baseline " + summary).status, 0);
  // A baseline whose CH was 20 % closer to the truth: this run regressed.
  auto better = nlohmann::json::parse(slurp(summary));
  for (auto& row : better["scores"]) row["rmse"] = row["rmse"].get<double>() * 0.8;
  std::ofstream(out + "/better.json") << better.dump();
  const CommandResult worse = run_cli("check " + out + "/two_bunches_hull --baseline " + out + "/better.json");
  EXPECT_EQ(worse.status, 1) << worse.out;
  EXPECT_NE(worse.out.find("WORSE    CH volume: RMSE"), std::string::npos) << worse.out;
}

}  // namespace
}  // namespace grapebench
