// The options a user meets: `register --help` lists the ones users set (and says how to see
// the rest), --help-all every one; --preset with an option beside it; docs/cli.md's
// reference agrees with the program's declarations.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"
#include "tests/cli_helpers.h"

namespace f2c::cli_test {
namespace {
namespace fs = std::filesystem;

// The options --help lists: the lines of its option groups that start with a flag.
int OptionLines(const std::string& help) {
  std::istringstream lines(help);
  int n = 0;
  for (std::string line; std::getline(lines, line);) n += std::regex_search(line, std::regex("^  -"));
  return n;
}

TEST(CliOptions, HelpListsTheOptionsUsersSetAndHelpAllEveryOne) {
  const Result help = RunCli("register --help");
  ASSERT_EQ(help.code, 0) << help.output;
  const int shown = OptionLines(help.output);
  EXPECT_LE(shown, 30) << help.output;
  EXPECT_GE(shown, 20) << help.output;
  for (const char* flag :
       {"--output", "--intrinsics", "--preset", "--voxel-size", "--threads", "--no-mesh", "--last"}) {
    EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
  }
  EXPECT_EQ(help.output.find("--ransac-threshold"), std::string::npos);
  const Result all = RunCli("register --help-all");
  ASSERT_EQ(all.code, 0) << all.output;
  const int every = OptionLines(all.output);
  EXPECT_GT(every, 150);
  EXPECT_NE(all.output.find("--ransac-threshold"), std::string::npos);
  // --help says how many it left out, and where they are.
  EXPECT_NE(help.output.find(std::to_string(every - shown) + " more options, grouped: register --help-all"),
            std::string::npos)
      << help.output;
}

TEST(CliOptions, APresetSetsItsValuesButAnOptionGivenBesideItWins) {
  const fs::path scan = SyntheticTum("preset", 12), out = scan.parent_path() / "out";
  const Result r =
      RunCli("register " + scan.string() + " -o " + out.string() +
             " --intrinsics primesense -q --no-mesh --no-report --preset paper --polish-iterations 2 --write-config " +
             (scan.parent_path() / "paper.toml").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json run = nlohmann::json::parse(ReadFileToString(out / "run.json"));
  EXPECT_EQ(run["preset"], "paper");
  const nlohmann::json& refine = run["options"]["refine"];
  EXPECT_EQ(refine["loops"]["enabled"], false);
  EXPECT_EQ(refine["solver"]["weight_velocity"], 0.0);
  EXPECT_EQ(refine["local"]["information"], false);
  EXPECT_EQ(refine["self_check"]["enabled"], false);
  EXPECT_EQ(refine["windows"]["polish_iterations"], 2);  // given beside the preset
  // The written config reproduces the run: the preset's values are left to the preset, the
  // option given is kept.
  const std::string config = ReadFileToString(scan.parent_path() / "paper.toml");
  EXPECT_NE(config.find("preset=\"paper\""), std::string::npos) << config;
  EXPECT_NE(config.find("polish-iterations=2"), std::string::npos) << config;
  EXPECT_EQ(config.find("weight-velocity="), std::string::npos) << config;
  const fs::path again = scan.parent_path() / "again";
  ASSERT_EQ(RunCli("register " + scan.string() + " -o " + again.string() +
                   " --intrinsics primesense -q --no-mesh --no-report --config " +
                   (scan.parent_path() / "paper.toml").string())
                .code,
            0);
  const nlohmann::json rerun = nlohmann::json::parse(ReadFileToString(again / "run.json"));
  EXPECT_EQ(rerun["options"]["refine"], refine);
  EXPECT_EQ(ReadFileToString(again / "trajectory.txt"), ReadFileToString(out / "trajectory.txt"));
  // Every flag the fast preset names is one of register's: its config leaves them out.
  const fs::path fast_config = scan.parent_path() / "fast.toml";
  ASSERT_EQ(RunCli("register " + scan.string() +
                   " --intrinsics primesense -q --no-report --stop-after odometry "
                   "--preset fast --write-config " +
                   fast_config.string() + " -o " + (scan.parent_path() / "fast").string())
                .code,
            0);
  const std::string fast = ReadFileToString(fast_config);
  EXPECT_NE(fast.find("preset=\"fast\""), std::string::npos) << fast;
  for (const char* key : {"voxel-size=", "polish-iterations=", "self-check="}) {
    EXPECT_EQ(fast.find(key), std::string::npos) << key;
  }
  const Result bad =
      RunCli("register " + scan.string() + " --intrinsics primesense -o " + out.string() + " --preset quick");
  EXPECT_EQ(bad.code, 1);
  EXPECT_EQ(bad.output, "error: --preset: unknown value 'quick' (default, fast, paper)\n");
}

// docs/cli.md holds the reference `fine2coarse cli-reference` prints, between two markers;
// scripts/update_cli_doc.sh rewrites it.
// A config file says each thing once and completely: a repeated key (in one section, in a
// repeated section, dotted at the top and again in its section), a key without a value and
// a string or list never closed are usage errors naming the line, before anything runs.
TEST(CliOptions, AConfigFileThatSaysAThingTwiceOrHalfIsAUsageError) {
  const fs::path scan = SyntheticTum("config_lines", 3), dir = testing::FreshTempDir("config_lines_files");
  const std::pair<std::string, std::string> cases[] = {
      {"[register]\noutput = \"o/x\n", ":2: 'output': a string that is never closed"},
      {"[register]\nseed = 1\nseed = 2\n", ":3: 'register.seed' given twice (first on line 2)"},
      {"register.seed = 1\n[register]\nseed = 2\n", ":3: 'register.seed' given twice (first on line 1)"},
      {"[register]\nseed = 1\n[register]\n# again\nseed = 2\n", ":5: 'register.seed' given twice (first on line 2)"},
      {"[register]\nseed =\n", ":2: 'seed' has no value (\"\" for empty text)"},
      {"[register]\nsequence = \"a\" b\n", ":2: 'sequence': text after the closing quote"},
      {"[evaluate]\nalso = [\"a=b\"\n", ":2: 'also': a list that is never closed"},
  };
  int k = 0;
  for (const auto& [text, message] : cases) {
    const fs::path config = dir / ("c" + std::to_string(k++) + ".toml");
    WriteFileAtomic(config, text);
    const Result r = RunCli("--config " + config.string() + " register " + scan.string() + " -q -o " +
                            (dir / "out").string() + " --intrinsics primesense --stop-after odometry");
    EXPECT_EQ(r.code, 2) << text;
    EXPECT_EQ(r.output, "error: " + config.string() + message + "\n");
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  // Well-formed: comments after values, an empty string, a list.
  const fs::path good = dir / "good.toml";
  WriteFileAtomic(good, "[register]\nseed = 3  # why\nsequence = \"\"\n[evaluate]\nalso = [\"a=b\", \"c=d\"]\n");
  const Result r = RunCli("--config " + good.string() + " register " + scan.string() + " -q -o " +
                          (dir / "out").string() + " --intrinsics primesense --stop-after odometry --no-report");
  EXPECT_EQ(r.code, 0) << r.output;
}

TEST(CliOptions, DocsCliMdAgreesWithTheDeclarations) {
  const Result printed = RunCli("cli-reference", " 2>/dev/null");
  ASSERT_EQ(printed.code, 0);
  const std::string doc = ReadFileToString(fs::path(F2C_SOURCE_DIR) / "docs" / "cli.md");
  const std::string begin = "<!-- generated by fine2coarse cli-reference: do not edit -->\n";
  const std::string end = "<!-- end of the generated reference -->\n";
  const size_t a = doc.find(begin), b = doc.find(end);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_TRUE(doc.substr(a + begin.size(), b - a - begin.size()) == printed.output)
      << "docs/cli.md is out of date: run bash scripts/update_cli_doc.sh";
}

}  // namespace
}  // namespace f2c::cli_test
