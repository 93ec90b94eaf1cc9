// End-to-end tests of `slam info FILE` (apps/info_command.cc) through the
// binary: counts, components and the initial chi2 of a small graph whose
// figures are worked out by hand, agreement with `slam optimize` on a
// simulated graph, and clean failures.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::Contains;
using ::slam::testing::ReadText;
using ::slam::testing::RunSlam;
using ::slam::testing::TempDir;
using ::slam::testing::WriteText;

struct SlamRun {
  int code = -1;
  std::string out;
  std::string err;
  std::string all() const { return out + err; }
};

SlamRun RunCaptured(const std::string& args, const std::string& dir) {
  SlamRun run;
  run.code = RunSlam(args + " > '" + dir + "/stdout' 2> '" + dir + "/stderr'");
  run.out = ReadText(dir + "/stdout");
  run.err = ReadText(dir + "/stderr");
  return run;
}

// The number after `label` in `text` (NaN when absent).
double NumberAfter(const std::string& text, const std::string& label) {
  const size_t at = text.find(label);
  if (at == std::string::npos) return NAN;
  return std::strtod(text.c_str() + at + label.size(), nullptr);
}

// Two components: {0, 1, 2, 3} (odometry 0-1-2-3 and a loop closure 3-0)
// and {10, 11} (odometry 10-11). Errors e = t2v(Z^-1 X_i^-1 X_j):
//   0-1   X_0^-1 X_1 = (1, 0, 0) = Z                 chi2 0
//   1-2   X_1^-1 X_2 = (1, 0, 0), Z = (1.5, 0, 0)    e = (-0.5, 0, 0), I11 = 2
//                                                    chi2 0.5
//   2-3   X_2^-1 X_3 = (-2, 0, 0) = Z                chi2 0
//   3-0   identity, Z = (0, 0, 0.1)                  e = (0, 0, -0.1), I33 =
//   100
//                                                    chi2 1.0
//   10-11 X_10^-1 X_11 = (1, 0, 0), Z = (1, 0.5, 0)  e = (0, -0.5, 0), I22 = 4
//                                                    chi2 1.0
// Total 2.5; odometry 4 (ids differ by 1), loop closures 1.
constexpr char kFixture[] =
    "# slam info fixture\n"
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1 0 0\n"
    "VERTEX_SE2 2 2 0 0\n"
    "VERTEX_SE2 3 0 0 0\n"
    "VERTEX_SE2 10 5 5 0\n"
    "VERTEX_SE2 11 6 5 0\n"
    "FIX 0\n"
    "\n"
    "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
    "EDGE_SE2 1 2 1.5 0 0 2 0 0 1 0 1\n"
    "EDGE_SE2 2 3 -2 0 0 1 0 0 1 0 1\n"
    "EDGE_SE2 3 0 0 0 0.1 1 0 0 1 0 100\n"
    "EDGE_SE2 10 11 1 0.5 0 4 0 0 4 0 4\n";

TEST(InfoCommandTest, CountsComponentsAndChi2OfAHandmadeGraph) {
  const std::string tmp = TempDir();
  const std::string path = tmp + "/graph.g2o";
  WriteText(path, kFixture);
  const SlamRun run = RunCaptured("info " + path, tmp);
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(run.err.empty()) << run.err;
  EXPECT_TRUE(Contains(run.out, "file: " + path + "\n")) << run.out;
  EXPECT_TRUE(Contains(run.out, "nodes: 6  pose2 6  (fixed 1)\n")) << run.out;
  EXPECT_TRUE(Contains(run.out, "factors: 5 (odometry 4, loop closures 1)\n"))
      << run.out;
  EXPECT_TRUE(Contains(run.out, "connected components: 2 (largest 4 nodes)\n"))
      << run.out;
  EXPECT_NEAR(NumberAfter(run.out, "initial chi2 (g2o convention): "), 2.5,
              1e-9)
      << run.out;
  // Per factor type: 5 between factors holding all of it.
  const std::regex by_type(R"(between_se2\s+5\s+chi2 ([0-9.eE+-]+))");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(run.out, match, by_type)) << run.out;
  EXPECT_NEAR(std::stod(match[1]), 2.5, 1e-9);
  EXPECT_FALSE(Contains(run.out, "repaired")) << run.out;
}

TEST(InfoCommandTest, ThreeDimensionalGraphAndEdgeOnlyFile) {
  const std::string tmp = TempDir();
  // SE(3): two poses one metre apart, measured exactly, plus an unknown tag.
  const std::string path3 = tmp + "/g3.g2o";
  WriteText(path3,
            "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
            "VERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
            "VERTEX_SE3:QUAT 2 1 0 1 0 0 0 1\n"
            "EQUIV 0 1\n"
            "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 "
            "1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n"
            "EDGE_SE3:QUAT 1 2 0 0 0.5 0 0 0 1 "
            "1 0 0 0 0 0 1 0 0 0 0 4 0 0 0 1 0 0 1 0 1\n");
  // The unknown tag is an error unless skipped on request.
  SlamRun failed = RunCaptured("info " + path3, tmp);
  EXPECT_EQ(failed.code, 1) << failed.all();
  EXPECT_TRUE(Contains(failed.err, "g3.g2o:4: unknown tag 'EQUIV'"))
      << failed.err;
  SlamRun run = RunCaptured("info --skip_unknown_tags " + path3, tmp);
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "nodes: 3  pose3 3  (fixed 0)")) << run.out;
  EXPECT_TRUE(Contains(run.out, "factors: 2 (odometry 2, loop closures 0)"))
      << run.out;
  EXPECT_TRUE(Contains(run.out, "connected components: 1 (largest 3 nodes)"))
      << run.out;
  // Second edge: e_t = (0, 0, 0.5) with weight 4: chi2 1.
  EXPECT_NEAR(NumberAfter(run.out, "initial chi2 (g2o convention): "), 1.0,
              1e-9)
      << run.out;
  EXPECT_TRUE(Contains(run.err, "EQUIV")) << run.err;  // The skipped tag.

  // A file without VERTEX lines: the nodes come from the edges and the
  // guess is built from them, so the chi2 is 0.
  const std::string edges = tmp + "/edges.g2o";
  WriteText(edges,
            "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
            "EDGE_SE2 1 2 1 0 0.5 1 0 0 1 0 1\n"
            "EDGE_SE2 7 8 1 0 0 1 0 0 1 0 1\n");
  run = RunCaptured("info " + edges, tmp);
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "nodes: 5  pose2 5")) << run.out;
  EXPECT_TRUE(Contains(run.out, "initial guess from the edges")) << run.out;
  EXPECT_TRUE(Contains(run.out, "connected components: 2 (largest 3 nodes)"))
      << run.out;
  EXPECT_NEAR(NumberAfter(run.out, "initial chi2 (g2o convention): "), 0.0,
              1e-12)
      << run.out;
}

// On a simulated graph info agrees with what the simulator wrote and with
// the chi2 `slam optimize` starts from.
TEST(InfoCommandTest, AgreesWithSimulateAndOptimize) {
  const std::string tmp = TempDir();
  const std::string dir = tmp + "/sim";
  SlamRun run = RunCaptured("simulate -o " + dir + " --num_poses 200", tmp);
  ASSERT_EQ(run.code, 0) << run.all();
  const double simulated_chi2 =
      NumberAfter(run.out, "chi2 of the initial guess (dead reckoning): ");
  run = RunCaptured("info " + dir + "/graph.g2o", tmp);
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "nodes: 200  pose2 200  (fixed 1)")) << run.out;
  EXPECT_TRUE(Contains(run.out, "(odometry 199, loop closures ")) << run.out;
  EXPECT_TRUE(Contains(run.out, "connected components: 1 (largest 200 nodes)"))
      << run.out;
  const double info_chi2 =
      NumberAfter(run.out, "initial chi2 (g2o convention): ");
  EXPECT_NEAR(info_chi2, simulated_chi2, 1e-6 * simulated_chi2);
  const double factors = NumberAfter(run.out, "factors: ");
  const std::string info_out = run.out;

  run = RunCaptured("optimize --quiet -i " + dir + "/graph.g2o", tmp);
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(
      run.out,
      "200 nodes, " + std::to_string(static_cast<int>(factors)) + " factors"))
      << run.out << info_out;
  EXPECT_NEAR(NumberAfter(run.out, "factors, chi2 "), info_chi2,
              1e-9 * info_chi2);
}

TEST(InfoCommandTest, FailsCleanly) {
  const std::string tmp = TempDir();
  SlamRun run = RunCaptured("info " + tmp + "/nothere.g2o", tmp);
  EXPECT_EQ(run.code, 1);
  EXPECT_TRUE(Contains(run.err, tmp + "/nothere.g2o: cannot open")) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;

  const std::string bad = tmp + "/bad.g2o";
  WriteText(bad,
            "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
            "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n");
  run = RunCaptured("info " + bad, tmp);
  EXPECT_EQ(run.code, 1);
  EXPECT_TRUE(Contains(run.err,
                       bad + ":3: information matrix is not positive definite"))
      << run.err;
  // --repair_information applies to info too.
  run = RunCaptured("info --repair_information " + bad, tmp);
  EXPECT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "repaired information matrices: 1")) << run.out;

  run = RunCaptured("info", tmp);
  EXPECT_EQ(run.code, 2);
  EXPECT_TRUE(Contains(run.err, "usage: slam info FILE")) << run.err;
  run = RunCaptured("info " + bad + " " + bad, tmp);
  EXPECT_EQ(run.code, 2);
  EXPECT_TRUE(Contains(run.err, "usage: slam info FILE")) << run.err;
}

}  // namespace
}  // namespace slam
