// Tests of the `slam` front (apps/main.cc): per-command help lists exactly the
// command's flags with their defaults, and a flag of another command is
// refused instead of being ignored.
#include <string>

#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::ReadText;

size_t CountLines(const std::string& text) {
  size_t n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

TEST(CommandHelpTest, EvalHelpListsEvalFlagsOnlyWithDefaults) {
  const std::string log = testing::TempDir() + "/help.txt";
  ASSERT_EQ(testing::RunSlam("eval --help", log), 0) << ReadText(log);
  const std::string out = ReadText(log);
  EXPECT_NE(out.find("--rpe_delta (double, default 1)"), std::string::npos)
      << out;
  EXPECT_NE(out.find("--align (string, default \"se3\")"), std::string::npos)
      << out;
  EXPECT_NE(out.find("--unique_pairs (bool, default false)"),
            std::string::npos);
  EXPECT_NE(out.find("--rpe_delta_tol (double, default 0.1)"),
            std::string::npos);
  EXPECT_NE(out.find("shared flags:"), std::string::npos);
  EXPECT_NE(out.find("--report"), std::string::npos);
  // Not other commands' flags, nor glog's or gflags' own.
  for (const char* other : {"--window_size", "--solver", "--num_poses",
                            "--logtostderr", "--flagfile", "--gt "}) {
    EXPECT_EQ(out.find(other), std::string::npos) << other;
  }
  EXPECT_LT(CountLines(out), 80u);
  // -h and --helpfull are the same help.
  ASSERT_EQ(testing::RunSlam("eval -h", log), 0);
  EXPECT_EQ(ReadText(log), out);
}

TEST(CommandHelpTest, EveryCommandHasItsOwnHelp) {
  const std::string log = testing::TempDir() + "/help.txt";
  struct Case {
    const char* command;
    const char* has;
    const char* lacks;
  };
  for (const Case& c : {Case{"optimize", "--max_iterations", "--rpe_delta"},
                        Case{"inertial", "--window_size", "--align"},
                        Case{"simulate", "--num_poses", "--solver"},
                        Case{"run", "--output_dir", "--est"},
                        Case{"info", "--repair_information", "--config"},
                        Case{"vocabulary", "--levels", "--rpe_delta"},
                        Case{"loops", "--voc", "--levels"}}) {
    ASSERT_EQ(testing::RunSlam(std::string(c.command) + " --help", log), 0)
        << c.command;
    const std::string out = ReadText(log);
    EXPECT_NE(out.find(c.has), std::string::npos) << c.command << "\n" << out;
    EXPECT_EQ(out.find(c.lacks), std::string::npos) << c.command << "\n" << out;
  }
}

TEST(CommandHelpTest, AFlagOfAnotherCommandIsRefused) {
  const std::string log = testing::TempDir() + "/refused.txt";
  // Before: `slam inertial` accepted --align and ignored it.
  EXPECT_EQ(testing::RunSlam("inertial --align se3", log), 2);
  EXPECT_NE(ReadText(log).find(
                "slam inertial: --align is not a flag of this command"),
            std::string::npos)
      << ReadText(log);
  EXPECT_EQ(testing::RunSlam("eval --solver gn --ref a --est b", log), 2);
  EXPECT_NE(
      ReadText(log).find("slam eval: --solver is not a flag of this command"),
      std::string::npos)
      << ReadText(log);
  // Forwarded image commands check their flags the same way.
  EXPECT_EQ(testing::RunSlam("loops --levels 3", log), 2);
  EXPECT_NE(
      ReadText(log).find("slam loops: --levels is not a flag of this command"),
      std::string::npos)
      << ReadText(log);
  // Even with its default value.
  EXPECT_EQ(testing::RunSlam("simulate --max_iterations 100", log), 2);
  // An unknown flag is still gflags' error.
  EXPECT_NE(testing::RunSlam("eval --no_such_flag 1", log), 0);
}

}  // namespace
}  // namespace slam
