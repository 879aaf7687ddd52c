#include "synth/config.h"

#include <gtest/gtest.h>

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

TEST(Config, RangeErrorNamesFileLineKeyAndRange) {
  const auto n = ConfigNode::load_string("a: 1\nb: 7.5\n", "s.yaml");
  const auto msg = error_of([&] { n.get_real("b", 0, 0, 5); });
  EXPECT_NE(msg.find("s.yaml:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'b'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("[0, 5]"), std::string::npos) << msg;
}

TEST(Config, TypeErrorsAndUnknownKeys) {
  const auto n = ConfigNode::load_string("x: hello\ny: 1\nextra: 2\n", "t.yaml");
  EXPECT_NE(error_of([&] { n.get_real("x", 0, 0, 1); }).find("expected a number"), std::string::npos);
  n.get_int("y", 0, 0, 3);
  const auto msg = error_of([&] { n.report_unused(); });
  EXPECT_NE(msg.find("t.yaml:3: unknown key 'extra'"), std::string::npos) << msg;
}

TEST(Config, NestedUnknownKeyAndSyntaxError) {
  const auto n = ConfigNode::load_string("list:\n  - a: 1\n    typo: 2\n", "u.yaml");
  for (const auto& c : n.children("list")) c.get_int("a", 0, 0, 5);
  const auto msg = error_of([&] { n.report_unused(); });
  EXPECT_NE(msg.find("u.yaml:3: unknown key 'list[0].typo'"), std::string::npos) << msg;
  const auto syntax = error_of([] { ConfigNode::load_string("a: [1, 2\n", "v.yaml"); });
  EXPECT_NE(syntax.find("v.yaml:"), std::string::npos) << syntax;
  EXPECT_NE(syntax.find("YAML syntax error"), std::string::npos) << syntax;
}

TEST(Config, NonFiniteAndListErrors) {
  const auto n = ConfigNode::load_string("a: .nan\nc: [1, 2]\n", "w.yaml");
  EXPECT_FALSE(error_of([&] { n.get_real("a", 0, -1, 1); }).empty());
  EXPECT_NE(error_of([&] { n.get_real_list("c", 3, 0, 1); }).find("list of 3"), std::string::npos);
}

}  // namespace
}  // namespace grapebench
