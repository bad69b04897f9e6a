// Strict YAML input (strict_yaml.h): one document, no duplicate keys, no application tags, for
// every file the tools read and for values on command lines; errors name the source and line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "flagella_sim/core/strict_yaml.h"
#include "flagella_sim/simulation/simulation_config.h"
#include "support/temp_dir.h"

namespace flagella {
namespace {

using testing::TempDir;

const std::string kDesign1 = std::string(FLAGELLA_CONFIG_DIR) + "/granular_design1.yaml";

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// The error of parsing `text`, with its line (0 if it parsed).
struct Outcome {
  std::string message;
  int line = 0;
  bool failed = false;
};
Outcome parse(const std::string& text) {
  Outcome out;
  try {
    loadStrictYamlText(text, "input");
  } catch (const YamlInputError& e) {
    out = {e.what(), e.line(), true};
  }
  return out;
}

std::string configError(const std::string& path, const std::vector<std::string>& overrides = {}) {
  return testing::errorMessageOf<ConfigError>([&] { loadSimulationConfig(path, overrides); });
}

TEST(StrictYaml, DuplicateKeyNamesBothLines) {
  const Outcome o = parse("a: 1\nb: 2\na: 3\n");
  ASSERT_TRUE(o.failed);
  EXPECT_EQ(o.line, 3);
  EXPECT_TRUE(contains(o.message, "duplicate key 'a'")) << o.message;
  EXPECT_TRUE(contains(o.message, "first given on line 1")) << o.message;
  EXPECT_TRUE(contains(o.message, "input: line 3")) << o.message;
}

TEST(StrictYaml, NestedDuplicateNamesTheDottedField) {
  const Outcome o = parse("motor:\n  omega_rpm: 10\n  ramp_time: 1\n  omega_rpm: .nan\n");
  ASSERT_TRUE(o.failed);
  EXPECT_EQ(o.line, 4);
  EXPECT_TRUE(contains(o.message, "duplicate key 'motor.omega_rpm'")) << o.message;
  // Inside a list of maps too.
  const Outcome in_list = parse("points:\n  - {x: 1, x: 2}\n");
  ASSERT_TRUE(in_list.failed);
  EXPECT_TRUE(contains(in_list.message, "duplicate key 'points[0].x'")) << in_list.message;
}

TEST(StrictYaml, EmptyDocumentsAreRejected) {
  const TempDir dir;
  for (const char* text :
       {"", "   \n\t\n", "# only a comment\n  # and another\n", "---\n", "~\n"}) {
    const std::string path = dir.write("empty.yaml", text);
    try {
      loadStrictYamlFile(path, "config");
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const YamlInputError& e) {
      EXPECT_TRUE(contains(e.what(), "config file is empty")) << e.what();
    }
  }
  // A value may be null (a --set value meaning "the default"), but not nothing.
  EXPECT_FALSE(parse("null").failed);
  EXPECT_TRUE(loadStrictYamlText("~", "value").IsNull());
  EXPECT_TRUE(parse("").failed);
  EXPECT_TRUE(parse("# nothing").failed);
}

TEST(StrictYaml, SecondDocumentIsRejectedWithItsLine) {
  const Outcome o = parse("a: 1\n---\na: 2\n");
  ASSERT_TRUE(o.failed);
  EXPECT_TRUE(contains(o.message, "2 YAML documents")) << o.message;
  EXPECT_GE(o.line, 2);
}

TEST(StrictYaml, StrayCommaAtTheTopLevelIsASyntaxError) {
  // Found by fuzz/fuzz_metadata: yaml-cpp's LoadAll stops in front of a top-level ',' without
  // consuming it and returns empty documents until memory runs out (std::bad_alloc or a hang).
  for (const char* text : {",", "[1], [2]\n", ", a\n", "{a: 1},\n"}) {
    const Outcome o = parse(text);
    ASSERT_TRUE(o.failed) << text;
    EXPECT_EQ(o.line, 1) << text;
    EXPECT_TRUE(contains(o.message, "YAML syntax error: unexpected ','")) << o.message;
  }
  const Outcome later = parse("a: 1\n---\n[1],\n");
  ASSERT_TRUE(later.failed);
  EXPECT_EQ(later.line, 3);
  const TempDir dir;
  const std::string msg = configError(dir.write("comma.yaml", "[1],\n"));
  EXPECT_TRUE(contains(msg, "comma.yaml: line 1, column 4: YAML syntax error")) << msg;
}

TEST(StrictYaml, AliasInsideItsOwnAnchorIsAnError) {
  // "&x [*x]" is a list holding itself: the checks recursed until the stack overflowed (an
  // AddressSanitizer stack-overflow report under fuzz/fuzz_config).
  const Outcome list = parse("a: &x [*x]\n");
  ASSERT_TRUE(list.failed);
  EXPECT_EQ(list.line, 1);
  EXPECT_TRUE(contains(list.message, "'a[0]' refers to a value that contains it")) << list.message;
  const Outcome map = parse("motor: &m {ramp: {x: *m}}\n");
  ASSERT_TRUE(map.failed);
  EXPECT_TRUE(contains(map.message, "'motor.ramp.x' refers to a value")) << map.message;
}

TEST(StrictYaml, RepeatedAliasesAreCheckedOnce) {
  // Each level repeats the one before ten times: 10^30 values when expanded, 300 when each
  // aliased value is checked once. Aliases of complete values stay plain YAML.
  std::string text = "l0: &l0 [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n";
  for (int level = 1; level <= 30; ++level) {
    const std::string previous = "*l" + std::to_string(level - 1);
    text += "l" + std::to_string(level) + ": &l" + std::to_string(level) + " [" + previous;
    for (int i = 1; i < 10; ++i) text += ", " + previous;
    text += "]\n";
  }
  EXPECT_FALSE(parse(text).failed);
  const Outcome duplicate = parse(text + "l7: 0\n");
  ASSERT_TRUE(duplicate.failed);
  EXPECT_TRUE(contains(duplicate.message, "duplicate key 'l7'")) << duplicate.message;
}

TEST(StrictYaml, HugeKeysAndTagsAreQuotedAbbreviated) {
  // Messages quote user text short (fuzz/ checks that every message is at most a few kB).
  const std::string huge(100000, 'k');
  for (const std::string& text : {"? " + huge + "\n: 1\n? " + huge + "\n: 2\n",
                                  "a: !" + huge + " 1\n", "? " + huge + "\n: [!x 1]\n"}) {
    const Outcome o = parse(text);
    ASSERT_TRUE(o.failed);
    EXPECT_LT(o.message.size(), 600u) << o.message.substr(0, 600);
    EXPECT_TRUE(contains(o.message, "characters)")) << o.message.substr(0, 600);
  }
}

TEST(StrictYaml, ApplicationTagsAreRejectedCoreTagsAccepted) {
  const Outcome tag = parse("a: 1\nb: !foo 3\n");
  ASSERT_TRUE(tag.failed);
  EXPECT_EQ(tag.line, 2);
  EXPECT_TRUE(contains(tag.message, "'!foo'")) << tag.message;
  EXPECT_TRUE(contains(tag.message, "'b'")) << tag.message;
  EXPECT_TRUE(parse("s: [1, !bar 2]\n").failed);
  EXPECT_TRUE(parse("!map {a: 1}\n").failed);
  // Plain, quoted and core-schema values are plain YAML.
  EXPECT_FALSE(parse("a: !!str 3\nb: \"x\"\nc: 'y'\nd: null\ne: [1, 2]\nf: {g: 1}\n").failed);
}

TEST(StrictYaml, SyntaxErrorsGiveLineAndColumn) {
  const Outcome o = parse("a: [1, 2\nb: 3\n");
  ASSERT_TRUE(o.failed);
  EXPECT_GT(o.line, 0);
  EXPECT_TRUE(contains(o.message, "YAML syntax error")) << o.message;
}

TEST(StrictYaml, ShippedConfigsAreStrict) {
  for (const char* name :
       {"granular_design1", "granular_design2", "interface_robot", "interface_path_planning",
        "helical_robot", "helical_gimbal", "helical_steering"}) {
    const std::string path = std::string(FLAGELLA_CONFIG_DIR) + "/" + name + ".yaml";
    EXPECT_NO_THROW(loadStrictYamlFile(path, "config")) << path;
  }
}

TEST(StrictYaml, ConfigWithADuplicatedSectionIsAnError) {
  // The reproducer of the issue: a NaN in a second 'motor' section was silently ignored.
  const TempDir dir;
  const std::string path =
      dir.write("dup.yaml", testing::readTextFile(kDesign1) + "motor:\n  omega_rpm: .nan\n");
  const std::string msg = configError(path);
  EXPECT_TRUE(contains(msg, path)) << msg;
  EXPECT_TRUE(contains(msg, "duplicate key 'motor'")) << msg;
}

TEST(StrictYaml, EmptyOrCommentOnlyConfigIsAnError) {
  const TempDir dir;
  for (const char* text : {"", "\n   \n", "# robot: nothing\n"}) {
    const std::string path = dir.write("empty.yaml", text);
    const std::string msg = configError(path);
    EXPECT_TRUE(contains(msg, "config file is empty")) << "'" << text << "': " << msg;
  }
}

TEST(StrictYaml, OverrideValueWithATagIsAnError) {
  const std::string msg = configError(kDesign1, {"motor.omega_rpm=!foo 30"});
  EXPECT_TRUE(contains(msg, "motor.omega_rpm")) << msg;
  EXPECT_TRUE(contains(msg, "'!foo'")) << msg;
}

TEST(StrictYaml, MissingFileAndDirectoryAreNamed) {
  const TempDir dir;
  EXPECT_TRUE(contains(configError(dir.path().string() + "/none.yaml"), "no such file"));
  EXPECT_TRUE(contains(configError(dir.path().string()), "not a regular file"));
}

}  // namespace
}  // namespace flagella
