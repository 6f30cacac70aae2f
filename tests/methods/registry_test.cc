// The registry: every type is listed once, makes a valid default method, and its options survive
// the text key and the setter (what the config I/O and the sweep sharing rely on).
#include "methods/registry.h"

#include <gtest/gtest.h>

#include <set>

#include "methods/options.h"
#include "tests/common/method_input.h"

namespace calibench {
namespace {

TEST(Registry, ListsTheTypesInMapFormRowOrder) {
  std::vector<std::string> names;
  for (const MethodType& t : MethodTypes()) names.push_back(t.name);
  // The order the pre-registry harness wrote rows in (the map form keeps it), then the new ones.
  EXPECT_EQ(names, (std::vector<std::string>{"adaptive", "dlt", "zhang", "zhang_handeye", "ceres",
                                             "ekf"}));
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  EXPECT_EQ(FindMethodType("nope"), nullptr);
  EXPECT_TRUE(FindMethodType("adaptive")->enabled_by_default);
  EXPECT_FALSE(FindMethodType("ceres")->enabled_by_default);
}

TEST(Registry, EveryTypeMakesAValidDefaultWithAStableKey) {
  for (const MethodType& t : MethodTypes()) {
    const std::unique_ptr<Method> m = t.create();
    ASSERT_NE(m, nullptr) << t.name;
    std::string why;
    EXPECT_TRUE(m->Check(&why)) << t.name << ": " << why;
    const std::string key = OptionsKey(*m);
    EXPECT_FALSE(key.empty()) << t.name;
    EXPECT_EQ(OptionsKey(*m->Clone()), key) << t.name;
    EXPECT_EQ(OptionsKey(*t.create()), key) << t.name;
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
