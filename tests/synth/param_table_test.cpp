// The key table: reading, range errors with file:line, conditional keys, required
// keys, cross-field rules, the JSON echo reading back, and help rows.
#include "synth/param_table.h"
#include "synth/registry.h"

#include <gtest/gtest.h>

namespace grapebench {
namespace {

enum class Mode { Fast, Exact };
struct Inner {
  double x = 1;
};
struct Params {
  double radius = 0.01;
  int count = 3;
  bool on = true;
  Mode mode = Mode::Fast;
  Rgb colour{0.1f, 0.2f, 0.3f};
  Vec3 corner{1, 2, 3};
  std::vector<double> distances{0.5, 1};
  std::vector<Mode> modes{Mode::Fast};
  Inner inner;
  struct {
    double y = 4;
  } nested;
  double exact_only = 0.5;
  std::vector<std::string> command;
};

const ParamTable<Inner> kInner = ParamTable<Inner>().real("x", "m", &Inner::x, 0, 10, "inner x");

ParamTable<Params> table() {
  using P = Params;
  return ParamTable<P>()
      .real("radius", "m", &P::radius, 1e-4, 0.5, "a radius")
      .integer("count", "count", &P::count, 1, 10, "a count")
      .boolean("on", &P::on, "a switch")
      .choice("mode", &P::mode, {{"fast", Mode::Fast}, {"exact", Mode::Exact}}, "a mode")
      .rgb("colour", &P::colour, "a colour")
      .vec3("corner", "m", &P::corner, -5, 5, "a corner")
      .reals("distances", "m", &P::distances, 1, 4, 0.2, 5, "stations")
      .choice_list("modes", &P::modes, {{"fast", Mode::Fast}, {"exact", Mode::Exact}}, 1, "modes")
      .section("inner", &P::inner, kInner, "a section")
      .real("y", "m", [](auto& p) -> auto& { return p.nested.y; }, 0, 10, "a nested field")
      .real("exact_only", "-", &P::exact_only, 0, 1, "read only in exact mode")
      .when("mode: exact", [](const P& p) { return p.mode == Mode::Exact; })
      .validate([](const P& p, const ConfigNode& n) {
        if (p.count > 5 && p.radius > 0.1) n.fail("count", "more than 5 only below 0.1 m radius");
      });
}

std::string error_of(const std::string& yaml) {
  try {
    Params p;
    const ConfigNode n = ConfigNode::load_string(yaml, "t.yaml");
    table().read(n, p);
    n.report_unused();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamTable, ReadsEveryKindAndKeepsDefaultsOfAbsentKeys) {
  Params p;
  const ConfigNode n = ConfigNode::load_string(
      "radius: 0.02\ncount: 4\non: false\nmode: exact\ncolour: [1, 0, 0.5]\ncorner: [0, -1, 2]\n"
      "distances: [0.3]\nmodes: [exact, fast]\ninner: {x: 7}\ny: 9\nexact_only: 0.25\n",
      "t.yaml");
  table().read(n, p);
  n.report_unused();
  EXPECT_EQ(p.radius, 0.02);
  EXPECT_EQ(p.count, 4);
  EXPECT_FALSE(p.on);
  EXPECT_EQ(p.mode, Mode::Exact);
  EXPECT_EQ(p.colour.b, 0.5f);
  EXPECT_EQ(p.corner, Vec3(0, -1, 2));
  EXPECT_EQ(p.distances, std::vector<double>{0.3});
  EXPECT_EQ(p.modes, (std::vector<Mode>{Mode::Exact, Mode::Fast}));
  EXPECT_EQ(p.inner.x, 7);
  EXPECT_EQ(p.nested.y, 9);
  EXPECT_EQ(p.exact_only, 0.25);
  Params d;
  table().read(ConfigNode::load_string("count: 2\n", "t.yaml"), d);
  EXPECT_EQ(d.radius, 0.01);
  EXPECT_EQ(d.count, 2);
}

TEST(ParamTable, ErrorsNameFileLineKeyAndAllowedRange) {
  EXPECT_NE(error_of("on: true\nradius: 2\n").find("t.yaml:2: 'radius': value 2 is outside the allowed range [0.0001, 0.5]"),
            std::string::npos)
      << error_of("on: true\nradius: 2\n");
  EXPECT_NE(error_of("mode: slow\n").find("t.yaml:1: 'mode': unknown value 'slow'; allowed: fast, exact"),
            std::string::npos);
  EXPECT_NE(error_of("modes: [fast, fast]\n").find("'fast' is listed twice"), std::string::npos);
  EXPECT_NE(error_of("inner:\n  x: 11\n").find("t.yaml:2: 'inner.x'"), std::string::npos) << error_of("inner:\n  x: 11\n");
  EXPECT_NE(error_of("corner: [0, 0]\n").find("expected a list of 3 numbers"), std::string::npos);
  EXPECT_NE(error_of("radius: 0.2\ncount: 6\n").find("t.yaml:2: 'count': more than 5 only below 0.1 m radius"),
            std::string::npos);
  // A key the table does not know is left for report_unused, which names it.
  EXPECT_NE(error_of("radius: 0.1\nradus: 0.2\n").find("t.yaml:2: unknown key 'radus'"), std::string::npos);
}

TEST(ParamTable, AKeyItsConditionExcludesIsAnErrorNamingTheCondition) {
  const std::string m = error_of("mode: fast\nexact_only: 0.3\n");
  EXPECT_NE(m.find("t.yaml:2: 'exact_only': is read only with mode: exact"), std::string::npos) << m;
  EXPECT_EQ(error_of("mode: exact\nexact_only: 0.3\n"), "");
}

TEST(ParamTable, TwoRowsMayShareAKeyUnderExclusiveConditions) {
  struct S {
    Mode mode = Mode::Fast;
    double a = 1, b = 2;
  };
  const auto t = ParamTable<S>()
                     .choice("mode", &S::mode, {{"fast", Mode::Fast}, {"exact", Mode::Exact}}, "mode")
                     .real("step", "m", &S::a, 0, 10, "fast step")
                     .when("mode: fast", [](const S& s) { return s.mode == Mode::Fast; })
                     .real("step", "m", &S::b, 0, 10, "exact step")
                     .when("mode: exact", [](const S& s) { return s.mode == Mode::Exact; });
  S s;
  t.read(ConfigNode::load_string("mode: exact\nstep: 5\n", "t.yaml"), s);
  EXPECT_EQ(s.a, 1);
  EXPECT_EQ(s.b, 5);
  EXPECT_EQ(t.to_json(s).dump(), R"({"mode":"exact","step":5.0})");
  S f;
  t.read(ConfigNode::load_string("step: 3\n", "t.yaml"), f);
  EXPECT_EQ(f.a, 3);
  EXPECT_EQ(f.b, 2);
  // A key written twice without conditions is a programming error.
  EXPECT_THROW(ParamTable<S>().real("a", "m", &S::a, 0, 1, "").real("a", "m", &S::b, 0, 1, ""), std::logic_error);
}

// A struct extending Params takes its rows, conditions and rules at its own level: the
// same keys, order, echo, help and errors as Params' own table, without writing them.
TEST(ParamTable, ExtendTakesAnotherTablesKeysConditionsAndRules) {
  struct Wider {
    double scale = 2;
    Params base;
  };
  const auto t = ParamTable<Wider>().real("scale", "-", &Wider::scale, 0, 10, "a scale").extend(&Wider::base, table());
  Wider w;
  t.read(ConfigNode::load_string("scale: 3\nradius: 0.2\nmode: exact\nexact_only: 0.25\ninner: {x: 7}\n", "t.yaml"),
         w);
  EXPECT_EQ(w.scale, 3);
  EXPECT_EQ(w.base.radius, 0.2);
  EXPECT_EQ(w.base.mode, Mode::Exact);
  EXPECT_EQ(w.base.exact_only, 0.25);
  EXPECT_EQ(w.base.inner.x, 7);
  nlohmann::ordered_json own = table().to_json(w.base), echo = t.to_json(w);
  EXPECT_EQ(echo["scale"], 3.0);
  echo.erase("scale");
  EXPECT_EQ(echo.dump(), own.dump());
  const std::vector<KeyInfo> keys = t.keys(Wider{}), base_keys = table().keys(Params{});
  ASSERT_EQ(keys.size(), base_keys.size() + 1);
  for (std::size_t i = 0; i < base_keys.size(); ++i) {
    EXPECT_EQ(keys[i + 1].key, base_keys[i].key);
    EXPECT_EQ(keys[i + 1].range, base_keys[i].range);
    EXPECT_EQ(keys[i + 1].default_value, base_keys[i].default_value);
    EXPECT_EQ(keys[i + 1].when, base_keys[i].when);
  }
  const auto error = [&](const std::string& yaml) {
    try {
      Wider v;
      t.read(ConfigNode::load_string(yaml, "t.yaml"), v);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("radius: 0.9\n").find("t.yaml:1: 'radius'"), std::string::npos);                        // range
  EXPECT_NE(error("exact_only: 0.3\n").find("is read only with mode: exact"), std::string::npos);       // condition
  EXPECT_NE(error("count: 6\nradius: 0.2\n").find("more than 5 only below 0.1 m"), std::string::npos);  // rule
}

TEST(ParamTable, RequiredKeysMustBeWritten) {
  struct S {
    std::vector<std::string> command;
  };
  const auto t = ParamTable<S>().strings("command", &S::command, 1, "the program").required();
  S s;
  try {
    t.read(ConfigNode::load_string("{}", "t.yaml"), s);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'command': missing: the program"), std::string::npos) << e.what();
  }
  EXPECT_EQ(t.keys(S{})[0].default_value, "(required)");
}

TEST(ParamTable, TheEchoReadsBackAsTheSameValues) {
  Params p;
  const ConfigNode n =
      ConfigNode::load_string("radius: 0.123456789012345\nmode: exact\nexact_only: 0.7\nmodes: [exact]\n", "t.yaml");
  table().read(n, p);
  const nlohmann::ordered_json j = table().to_json(p);
  Params back;
  table().read(ConfigNode::load_string(j.dump(), "echo"), back);
  EXPECT_EQ(table().to_json(back), j);
  EXPECT_EQ(back.radius, p.radius);
  // Keys whose condition fails are not echoed (they would not read back).
  EXPECT_FALSE(table().to_json(Params{}).contains("exact_only"));
}

TEST(ParamTable, KeysGiveUnitRangeDefaultAndWhetherTheDefaultIsInRange) {
  const auto keys = table().keys(Params{});
  ASSERT_GE(keys.size(), 12u);
  EXPECT_EQ(keys[0].key, "radius");
  EXPECT_EQ(keys[0].unit, "m");
  EXPECT_EQ(keys[0].range, "[0.0001, 0.5]");
  EXPECT_EQ(keys[0].default_value, "0.01");
  bool nested = false;
  for (const auto& k : keys) {
    EXPECT_TRUE(k.default_in_range) << k.key;
    nested = nested || k.key == "inner.x";
  }
  EXPECT_TRUE(nested);
  Params bad;
  bad.radius = 1;
  EXPECT_FALSE(table().keys(bad)[0].default_in_range);
  const std::string help = table().help(Params{});
  for (const auto& k : keys) EXPECT_NE(help.find(k.key), std::string::npos) << k.key;
  EXPECT_NE(help.find("(only with mode: exact)"), std::string::npos) << help;
}

TEST(ParamNumber, ShortestTextThatReadsBack) {
  EXPECT_EQ(param_number(10.0), "10");
  EXPECT_EQ(param_number(0.1), "0.1");
  EXPECT_EQ(param_number(1e-9), "1e-09");
  EXPECT_EQ(param_number(1e9), "1000000000");
  EXPECT_EQ(param_number(0.45f), "0.45");
  EXPECT_EQ(std::stod(param_number(M_PI)), M_PI);
}

TEST(Registry, FindsByTypeAndNamesTheRegisteredOnes) {
  struct A {
    double a = 1;
  };
  const Registry<double> r("widget", {entry<double>("twice", "2 a", ParamTable<A>().real("a", "-", &A::a, 0, 5, "a"),
                                                    A{}, [](const A& p, const ConfigNode&) { return 2 * p.a; })});
  nlohmann::ordered_json params;
  EXPECT_EQ(r.create(ConfigNode::load_string("type: twice\na: 2\n", "t.yaml"), params), 4);
  EXPECT_EQ(params.dump(), R"({"type":"twice","a":2.0})");
  try {
    r.create(ConfigNode::load_string("type: thrice\n", "t.yaml"), params);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml:1: 'type': unknown value 'thrice'; allowed: twice"),
              std::string::npos)
        << e.what();
  }
  try {
    r.create(ConfigNode::load_string("a: 1\n", "t.yaml"), params);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing: one of the registered widgets: twice"), std::string::npos)
        << e.what();
  }
  EXPECT_NE(r.help().find("twice: 2 a"), std::string::npos);
}

}  // namespace
}  // namespace grapebench

namespace grapebench {
namespace {

struct Free {
  std::string module = "m";
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
};

const ParamTable<Free>& free_table() {
  static const ParamTable<Free> t = ParamTable<Free>()
                                        .string("module", &Free::module, "a name")
                                        .document("params", &Free::params, "handed through");
  return t;
}

// A free mapping keeps YAML 1.2's core types: what a Python estimator's own settings
// arrive as (algorithms/external/python_estimator.h).
TEST(ParamTable, ADocumentKeepsYamlTypesAndAStringMustNotBeEmpty) {
  Free f;
  const auto node = ConfigNode::load_string(
      "module: mine\nparams: {i: 3, neg: -2, x: 2.5e-3, t: true, F: False, s: hello, q: '7', n: null, tilde: ~, "
      "l: [1, two, 3.0], m: {k: [yes]}, big: 123456789012345678901234567890, inf: .inf}\n",
      "free.yaml");
  free_table().read(node, f);
  node.report_unused();
  EXPECT_EQ(f.module, "mine");
  const auto& p = f.params;
  EXPECT_TRUE(p["i"].is_number_integer()) << p.dump();
  EXPECT_EQ(p["i"], 3);
  EXPECT_EQ(p["neg"], -2);
  EXPECT_TRUE(p["x"].is_number_float());
  EXPECT_DOUBLE_EQ(p["x"].get<double>(), 2.5e-3);
  EXPECT_EQ(p["t"], true);
  EXPECT_EQ(p["F"], false);
  EXPECT_EQ(p["s"], "hello");
  EXPECT_EQ(p["q"], "7");  // quoted: a string
  EXPECT_TRUE(p["n"].is_null() && p["tilde"].is_null());
  EXPECT_EQ(p["l"].dump(), "[1,\"two\",3.0]");
  EXPECT_EQ(p["m"]["k"][0], "yes");  // YAML 1.2: yes is a string
  EXPECT_TRUE(p["big"].is_number_float());  // past 64 bits: the nearest double
  EXPECT_EQ(p["inf"], ".inf");               // not finite: kept as written
  EXPECT_EQ(free_table().to_json(f)["params"], p);

  Free g;
  EXPECT_THROW(free_table().read(ConfigNode::load_string("params: [1, 2]\n", "free.yaml"), g), InputError);
  try {
    free_table().read(ConfigNode::load_string("module: ''\n", "free.yaml"), g);
    FAIL() << "an empty string was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("free.yaml:1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("must not be empty"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grapebench
