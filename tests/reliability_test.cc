// Bad input, faults and odd files (issue 17): each case failed before its
// fix. Readers are called directly; commands through the `slam` binary.
#include <bzlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/yaml_config.h"
#include "datasets/carmen_io.h"
#include "datasets/imu_io.h"
#include "datasets/relations_io.h"
#include "datasets/stereo_vo_io.h"
#include "datasets/trajectory_io.h"
#include "frontends/inertial/inertial_estimator.h"
#include "frontends/laser/scan_matcher.h"
#include "frontends/laser/scan_simulator.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

namespace fs = std::filesystem;
using ::slam::testing::Contains;
using ::slam::testing::ReadText;
using ::slam::testing::TempDir;
using ::slam::testing::WriteText;

using SlamRun = ::slam::testing::CapturedRun;

SlamRun RunIn(const std::string& dir, const std::string& args) {
  return ::slam::testing::RunSlamCaptured(args, dir);
}

// Regular files (recursively) under dir, but the captured stdout/stderr.
std::vector<std::string> OutputFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (!fs::exists(dir)) return files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name != "stdout" && name != "stderr") {
      files.push_back(fs::relative(e.path(), dir).string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// ---------------------------------------------------------------------------
// Configs.

TEST(ReliabilityTest, ConfigThatIsADirectoryIsAnErrorInEveryCommand) {
  const std::string dir = TempDir();
  for (const std::string& command : std::vector<std::string>{
           "run", "optimize -i x.g2o", "eval --ref a --est b", "inertial -i x",
           "simulate -o " + dir + "/sim"}) {
    const SlamRun run = RunIn(dir, command + " --config " + dir);
    // An error (1) or a usage error (2), not an abort (134).
    EXPECT_TRUE(run.code == 1 || run.code == 2)
        << command << ": exit " << run.code << "\n"
        << run.err;
    EXPECT_TRUE(Contains(run.err, dir + ": cannot open: Is a directory"))
        << command << "\n"
        << run.err;
  }
}

TEST(ReliabilityTest, UnreadableOrHugeConfigNamesTheReason) {
  const std::string dir = TempDir();
  YAML::Node root;
  std::string error;
  EXPECT_FALSE(LoadYamlFile(dir + "/c.yaml", &root, &error));
  EXPECT_EQ(error, dir + "/c.yaml: no such file");
  EXPECT_FALSE(LoadYamlFile("/dev/zero", &root, &error));  // Never ends.
  EXPECT_TRUE(Contains(error, "/dev/zero: larger than")) << error;
  // A syntax error names the line.
  WriteText(dir + "/bad.yaml", "run:\n  log: [unclosed\n");
  EXPECT_FALSE(LoadYamlFile(dir + "/bad.yaml", &root, &error));
  EXPECT_TRUE(Contains(error, dir + "/bad.yaml:")) << error;
  EXPECT_FALSE(Contains(error, "bad.yaml:0:")) << error;
}

// Found by fuzz_config: a mapping or a sequence as a key made the loaders
// throw (abort) instead of reporting the line.
TEST(ReliabilityTest, ConfigKeysThatAreNotNamesAreErrors) {
  const std::string dir = TempDir();
  // (config, command reading it).
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{a: 1}: x\n", "simulate -o "},
      {"{a: 1}: x\n", "run --output_dir "},
      {"simulate:\n  [a, b]: 2\n", "simulate -o "},
      {"run:\n  scans:\n    {x: 1}: 2\n", "run --output_dir "}};
  for (const auto& [text, command] : cases) {
    WriteText(dir + "/c.yaml", text);
    const SlamRun run =
        RunIn(dir, command + dir + "/out --config " + dir + "/c.yaml");
    EXPECT_TRUE(run.code == 1 || run.code == 2)
        << text << command << ": exit " << run.code << "\n"
        << run.err;
    EXPECT_TRUE(Contains(run.err, "a key must be a plain name"))
        << text << command << "\n"
        << run.err;
  }
}

// ---------------------------------------------------------------------------
// Trajectory and relation readers: byte order mark, hex floats, escapes.

TEST(ReliabilityTest, TrajectoryReadersSkipAByteOrderMark) {
  const std::string dir = TempDir();
  const std::string bom = "\xEF\xBB\xBF";
  WriteText(dir + "/t.tum", bom + "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n");
  WriteText(dir + "/k.txt", bom + "1 0 0 0 0 1 0 0 0 0 1 0\n");
  WriteText(dir + "/e.csv",
            bom + "#timestamp,x,y,z,qw,qx,qy,qz\n" + "1000,0,0,0,1,0,0,0\n");
  for (const char* name : {"t.tum", "k.txt", "e.csv"}) {
    TrajectoryData data;
    std::string error;
    ASSERT_TRUE(ReadTrajectory(dir + "/" + name, {}, &data, &error))
        << name << ": " << error;
    EXPECT_FALSE(data.poses.empty()) << name;
  }
}

TEST(ReliabilityTest, HexFloatsAreRejected) {
  const std::string dir = TempDir();
  WriteText(dir + "/t.tum", "0x1p3 0 0 0 0 0 0 1\n");
  WriteText(dir + "/v.tum", "1.0 0x1p3 0 0 0 0 0 1\n");
  WriteText(dir + "/e.csv", "1000,0x1p3,0,0,1,0,0,0\n");
  WriteText(dir + "/r.relations", "1.0 0x1p3 0 0 0 0 0 0\n");
  WriteText(dir + "/s.relations", "1.0 2.0 0x1p3 0 0 0 0 0\n");
  Trajectory t;
  std::string error;
  EXPECT_FALSE(ReadTumTrajectory(dir + "/t.tum", &t, &error));
  EXPECT_TRUE(Contains(error, "t.tum:1:")) << error;
  EXPECT_FALSE(ReadTumTrajectory(dir + "/v.tum", &t, &error));
  EXPECT_TRUE(Contains(error, "v.tum:1:")) << error;
  EXPECT_FALSE(ReadEurocTrajectory(dir + "/e.csv", &t, &error));
  EXPECT_TRUE(Contains(error, "e.csv:1:")) << error;
  std::vector<PoseRelation> relations;
  EXPECT_FALSE(ReadRelations(dir + "/r.relations", &relations, &error));
  EXPECT_TRUE(Contains(error, "r.relations:1:")) << error;
  EXPECT_FALSE(ReadRelations(dir + "/s.relations", &relations, &error));
  EXPECT_TRUE(Contains(error, "s.relations:1:")) << error;
}

// Found by fuzz_trajectory (UBSan: signed overflow in the seconds to
// nanoseconds conversion).
TEST(ReliabilityTest, StampsBeyondTheNanosecondRangeAreRejected) {
  TimeNs stamp = 0;
  EXPECT_FALSE(ParseStampSeconds("74480544800", &stamp));
  EXPECT_FALSE(ParseStampSeconds("9223372037", &stamp));
  EXPECT_TRUE(ParseStampSeconds("9000000000.5", &stamp));
  EXPECT_EQ(stamp, 9000000000500000000LL);
}

TEST(ReliabilityTest, ControlBytesOfTheInputAreNotEchoed) {
  const std::string dir = TempDir();
  WriteText(dir + "/t.tum", "1.0 \x1b[31mred\x1b[0m 0 0 0 0 0 1\n");
  WriteText(dir + "/e.csv", "\x1b[2J,0,0,0,1,0,0,0\n");
  Trajectory t;
  std::string error;
  EXPECT_FALSE(ReadTumTrajectory(dir + "/t.tum", &t, &error));
  EXPECT_TRUE(Contains(error, "t.tum:1:")) << error;
  EXPECT_FALSE(Contains(error, "\x1b")) << error;
  EXPECT_FALSE(ReadEurocTrajectory(dir + "/e.csv", &t, &error));
  EXPECT_FALSE(Contains(error, "\x1b")) << error;
  // Through the command too.
  const SlamRun run = RunIn(
      dir, "eval --ref " + dir + "/t.tum --est " + dir + "/t.tum --format tum");
  EXPECT_EQ(run.code, 1);
  EXPECT_FALSE(Contains(run.err, "\x1b")) << run.err;
  // A config value quoted in a message (YAML "\e" is ESC).
  WriteText(dir + "/c.yaml", "optimize:\n  solver: \"\\e[31mred\"\n");
  const SlamRun config =
      RunIn(dir, "optimize -i x.g2o --config " + dir + "/c.yaml");
  EXPECT_NE(config.code, 0);
  EXPECT_TRUE(Contains(config.err, "?[31mred")) << config.err;
  EXPECT_FALSE(Contains(config.err, "\x1b")) << config.err;
}

// ---------------------------------------------------------------------------
// Inputs with nothing to do.

TEST(ReliabilityTest, EmptyInputsAreErrors) {
  const std::string dir = TempDir();
  WriteText(dir + "/empty.g2o", "");
  WriteText(dir + "/comments.g2o", "# nothing\n\n");
  for (const std::string& input :
       {dir + "/empty.g2o", dir + "/comments.g2o", std::string("/dev/null")}) {
    const SlamRun run =
        RunIn(dir, "optimize -i " + input + " -o " + dir + "/out.g2o");
    EXPECT_EQ(run.code, 1) << input << "\n" << run.out << run.err;
    EXPECT_TRUE(Contains(run.err, "no records")) << run.err;
    EXPECT_FALSE(fs::exists(dir + "/out.g2o"));
  }
  // Vertices without a single edge: nothing to optimize.
  WriteText(dir + "/vertices.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n");
  const SlamRun vertices = RunIn(dir, "optimize -i " + dir + "/vertices.g2o");
  EXPECT_EQ(vertices.code, 1) << vertices.out << vertices.err;
  EXPECT_TRUE(Contains(vertices.err, "nothing to optimize")) << vertices.err;
  EXPECT_FALSE(Contains(vertices.out, "-1 iterations")) << vertices.out;
  // Stereo VO: an empty factor file.
  WriteText(dir + "/calib.txt", "700 700 0 600 180 0.5\n");
  WriteText(dir + "/poses.txt", "1 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
  WriteText(dir + "/factors.txt", "");
  Graph graph;
  StereoVoReport report;
  std::string error;
  EXPECT_FALSE(ReadStereoVo(dir + "/factors.txt", dir + "/calib.txt",
                            dir + "/poses.txt", &graph, &report, &error));
  EXPECT_TRUE(Contains(error, "factors.txt: no stereo factors")) << error;
  // GTSAM IMU file with the initial state only.
  WriteText(dir + "/imu.csv", "i,0,0,0,0,0,0,1,0,0,0\n");
  InertialData data;
  EXPECT_FALSE(ReadGtsamImuCsv(dir + "/imu.csv", kGtsamImuDt, &data, &error));
  EXPECT_TRUE(Contains(error, "no IMU rows")) << error;
}

// ---------------------------------------------------------------------------
// Finite but absurd values, named with file and line.

TEST(ReliabilityTest, AbsurdImuValuesAreReportedWithFileAndLine) {
  const std::string dir = TempDir();
  WriteText(dir + "/imu.csv",
            "i,0,0,0,0,0,0,1,0,0,0\n0,0,0,9.81,0,0,0\n"
            "0,9.2e18,0,9.81,0,0,0\n");
  InertialData data;
  std::string error;
  EXPECT_FALSE(ReadGtsamImuCsv(dir + "/imu.csv", kGtsamImuDt, &data, &error));
  EXPECT_TRUE(Contains(error, "imu.csv:3: accelerometer reading '9.2e18'"))
      << error;

  const std::string euroc = dir + "/euroc/mav0/imu0";
  fs::create_directories(euroc);
  WriteText(euroc + "/data.csv",
            "#timestamp,wx,wy,wz,ax,ay,az\n"
            "1000000000,0,0,0,0,0,9.81\n"
            "1005000000,0,0,0,0,0,9.81\n"
            "11005000000,0,0,0,0,0,9.81\n");
  EXPECT_FALSE(ReadEurocInertial(dir + "/euroc", &data, &error));
  EXPECT_TRUE(Contains(error, "data.csv:4: a gap of 10")) << error;
  WriteText(euroc + "/data.csv",
            "#timestamp,wx,wy,wz,ax,ay,az\n"
            "1000000000,0,0,0,0,0,9.81\n"
            "1005000000,0,0,1e9,0,0,9.81\n");
  EXPECT_FALSE(ReadEurocInertial(dir + "/euroc", &data, &error));
  EXPECT_TRUE(Contains(error, "data.csv:3: gyroscope reading '1e9'")) << error;
}

TEST(ReliabilityTest, KeyframesFasterThanTheImuAreRefused) {
  InertialData data;
  for (int k = 0; k < 10; ++k) {
    ImuSample s;
    s.stamp = k * 100000000LL;  // 10 Hz.
    s.accel = Eigen::Vector3d(0, 0, 9.81);
    data.imu.push_back(s);
  }
  KeyframePlan plan;
  std::string error;
  EXPECT_FALSE(PlanKeyframes(data, 50.0, &plan, &error));
  EXPECT_TRUE(Contains(error, "50 Hz is faster than the IMU (10 Hz)")) << error;
  EXPECT_TRUE(PlanKeyframes(data, 5.0, &plan, &error)) << error;
}

TEST(ReliabilityTest, AbsurdCarmenCoordinatesAreReportedWithTheLine) {
  CarmenLog log;
  std::string error;
  EXPECT_FALSE(ParseCarmenLog("mem",
                              "ODOM 0 0 0 0 0 0 1.0 host 1.0\n"
                              "ODOM 9e18 0 0 0 0 0 2.0 host 2.0\n",
                              {}, &log, &error));
  EXPECT_TRUE(Contains(error, "mem:2: coordinate '9e18'")) << error;
}

// ---------------------------------------------------------------------------
// bzip2: streamed, bounded.

std::string Bzip2(const std::string& text) {
  std::string out(text.size() + text.size() / 100 + 600, '\0');
  unsigned int size = static_cast<unsigned int>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(
                out.data(), &size, const_cast<char*>(text.data()),
                static_cast<unsigned int>(text.size()), 9, 0, 0),
            BZ_OK);
  out.resize(size);
  return out;
}

TEST(ReliabilityTest, Bzip2BombIsStoppedWithBoundedMemory) {
  const std::string dir = TempDir();
  // 64 MB of newlines: about 100 KB compressed.
  WriteText(dir + "/lines.clf.bz2", Bzip2(std::string(64 << 20, '\n')));
  CarmenReadOptions options;
  options.max_log_bytes = 16 << 20;
  CarmenLog log;
  std::string error;
  EXPECT_FALSE(ReadCarmenLog(dir + "/lines.clf.bz2", options, &log, &error));
  EXPECT_TRUE(Contains(error, "decompresses to more than 16777216 bytes"))
      << error;
  // One endless line.
  WriteText(dir + "/line.clf.bz2", Bzip2(std::string(8 << 20, 'A')));
  options.max_line_bytes = 1 << 20;
  EXPECT_FALSE(ReadCarmenLog(dir + "/line.clf.bz2", options, &log, &error));
  EXPECT_TRUE(Contains(error, "line.clf.bz2:1: a line longer than 1048576"))
      << error;
}

TEST(ReliabilityTest, StreamedBzip2ReadsAsThePlainText) {
  // Several decompression pieces; an error far down names its exact line.
  std::string text;
  for (int k = 0; k < 40000; ++k) {
    text += "ODOM " + std::to_string(k * 0.01) + " 0 0 0 0 0 " +
            std::to_string(100 + k) + ".5 host 0\n";
  }
  const std::string dir = TempDir();
  WriteText(dir + "/log.clf", text);
  WriteText(dir + "/log.clf.bz2", Bzip2(text));
  CarmenLog plain, packed;
  std::string error;
  ASSERT_TRUE(ReadCarmenLog(dir + "/log.clf", {}, &plain, &error)) << error;
  ASSERT_TRUE(ReadCarmenLog(dir + "/log.clf.bz2", {}, &packed, &error))
      << error;
  ASSERT_EQ(packed.odometry.size(), 40000u);
  for (size_t i = 0; i < plain.odometry.size(); ++i) {
    ASSERT_EQ(packed.odometry[i].stamp, plain.odometry[i].stamp);
    ASSERT_EQ(packed.odometry[i].pose.t, plain.odometry[i].pose.t);
  }
  WriteText(dir + "/bad.clf.bz2", Bzip2(text + "ODOM 1 2\n"));
  EXPECT_FALSE(ReadCarmenLog(dir + "/bad.clf.bz2", {}, &packed, &error));
  EXPECT_TRUE(Contains(error, "bad.clf.bz2:40001:")) << error;
}

// ---------------------------------------------------------------------------
// Laser: cells of negative and absurd coordinates (UBSan: no negative shift,
// no out-of-range float-to-int conversion).

TEST(ReliabilityTest, VoxelFilterHandlesNegativeAndAbsurdCoordinates) {
  const Points2 points = {{-0.75, -0.25}, {-0.25, -0.75},  {0.5, 0.5},
                          {-0.5, 0.5},    {1e300, -1e300}, {1e300, -1e300}};
  const Points2 voxels = VoxelFilter(points, 1.0);
  // (-1, -1) holds two points, (0, 0), (-1, 0) and the far cell one each.
  ASSERT_EQ(voxels.size(), 4u);
  EXPECT_TRUE(voxels[0].isApprox(Eigen::Vector2d(-0.5, -0.5)));
  EXPECT_EQ(voxels[3], Eigen::Vector2d(1e300, -1e300));
}

// ---------------------------------------------------------------------------
// slam run: outputs never left by a failure; a log whose stamps go
// backwards.

// A handmade CARMEN log: the robot drives along x in a 10 m x 6 m room,
// one FLASER scan per 0.1 m. `stamps` gives each scan's stamp (seconds).
std::string RoomLog(const std::vector<double>& stamps) {
  const std::vector<Wall> walls = RectangleWalls(-2, -3, 8, 3);
  ScanGeometry g;
  g.max_range = 20.0;
  std::string log = "PARAM robot_front_laser_max 20 nohost 0\n";
  for (size_t i = 0; i < stamps.size(); ++i) {
    const Pose2 pose(0.1 * static_cast<double>(i), 0.0, 0.0);
    const std::vector<float> ranges =
        SimulateScan(walls, pose, g, 0.0, nullptr);
    char stamp[64];
    std::snprintf(stamp, sizeof(stamp), "%.6f", stamps[i]);
    std::string line = "FLASER 181";
    for (float r : ranges) line += " " + std::to_string(r);
    for (int k = 0; k < 2; ++k) {
      line += " " + std::to_string(pose.t.x()) + " 0 0";
    }
    log += line + " " + stamp + " host " + stamp + "\n";
  }
  return log;
}

std::string RunConfig(const std::string& dir, const std::string& extra) {
  const std::string path = dir + "/run.yaml";
  WriteText(path, "run:\n  log: " + dir + "/room.clf\n  output_dir: " + dir +
                      "/out\n" + extra);
  return path;
}

std::vector<double> Stamps(int n) {
  std::vector<double> stamps;
  for (int i = 0; i < n; ++i) stamps.push_back(100.0 + 0.1 * i);
  return stamps;
}

TEST(ReliabilityTest, RunWithRelationsOfAnotherLogFailsBeforeAnyOutput) {
  const std::string dir = TempDir();
  WriteText(dir + "/room.clf", RoomLog(Stamps(30)));
  WriteText(dir + "/other.relations", "5000.0 5001.0 1 0 0 0 0 0\n");
  const SlamRun run = RunIn(
      dir, "run --config " +
               RunConfig(dir, "  relations: " + dir + "/other.relations\n"));
  EXPECT_EQ(run.code, 1) << run.out << run.err;
  EXPECT_TRUE(Contains(run.err, "none of the 1 relations")) << run.err;
  EXPECT_EQ(OutputFiles(dir + "/out"), std::vector<std::string>{});
}

TEST(ReliabilityTest, RunWithAMapTooFineForOneScanFailsBeforeTheWork) {
  const std::string dir = TempDir();
  WriteText(dir + "/room.clf", RoomLog(Stamps(30)));
  const SlamRun run = RunIn(
      dir, "run --config " + RunConfig(dir, "  map:\n    resolution: 1e-5\n"));
  EXPECT_EQ(run.code, 1) << run.out << run.err;
  EXPECT_TRUE(Contains(run.err, "resolution 1e-05 m is too fine")) << run.err;
  EXPECT_FALSE(Contains(run.err, "processing")) << run.err;
  EXPECT_EQ(OutputFiles(dir + "/out"), std::vector<std::string>{});
}

TEST(ReliabilityTest, RunFailingAfterTheWorkLeavesNoOutput) {
  const std::string dir = TempDir();
  WriteText(dir + "/room.clf", RoomLog(Stamps(30)));
  fs::create_directories(dir + "/out/map.png");     // The last output fails.
  WriteText(dir + "/out/trajectory.tum", "old\n");  // Must stay as it is.
  const SlamRun run = RunIn(dir, "run --config " + RunConfig(dir, ""));
  EXPECT_EQ(run.code, 1) << run.out << run.err;
  EXPECT_TRUE(Contains(run.err, "map.png: is a directory")) << run.err;
  EXPECT_EQ(OutputFiles(dir + "/out"),
            std::vector<std::string>{"trajectory.tum"});
  EXPECT_EQ(ReadText(dir + "/out/trajectory.tum"), "old\n");
}

TEST(ReliabilityTest,
     RunOnALogWithStampsGoingBackwardsWritesASortedTrajectory) {
  std::vector<double> stamps = Stamps(40);
  std::swap(stamps[10], stamps[11]);  // Backwards once.
  stamps[21] = stamps[20];            // A duplicate.
  stamps[30] = stamps[29] - 0.05;     // Backwards again.
  const std::string dir = TempDir();
  WriteText(dir + "/room.clf", RoomLog(stamps));
  const SlamRun run = RunIn(dir, "run --config " + RunConfig(dir, ""));
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  EXPECT_TRUE(Contains(run.err,
                       "3 of 40 laser scans have a stamp not after "
                       "the previous scan's (first at line 13)"))
      << run.err;
  EXPECT_TRUE(Contains(run.out, "trajectory.tum is sorted by stamp, 1 scan(s)"))
      << run.out;
  Trajectory trajectory;
  std::string error;
  ASSERT_TRUE(
      ReadTumTrajectory(dir + "/out/trajectory.tum", &trajectory, &error))
      << error;
  EXPECT_EQ(trajectory.size(), 39u);
  // Usable by the evaluation: relations between scans along the way.
  WriteText(dir + "/room.relations",
            "100.000000 100.500000 0.5 0 0 0 0 0\n"
            "101.500000 102.000000 0.5 0 0 0 0 0\n");
  const SlamRun eval =
      RunIn(dir, "eval --relations " + dir + "/room.relations " + dir +
                     "/out/trajectory.tum");
  EXPECT_EQ(eval.code, 0) << eval.out << eval.err;
}

// ---------------------------------------------------------------------------
// optimize and eval: a report that cannot be written leaves no output.

TEST(ReliabilityTest, OptimizeWithAnUnwritableReportLeavesNoGraph) {
  const std::string dir = TempDir();
  WriteText(dir + "/g.g2o",
            "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
            "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  fs::create_directories(dir + "/report.json");  // A directory.
  const SlamRun run =
      RunIn(dir, "optimize -i " + dir + "/g.g2o -o " + dir +
                     "/out.g2o --report " + dir + "/report.json");
  EXPECT_EQ(run.code, 1) << run.out << run.err;
  EXPECT_FALSE(fs::exists(dir + "/out.g2o"));
  EXPECT_EQ(OutputFiles(dir), std::vector<std::string>{"g.g2o"});
}

TEST(ReliabilityTest, EvalWithAnUnwritableReportLeavesNoPlots) {
  const std::string dir = TempDir();
  std::string tum;
  for (int k = 0; k < 20; ++k) {
    tum +=
        std::to_string(k) + ".0 " + std::to_string(0.1 * k) + " 0 0 0 0 0 1\n";
  }
  WriteText(dir + "/a.tum", tum);
  fs::create_directories(dir + "/report.json");
  const SlamRun run = RunIn(dir, "eval --ref " + dir + "/a.tum --est " + dir +
                                     "/a.tum --plot " + dir +
                                     "/plots --report " + dir + "/report.json");
  EXPECT_EQ(run.code, 1) << run.out << run.err;
  EXPECT_EQ(OutputFiles(dir + "/plots"), std::vector<std::string>{});
}

}  // namespace
}  // namespace slam
