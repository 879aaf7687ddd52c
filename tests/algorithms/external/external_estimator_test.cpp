// The external estimator's own checks: answers outside the protocol or out of range,
// programs that hang, die or answer garbage, per request and persistent.
#include "algorithms/external/external_estimator.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>

namespace grapebench {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

ExternalParams shell(const std::string& script, bool persistent = false) {
  ExternalParams p;
  p.command = {"/bin/sh", "-c", script, "sh"};
  p.version = 2;
  p.persistent = persistent;
  p.timeout = 2;
  if (persistent) p.programs = start_persistent_programs(p);
  return p;
}

EstimatorInput cube() {
  EstimatorInput in;
  in.points.resize(8, 3);
  for (int i = 0; i < 8; ++i) in.points.row(i) << (i & 1), (i >> 1 & 1), (i >> 2 & 1);
  return in;
}

TEST(ExternalAnswer, QuantitiesMustBeFiniteAndInRangeAndOutputKindsWellFormed) {
  ExternalParams p;
  p.command = {"x"};
  p.version = 2;
  p.quantities = {Quantity::Volume};
  const auto parse = [&](const char* json) { return parse_external_answer(nlohmann::json::parse(json), p, 2); };
  EXPECT_DOUBLE_EQ(parse(R"({"volume": 0.001})").values[0].second, 0.001);
  for (const char* bad : {R"({"volume": -0.5})", R"({"volume": 0})", R"({"volume": 1e300})", R"({"volume": "1"})",
                          R"({"height": 1})", R"([1])"}) {
    EXPECT_NE(error_of([&] { parse(bad); }), "") << bad;
  }
  EXPECT_NE(error_of([&] { parse(R"({"volume": -0.5})"); }).find("outside (0, 1000]"), std::string::npos);
  EXPECT_NE(error_of([&] { parse(R"({"error": "no bunch here"})"); }).find("answered an error: no bunch here"),
            std::string::npos);
  const Estimate e = parse(R"({"volume": 1e-3, "points": {"cutting_point": [0.1, 0.2, 0.3]},
      "detections": [{"x": 10, "y": 20, "r": 5, "score": 0.9}], "class_scores": [[0.1, 0.9], [0.8, 0.2]],
      "watertight": true, "notes": "ok"})");
  ASSERT_EQ(e.points.size(), 1u);
  EXPECT_EQ(e.points[0].first, "cutting_point");
  EXPECT_DOUBLE_EQ(e.points[0].second.z(), 0.3);
  ASSERT_EQ(e.detections.size(), 1u);
  EXPECT_DOUBLE_EQ(e.detections[0].circle.r, 5);
  EXPECT_EQ(e.class_scores.rows(), 2);
  EXPECT_DOUBLE_EQ(e.class_scores(1, 0), 0.8);
  EXPECT_TRUE(e.watertight);
  for (const char* bad : {R"({"volume": 1e-3, "points": {"p": [1, 2]}})", R"({"volume": 1e-3, "detections": [{"x": 1}]})",
                          R"({"volume": 1e-3, "class_scores": [[1, 2]]})",
                          R"({"volume": 1e-3, "class_scores": [[1, 2], [3]]})"}) {
    EXPECT_NE(error_of([&] { parse(bad); }), "") << bad;
  }
}

// Reproducer: a scene folder whose path holds "{scene_dir}" made the substitution
// loop forever (each replacement brought the placeholder back).
TEST(ExternalCommand, SceneDirPlaceholderInTheFolderNameIsReplacedOnce) {
  std::vector<std::string> cmd = {"python3", "{scene_dir}/a.py", "--x={scene_dir}{scene_dir}"};
  substitute_scene_dir(cmd, "/data/{scene_dir}");
  EXPECT_EQ(cmd[1], "/data/{scene_dir}/a.py");
  EXPECT_EQ(cmd[2], "--x=/data/{scene_dir}/data/{scene_dir}");
  std::vector<std::string> here = {"{scene_dir}/b.py"};
  substitute_scene_dir(here, "");
  EXPECT_EQ(here[0], "./b.py");
}

TEST(ExternalProgram, PerRequestTimeoutAndFailureAreErrorsWithTheReason) {
  ExternalParams slow = shell("sleep 30");
  slow.timeout = 0.3;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_NE(error_of([&] { external_estimate(cube(), slow); }).find("killed after the timeout"), std::string::npos);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5);
  EXPECT_NE(error_of([&] { external_estimate(cube(), shell("echo broken >&2; exit 4")); }).find("exit status 4): broken"),
            std::string::npos);
}

// Issue 23's reproducer: a FIFO left at the answer path blocked the harness.
TEST(ExternalProgram, AFifoOrLinkAtTheAnswerPathIsAnErrorNotAHang) {
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_NE(error_of([&] { external_estimate(cube(), shell("mkfifo \"$(dirname \"$1\")/answer.json\"")); })
                .find("answer.json is not a regular file"),
            std::string::npos);
  EXPECT_NE(error_of([&] { external_estimate(cube(), shell("ln -s /dev/zero \"$(dirname \"$1\")/answer.json\"")); })
                .find("answer.json cannot be opened"),
            std::string::npos);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5);
}

TEST(ExternalProgram, PersistentProgramsAnswerLinesAndFailCleanly) {
  // A program that answers each request line with a fixed volume.
  ExternalParams good = shell("while read line; do echo '{\"volume\": 0.002}'; done", true);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(external_estimate(cube(), good).values[0].second, 0.002);
  ExternalParams mute = shell("read line; sleep 30", true);
  mute.timeout = 0.3;
  mute.programs = start_persistent_programs(mute);
  EXPECT_NE(error_of([&] { external_estimate(cube(), mute); }).find("timeout"), std::string::npos);
  EXPECT_NE(error_of([&] { external_estimate(cube(), shell("read line; echo gone >&2", true)); })
                .find("exited before answering: gone"),
            std::string::npos);
  EXPECT_NE(error_of([&] { external_estimate(cube(), shell("read line; echo not json", true)); }).find("not JSON"),
            std::string::npos);
}

// Issue 39's reproducer: a program's bytes that are not UTF-8 (on stderr, in a key or
// a string of its answer, per request and persistent) ended the whole run with exit 3
// when the case file was written. Each is now a failed request whose message is
// UTF-8 (the bytes written \xNN); wrong types in an answer are refused too.
TEST(ExternalProgram, BytesThatAreNotUtf8AreAFailedRequestWithAUtf8Message) {
  const EstimatorInput in = cube();
  const auto check = [&](const ExternalParams& p, const std::string& expected) {
    const std::string e = error_of([&] { external_estimate(in, p); });
    EXPECT_NE(e.find(expected), std::string::npos) << e;
    EXPECT_NO_THROW((void)nlohmann::json(e).dump()) << e;
  };
  check(shell(R"(printf 'bad \377 bytes\n' >&2; exit 1)"), "bad \\xFF bytes");
  check(shell(R"(printf '{"vol\377": 1}' > answer.json)"), "not UTF-8 at byte 5");
  check(shell(R"(printf '{"volume": 0.001, "notes": "caf\351"}' > answer.json)"), "not UTF-8 at byte 31");
  check(shell(R"(while read -r l; do printf '{"volume\377": 1}\n'; done)", true), "not UTF-8 at byte 8");
  check(shell(R"(printf '{"volume": 0.001, "watertight": "yes"}' > answer.json)"), "'watertight' must be true or false");
  check(shell(R"(printf '{"volume": 0.001, "notes": 7}' > answer.json)"), "'notes' must be a string");
}

}  // namespace
}  // namespace grapebench
