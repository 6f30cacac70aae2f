// The registry: every type is listed once, makes a valid default method that clones, and its
// options survive the text key and the setter (what the config I/O and the sweep sharing rely on).
// Properties of every registered type, never a literal list of them.
#include "methods/registry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <regex>
#include <set>
#include <utility>

#include "methods/options.h"
#include "tests/common/method_input.h"
#include "tests/common/option_specs.h"

namespace calibench {
namespace {

// Properties of every registered type (no literal list: a new type is checked by being listed).
TEST(Registry, EveryTypeIsNamedOnceAndFindable) {
  ASSERT_FALSE(MethodTypes().empty());
  std::set<std::string> names;
  bool any_enabled = false;
  for (const MethodType& t : MethodTypes()) {
    EXPECT_FALSE(t.name.empty());
    EXPECT_EQ(t.name.find_first_of(" .[],;="), std::string::npos) << t.name;
    EXPECT_TRUE(names.insert(t.name).second) << "listed twice: " << t.name;
    EXPECT_FALSE(t.description.empty()) << t.name;
    EXPECT_EQ(FindMethodType(t.name), &t) << t.name;
    EXPECT_NE(MethodTypeNames().find(t.name), std::string::npos) << t.name;
    for (const std::string& companion : t.companions) {
      EXPECT_NE(FindMethodType(companion), nullptr) << t.name << " adds unknown " << companion;
    }
    any_enabled = any_enabled || t.enabled_by_default;
  }
  EXPECT_TRUE(any_enabled) << "a scenario without methods: would run nothing";
  EXPECT_EQ(FindMethodType("nope"), nullptr);
}

TEST(Registry, EveryTypeMakesAValidDefaultWithAStableKey) {
  for (const MethodType& t : MethodTypes()) {
    const std::unique_ptr<Method> m = t.create();
    ASSERT_NE(m, nullptr) << t.name;
    std::string why;
    EXPECT_TRUE(m->Check(&why)) << t.name << ": " << why;
    const std::string key = OptionsKey(*m);
    EXPECT_FALSE(key.empty()) << t.name;
    const std::unique_ptr<Method> clone = m->Clone();
    ASSERT_NE(clone, nullptr) << t.name;
    EXPECT_EQ(OptionsKey(*clone), key) << t.name;
    EXPECT_EQ(OptionsKey(*t.create()), key) << t.name;
    EXPECT_TRUE(MethodInstance::OfType(t.name, t.name) == MethodInstance::OfType(t.name, t.name));
  }
}

// Every option of every type survives the writer (its text in the key) and the parser (SetOption
// from that text): the key reads back to itself, option by option. Cameras have no text form.
TEST(Registry, EveryOptionRoundTripsThroughItsText) {
  for (const MethodType& t : MethodTypes()) {
    const std::unique_ptr<Method> m = t.create();
    const std::string key = OptionsKey(*m);
    size_t options = 0;
    for (size_t start = 0; start < key.size();) {
      const size_t end = key.find(';', start);
      const std::string entry = key.substr(start, end - start);
      start = end == std::string::npos ? key.size() : end + 1;
      const size_t eq = entry.find('=');
      ASSERT_NE(eq, std::string::npos) << t.name << ": " << entry;
      const std::string name = entry.substr(0, eq), value = entry.substr(eq + 1);
      std::string why;
      if (!SetOption(m.get(), name, value, &why)) {
        EXPECT_NE(why.find("camera"), std::string::npos) << t.name << "." << name << ": " << why;
        continue;
      }
      ++options;
      EXPECT_EQ(OptionsKey(*m), key) << t.name << "." << name << "=" << value;
    }
    EXPECT_GT(options, 0u) << t.name;
    std::string why;
    EXPECT_FALSE(SetOption(m.get(), "no_such_option", "1", &why)) << t.name;
    EXPECT_NE(why.find("unknown option"), std::string::npos) << why;
  }
}

// Setting each option from the text of another value changes the key, and setting it back
// restores it: no option is lost between the visitor's reading and writing passes.
TEST(Registry, SetOptionChangesExactlyThatOption) {
  const std::unique_ptr<Method> m = MakeMethod("adaptive");
  const std::string before = OptionsKey(*m);
  std::string why;
  ASSERT_TRUE(SetOption(m.get(), "alpha", "250", &why)) << why;
  EXPECT_NE(OptionsKey(*m), before);
  EXPECT_NE(OptionsKey(*m).find("alpha=250;"), std::string::npos) << OptionsKey(*m);
  ASSERT_TRUE(SetOption(m.get(), "alpha", "1000", &why)) << why;
  EXPECT_EQ(OptionsKey(*m), before);
  EXPECT_FALSE(SetOption(m.get(), "alhpa", "5", &why));
  EXPECT_NE(why.find("unknown option 'alhpa'"), std::string::npos) << why;
  EXPECT_FALSE(SetOption(m.get(), "alpha", "-1", &why));
  EXPECT_NE(why.find("alpha must be"), std::string::npos) << why;
  EXPECT_FALSE(SetOption(m.get(), "alpha", "fast", &why));
  EXPECT_NE(why.find("expected a number"), std::string::npos) << why;
  const std::unique_ptr<Method> ceres = MakeMethod("ceres");
  ASSERT_TRUE(SetOption(ceres.get(), "model", "pinhole-k2", &why)) << why;
  EXPECT_NE(OptionsKey(*ceres).find("model=pinhole-k2;"), std::string::npos);
  EXPECT_FALSE(SetOption(ceres.get(), "model", "fisheye", &why));
  EXPECT_FALSE(SetOption(ceres.get(), "loss", "l1", &why));
}

// Key suffixes and the unit each names (the house rule "units in names"), longest first: a
// variance rate `q_focal_px2_s` is px²/s, not s.
const std::vector<std::pair<std::string, std::string>>& UnitSuffixes() {
  static const std::vector<std::pair<std::string, std::string>> suffixes = {
      {"_px2_s", "px²/s"}, {"_rad2_s", "rad²/s"}, {"_m2_s", "m²/s"}, {"_s", "s"},
      {"_px", "px"},       {"_deg", "deg"},       {"_hz", "Hz"},     {"_m", "m"}};
  return suffixes;
}

// The unit `key`'s suffix names; "" when it names none.
std::string UnitOfSuffix(const std::string& key) {
  for (const auto& [suffix, unit] : UnitSuffixes()) {
    if (key.size() > suffix.size() &&
        key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0) {
      return unit;
    }
  }
  return "";
}

// Every option of every registered type is documented: a snake_case key, a one-line doc (the
// reference's table cell: no newline, no '|'), and the unit its key's suffix names; a unit that a
// suffix stands for is only declared on keys with that suffix. Checked by hand: emptying the doc
// of adaptive's `alpha` or giving `max_step_s` the unit "ms" fails this test.
TEST(Registry, EveryOptionHasADocAndTheUnitOfItsKey) {
  const std::regex snake_case("[a-z][a-z0-9]*(_[a-z0-9]+)*");
  std::set<std::string> suffix_units;
  for (const auto& entry : UnitSuffixes()) suffix_units.insert(entry.second);
  for (const MethodType& t : MethodTypes()) {
    const std::vector<OptionSpec> specs = OptionSpecs(*t.create());
    EXPECT_FALSE(specs.empty()) << t.name;
    std::set<std::string> keys;
    for (const OptionSpec& o : specs) {
      ASSERT_NE(o.key, nullptr) << t.name;
      ASSERT_NE(o.unit, nullptr) << t.name << "." << o.key;
      ASSERT_NE(o.doc, nullptr) << t.name << "." << o.key;
      const std::string key = o.key, unit = o.unit, doc = o.doc;
      const std::string where = t.name + "." + key;
      EXPECT_TRUE(keys.insert(key).second) << where << " declared twice";
      EXPECT_TRUE(std::regex_match(key, snake_case)) << where << ": not snake_case";
      EXPECT_FALSE(doc.empty()) << where << ": no doc";
      EXPECT_EQ(doc.find_first_of("\n|"), std::string::npos) << where << ": " << doc;
      const std::string expected = UnitOfSuffix(key);
      if (!expected.empty()) {
        EXPECT_EQ(unit, expected) << where << ": its key's suffix names " << expected;
      } else {
        EXPECT_EQ(suffix_units.count(unit), 0u)
            << where << ": unit " << unit << " without its suffix in the key";
      }
    }
  }
}

// Every output of every registered type is declared as runs.csv needs it: a snake_case name that
// ends in its unit (metrics/metric_table.h, rule 1: _px, _deg, _m, _s; none when dimensionless),
// a label and a one-line doc; DeclaredOutputs holds each once, in registry order. A windup law
// names options of its type. Checked by hand: giving adaptive's pe_min_eig the unit "s" fails.
TEST(Registry, EveryOutputIsDeclaredWithItsUnitAndDocOnce) {
  const std::regex snake_case("[a-z][a-z0-9]*(_[a-z0-9]+)*");
  std::vector<std::string> expected;
  for (const MethodType& t : MethodTypes()) {
    const std::unique_ptr<Method> m = t.create();
    for (const OutputSpec& o : m->Outputs()) {
      const std::string name = o.name, unit = o.unit, where = t.name + " output " + name;
      EXPECT_TRUE(std::regex_match(name, snake_case)) << where;
      EXPECT_FALSE(std::string(o.label).empty()) << where;
      EXPECT_FALSE(std::string(o.doc).empty()) << where;
      EXPECT_EQ(std::string(o.doc).find_first_of("\n|"), std::string::npos) << where;
      EXPECT_EQ(UnitOfSuffix(name), unit) << where << ": its name must end in its unit";
      if (std::find(expected.begin(), expected.end(), name) == expected.end()) {
        expected.push_back(name);
      }
    }
    if (const std::optional<WindupLaw> law = m->Windup()) {
      std::set<std::string> keys;
      for (const OptionSpec& o : OptionSpecs(*m)) keys.insert(o.key);
      EXPECT_EQ(keys.count(law->exponent_option), 1u) << t.name << ": " << law->exponent_option;
      for (const char* option : law->only_when_zero) {
        EXPECT_EQ(keys.count(option), 1u) << t.name << ": " << option;
      }
    }
  }
  std::vector<std::string> declared;
  for (const OutputSpec& o : DeclaredOutputs()) declared.push_back(o.name);
  EXPECT_EQ(declared, expected);
}

// A result may set only the outputs its type declares (the harness fails the row otherwise).
TEST(Registry, CheckOutputsRefusesAnUndeclaredOutput) {
  const std::unique_ptr<Method> adaptive = MakeMethod("adaptive");
  ASSERT_FALSE(adaptive->Outputs().empty());
  MethodResult result;
  std::string why;
  EXPECT_TRUE(CheckOutputs(*adaptive, result, &why)) << why;  // Nothing set: every cell NaN.
  result.SetOutput(adaptive->Outputs().front(), 0.5);
  EXPECT_TRUE(CheckOutputs(*adaptive, result, &why)) << why;
  result.outputs["no_such_output"] = 1.0;
  EXPECT_FALSE(CheckOutputs(*adaptive, result, &why));
  EXPECT_NE(why.find("no_such_output"), std::string::npos) << why;
  MethodResult of_adaptive;
  of_adaptive.SetOutput(adaptive->Outputs().front(), 0.5);
  for (const MethodType& t : MethodTypes()) {  // A type that declares none refuses another's.
    const std::unique_ptr<Method> m = t.create();
    if (m->Outputs().empty()) {
      EXPECT_FALSE(CheckOutputs(*m, of_adaptive, &why)) << t.name;
    }
  }
}

TEST(Registry, InstancesCopyDeeply) {
  MethodInstance a = MethodInstance::OfType("adaptive", "a");
  MethodInstance b = a;
  std::string why;
  ASSERT_TRUE(SetOption(b.method.get(), "alpha", "5", &why)) << why;
  EXPECT_NE(OptionsKey(*a.method), OptionsKey(*b.method));
  EXPECT_FALSE(a == b);
  b = a;
  EXPECT_TRUE(a == b);
  EXPECT_EQ(MethodInstance::OfType("bogus", "x").method, nullptr);
}

}  // namespace
}  // namespace calibench
