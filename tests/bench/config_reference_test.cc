// The method types' reference (bench/config/config_reference.h): `calibench methods` and the
// methods part of `calibench config-reference` list every option of every registered type with
// its declared type, default, unit and doc. Properties of every registered type, never a literal
// list of them. Checked by hand: dropping the doc cell from the table, or `--type` listing every
// type, fails these tests.
#include "bench/config/config_reference.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "tests/common/cli_run.h"
#include "tests/common/option_specs.h"
#include "tests/common/temp_files.h"

namespace calibench {
namespace {

// The lines of `text` from the heading of type `name` to the next type's heading.
std::string TypeBlock(const std::string& text, const std::string& name) {
  const size_t begin = text.find("**" + name + "** (");
  if (begin == std::string::npos) return "";
  const size_t end = text.find("\n**", begin);
  return text.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

// The table row of option `key` in `block`; "" when there is none.
std::string Row(const std::string& block, const std::string& key) {
  const size_t begin = block.find("\n| `" + key + "` |");
  if (begin == std::string::npos) return "";
  return block.substr(begin + 1, block.find('\n', begin + 1) - begin - 1);
}

TEST(ConfigReference, MethodsListsEveryOptionOfEveryTypeWithItsUnitAndDoc) {
  std::string text, why;
  ASSERT_TRUE(MethodsReference("", &text, &why)) << why;
  for (const MethodType& t : MethodTypes()) {
    const std::string block = TypeBlock(text, t.name);
    ASSERT_FALSE(block.empty()) << t.name << " missing from:\n" << text;
    EXPECT_NE(block.find(t.description), std::string::npos) << block;
    EXPECT_NE(block.find(t.enabled_by_default ? "(enabled by default)" : "(disabled by default)"),
              std::string::npos)
        << block;
    EXPECT_NE(block.find("| key | type | default | unit | meaning |"), std::string::npos) << block;
    const std::vector<OptionSpec> specs = OptionSpecs(*t.create());
    ASSERT_FALSE(specs.empty()) << t.name;
    for (const OptionSpec& o : specs) {
      const std::string row = Row(block, o.key);
      ASSERT_FALSE(row.empty()) << t.name << "." << o.key << " missing from:\n" << block;
      // key | type | default | unit | meaning: the last two cells are the declaration's.
      const std::string unit = *o.unit ? o.unit : "–";
      const std::string tail = " | " + unit + " | " + o.doc + " |";
      ASSERT_GE(row.size(), tail.size()) << row;
      EXPECT_EQ(row.substr(row.size() - tail.size()), tail) << t.name << "." << o.key;
    }
  }
}

TEST(ConfigReference, MethodsOfOneTypeListOnlyThatType) {
  for (const MethodType& t : MethodTypes()) {
    std::string text, why;
    ASSERT_TRUE(MethodsReference(t.name, &text, &why)) << why;
    EXPECT_EQ(text, MethodTypeReference(t));
    for (const MethodType& other : MethodTypes()) {
      if (other.name != t.name) {
        EXPECT_EQ(TypeBlock(text, other.name), "") << t.name;
      }
    }
  }
}

TEST(ConfigReference, MethodsOfAnUnknownTypeFailNamingTheKnownTypes) {
  std::string text = "unchanged", why;
  EXPECT_FALSE(MethodsReference("nosuch", &text, &why));
  EXPECT_EQ(text, "unchanged");
  EXPECT_NE(why.find("unknown method type 'nosuch'"), std::string::npos) << why;
  EXPECT_EQ(why.find("did you mean"), std::string::npos) << why;
  for (const MethodType& t : MethodTypes()) EXPECT_NE(why.find(t.name), std::string::npos) << why;
  const std::string first = MethodTypes().front().name;
  const std::string misspelt = first.substr(0, first.size() - 1);  // One letter dropped.
  EXPECT_FALSE(MethodsReference(misspelt, &text, &why));
  EXPECT_NE(why.find("did you mean '" + first + "'?"), std::string::npos) << why;
}

// One home: the configuration reference holds exactly these blocks.
TEST(ConfigReference, ConfigurationReferenceHoldsEveryTypesBlock) {
  const std::string reference = ConfigurationReference();
  for (const MethodType& t : MethodTypes()) {
    EXPECT_NE(reference.find(MethodTypeReference(t)), std::string::npos) << t.name;
  }
}

CliRun Calibench(const std::string& args) { return RunCli(CALIBENCH_BINARY, args); }

TEST(ConfigReference, MethodsCommandPrintsTheReferenceAndRefusesAnUnknownType) {
  std::string text, why;
  ASSERT_TRUE(MethodsReference("", &text, &why)) << why;
  const CliRun all = Calibench("methods");
  EXPECT_EQ(all.status, 0) << all.output;
  EXPECT_EQ(all.output, text);
  const std::string last = MethodTypes().back().name;
  const CliRun one = Calibench("methods --type " + last);
  EXPECT_EQ(one.status, 0) << one.output;
  EXPECT_EQ(one.output, MethodTypeReference(MethodTypes().back()));
  const CliRun bad = Calibench("methods --type nosuch");
  EXPECT_NE(bad.status, 0) << bad.output;
  EXPECT_NE(bad.output.find("calibench: methods: unknown method type 'nosuch'"), std::string::npos)
      << bad.output;
  for (const MethodType& t : MethodTypes()) {
    EXPECT_NE(bad.output.find(t.name), std::string::npos) << bad.output;
  }
}

}  // namespace
}  // namespace calibench
