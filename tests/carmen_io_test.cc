// CARMEN log reader/writer: a handmade log (plain and bzip2-compressed in the
// test), the laser geometry rules, a write/read round trip, bad input and the
// real ACES log.
#include "datasets/carmen_io.h"

#include <bzlib.h>

#include <cmath>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::FixturePath;
using testing::ReadText;
using testing::TempDir;
using testing::WriteText;

constexpr double kDeg = M_PI / 180.0;

CarmenReadOptions AllLasers() {
  CarmenReadOptions options;
  options.front_laser = true;
  options.rear_laser = true;
  options.robot_laser = true;
  return options;
}

std::string Bzip2(const std::string& text) {
  std::vector<char> out(text.size() + text.size() / 50 + 1024);
  unsigned int out_size = static_cast<unsigned int>(out.size());
  const int status = BZ2_bzBuffToBuffCompress(
      out.data(), &out_size, const_cast<char*>(text.data()),
      static_cast<unsigned int>(text.size()), 9, 0, 0);
  EXPECT_EQ(status, BZ_OK);
  return std::string(out.data(), out_size);
}

void ExpectPose(const Pose2& p, double x, double y, double theta) {
  EXPECT_NEAR(p.t.x(), x, 1e-12);
  EXPECT_NEAR(p.t.y(), y, 1e-12);
  EXPECT_NEAR(p.theta, theta, 1e-12);
}

void ExpectSameLog(const CarmenLog& a, const CarmenLog& b) {
  ASSERT_EQ(a.odometry.size(), b.odometry.size());
  ASSERT_EQ(a.scans.size(), b.scans.size());
  EXPECT_EQ(a.params, b.params);
  for (size_t i = 0; i < a.odometry.size(); ++i) {
    EXPECT_EQ(a.odometry[i].stamp, b.odometry[i].stamp);
    EXPECT_EQ(a.odometry[i].pose.t, b.odometry[i].pose.t);
    EXPECT_EQ(a.odometry[i].pose.theta, b.odometry[i].pose.theta);
    EXPECT_EQ(a.odometry[i].tv, b.odometry[i].tv);
    EXPECT_EQ(a.odometry[i].rv, b.odometry[i].rv);
  }
  for (size_t i = 0; i < a.scans.size(); ++i) {
    const LaserScan& s = a.scans[i];
    const LaserScan& t = b.scans[i];
    EXPECT_EQ(s.tag, t.tag);
    EXPECT_EQ(s.stamp, t.stamp);
    EXPECT_EQ(s.ranges, t.ranges);
    EXPECT_EQ(s.odom.t, t.odom.t);
    EXPECT_EQ(s.odom.theta, t.odom.theta);
    EXPECT_EQ(s.logged_pose.t, t.logged_pose.t);
    EXPECT_EQ(s.logged_pose.theta, t.logged_pose.theta);
    EXPECT_NEAR(s.laser_offset.t.x(), t.laser_offset.t.x(), 1e-12);
    EXPECT_NEAR(s.laser_offset.t.y(), t.laser_offset.t.y(), 1e-12);
    EXPECT_NEAR(s.laser_offset.theta, t.laser_offset.theta, 1e-12);
    EXPECT_EQ(s.angle_min, t.angle_min);
    EXPECT_NEAR(s.angle_increment, t.angle_increment, 1e-15);
    EXPECT_EQ(s.max_range, t.max_range);
  }
}

TEST(CarmenIo, ReadsHandmadeLog) {
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(
      ReadCarmenLog(FixturePath("carmen_small.clf"), AllLasers(), &log, &error))
      << error;
  ASSERT_EQ(log.odometry.size(), 3u);
  ASSERT_EQ(log.scans.size(), 3u);
  EXPECT_EQ(log.params.at("robot_frontlaser_offset"), "0.25");
  EXPECT_EQ(log.params.size(), 3u);

  // Stamps are read exactly from the decimal text.
  EXPECT_EQ(log.odometry[0].stamp, 10000001000);
  EXPECT_EQ(log.odometry[2].stamp, 10400000123);
  ExpectPose(log.odometry[1].pose, 0.5, 0.1, 0.1);
  EXPECT_DOUBLE_EQ(log.odometry[1].tv, 0.3);
  EXPECT_DOUBLE_EQ(log.odometry[1].rv, 0.05);

  const LaserScan& front = log.scans[0];
  EXPECT_EQ(front.tag, "FLASER");
  EXPECT_EQ(front.line, 8);
  EXPECT_EQ(front.stamp, 10100000000);
  EXPECT_EQ(front.ranges, (std::vector<float>{1.0f, 2.0f, 3.5f, 8.5f, 0.25f}));
  ExpectPose(front.logged_pose, 0.1, 0.2, 0.05);
  ExpectPose(front.odom, 0.0, 0.0, 0.0);
  ExpectPose(front.laser_offset, 0.25, 0.0, 0.0);
  // 5 readings over the default 180 deg: -90, -45, ..., 90 deg.
  EXPECT_DOUBLE_EQ(front.angle_min, -M_PI / 2);
  EXPECT_DOUBLE_EQ(front.angle_increment, M_PI / 4);
  EXPECT_DOUBLE_EQ(front.max_range, 8.5);  // PARAM robot_front_laser_max.

  const LaserScan& rear = log.scans[1];
  EXPECT_EQ(rear.tag, "RLASER");
  ExpectPose(rear.laser_offset, -0.1, 0.0, -M_PI);  // Looks backwards.
  ExpectPose(rear.odom, 0.5, 0.1, 0.1);
  EXPECT_DOUBLE_EQ(rear.max_range, CarmenReadOptions().default_max_range);

  const LaserScan& robot = log.scans[2];
  EXPECT_EQ(robot.tag, "ROBOTLASER1");
  EXPECT_EQ(robot.ranges.size(), 5u);
  EXPECT_FLOAT_EQ(robot.ranges[4], 5.5f);
  EXPECT_DOUBLE_EQ(robot.angle_min, -1.5707963);
  EXPECT_DOUBLE_EQ(robot.angle_increment, 0.7853982);
  EXPECT_DOUBLE_EQ(robot.max_range, 20.0);
  ExpectPose(robot.odom, 1.0, 0.2, 0.2);
  ExpectPose(robot.logged_pose, 1.2, 0.3, 0.2);
  // Laser in the robot frame: R(-0.2) * (0.2, 0.1).
  ExpectPose(robot.laser_offset, std::cos(0.2) * 0.2 + std::sin(0.2) * 0.1,
             -std::sin(0.2) * 0.2 + std::cos(0.2) * 0.1, 0.0);

  // One warning per skipped tag, with the count.
  ASSERT_EQ(log.warnings.size(), 2u);
  EXPECT_TRUE(Contains(log.warnings[0], "skipped 2 SYNC line(s)"))
      << log.warnings[0];
  EXPECT_TRUE(Contains(log.warnings[1], "skipped 1 TRUEPOS line(s)"))
      << log.warnings[1];
}

TEST(CarmenIo, OptionsSelectTheLasers) {
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(ReadCarmenLog(FixturePath("carmen_small.clf"),
                            CarmenReadOptions(), &log, &error))
      << error;
  ASSERT_EQ(log.scans.size(), 2u);  // Rear laser off by default.
  EXPECT_EQ(log.scans[0].tag, "FLASER");
  EXPECT_EQ(log.scans[1].tag, "ROBOTLASER1");
  CarmenReadOptions rear_only;
  rear_only.front_laser = false;
  rear_only.rear_laser = true;
  rear_only.robot_laser = false;
  ASSERT_TRUE(
      ReadCarmenLog(FixturePath("carmen_small.clf"), rear_only, &log, &error));
  ASSERT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.scans[0].tag, "RLASER");
  EXPECT_EQ(log.odometry.size(), 3u);
}

// The FLASER angle rule by number of readings, and the PARAM overrides.
TEST(CarmenIo, FlaserGeometry) {
  auto flaser = [](int n) {
    std::string line = "FLASER " + std::to_string(n);
    for (int i = 0; i < n; ++i) line += " 1.5";
    return line + " 0 0 0 0 0 0 1.0 host 0\n";
  };
  struct Case {
    std::string params;
    int n;
    double angle_min;
    double increment;
  };
  const std::vector<Case> cases = {
      {"", 180, -90 * kDeg, 1 * kDeg},
      {"", 181, -90 * kDeg, 1 * kDeg},
      {"", 361, -90 * kDeg, 0.5 * kDeg},
      {"", 401, -90 * kDeg, 0.25 * kDeg},
      {"", 91, -90 * kDeg, 2 * kDeg},
      {"PARAM laser_front_laser_resolution 0.5 nohost 0\n", 181, -90 * kDeg,
       0.5 * kDeg},
      {"PARAM laser_front_laser_fov 100 nohost 0\n", 101, -50 * kDeg, 1 * kDeg},
  };
  for (const Case& c : cases) {
    CarmenLog log;
    std::string error;
    ASSERT_TRUE(ParseCarmenLog("mem", c.params + flaser(c.n),
                               CarmenReadOptions(), &log, &error))
        << error;
    ASSERT_EQ(log.scans.size(), 1u);
    EXPECT_EQ(log.scans[0].ranges.size(), static_cast<size_t>(c.n));
    EXPECT_NEAR(log.scans[0].angle_min, c.angle_min, 1e-12) << c.n;
    EXPECT_NEAR(log.scans[0].angle_increment, c.increment, 1e-12) << c.n;
  }
}

TEST(CarmenIo, Bzip2DetectedByContent) {
  const std::string plain = ReadText(FixturePath("carmen_small.clf"));
  const std::string dir = TempDir();
  // No .bz2 in the name: the magic decides. Two concatenated streams (as
  // pbzip2 writes them) give the log twice.
  const std::string path = dir + "/log.clf";
  WriteText(path, Bzip2(plain) + Bzip2(plain));
  CarmenLog expected;
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(
      ParseCarmenLog("mem", plain + plain, AllLasers(), &expected, &error))
      << error;
  std::vector<double> fractions;
  ASSERT_TRUE(ReadCarmenLog(path, AllLasers(), &log, &error, [&](double f) {
    fractions.push_back(f);
  })) << error;
  ExpectSameLog(log, expected);
  EXPECT_EQ(log.scans.size(), 6u);
  // Line numbers count lines of the decompressed text.
  EXPECT_EQ(log.scans[3].line, expected.scans[3].line);
  ASSERT_GE(fractions.size(), 2u);
  for (size_t i = 1; i < fractions.size(); ++i) {
    EXPECT_GE(fractions[i], fractions[i - 1]);
  }
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);

  // A truncated compressed file is an error, not a partial log.
  const std::string compressed = Bzip2(plain);
  WriteText(path, compressed.substr(0, compressed.size() / 2));
  EXPECT_FALSE(ReadCarmenLog(path, AllLasers(), &log, &error));
  EXPECT_TRUE(Contains(error, path + ": corrupt or truncated bzip2")) << error;
  EXPECT_TRUE(log.scans.empty());
  EXPECT_TRUE(log.odometry.empty());
}

TEST(CarmenIo, RoundTrip) {
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(
      ReadCarmenLog(FixturePath("carmen_small.clf"), AllLasers(), &log, &error))
      << error;
  const std::string path = TempDir() + "/out.clf";
  ASSERT_TRUE(WriteCarmenLog(path, log, &error)) << error;
  CarmenLog back;
  ASSERT_TRUE(ReadCarmenLog(path, AllLasers(), &back, &error)) << error;
  ExpectSameLog(log, back);
  EXPECT_TRUE(back.warnings.empty());

  // A scan with an unknown tag is refused; the old file stays.
  log.scans[0].tag = "LASER9";
  EXPECT_FALSE(WriteCarmenLog(path, log, &error));
  EXPECT_TRUE(Contains(error, "unknown tag 'LASER9'")) << error;
  ASSERT_TRUE(ReadCarmenLog(path, AllLasers(), &back, &error)) << error;
  EXPECT_EQ(back.scans.size(), 3u);
}

TEST(CarmenIo, BadInput) {
  const std::string good_flaser = "FLASER 2 1 2 0 0 0 0 0 0 1.0 host 0";
  const std::string good_robot =
      "ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 0 0 0 0 0 0 0 0 0 0 0 1.0 "
      "host 0";
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"ODOM 1 2 3 4 5 6 1.0 host\n", "mem:1: ODOM needs 9 fields"},
      {"ODOM 1 2 x 4 5 6 1.0 host 0\n", "mem:1: bad number 'x'"},
      {"PARAM a b\nODOM 1 2 nan 4 5 6 1.0 host 0\n", "mem:2: non-finite"},
      {"ODOM 1 2 3 4 5 6 abc host 0\n", "mem:1: bad ipc_timestamp 'abc'"},
      {"FLASER 3 1 2 0 0 0 0 0 0 1.0 host 0\n",
       "mem:1: FLASER needs 13 fields after the tag, found 12"},
      {"FLASER -2 1 2 0 0 0 0 0 0 1.0 host 0\n",
       "mem:1: bad number of readings '-2'"},
      {"FLASER\n", "mem:1: FLASER needs at least 1 field"},
      {"FLASER 2 1 -2 0 0 0 0 0 0 1.0 host 0\n", "mem:1: negative range '-2'"},
      {"FLASER 2 1 inf 0 0 0 0 0 0 1.0 host 0\n", "mem:1: non-finite"},
      {good_flaser + "\n" + good_flaser + " 7\n", "mem:2: FLASER needs 12"},
      {"ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2 3 0 0 0 0 0 0 0 0 0 0 0 1.0 "
       "host 0\n",
       "mem:1: ROBOTLASER1 needs 26 fields after the tag, found 25"},
      {"ROBOTLASER1 0 -1.5 3 1.5 20 0.01 0 3 1 2\n",
       "mem:1: ROBOTLASER1 needs at least 12 field(s)"},
      {"ROBOTLASER1 0 -1.5 3 1.5 -1 0.01 0 3 1 2 3 0 0 0 0 0 0 0 0 0 0 0 0 "
       "1.0 host 0\n",
       "mem:1: ROBOTLASER1 max_range must be positive"},
      {"PARAM robot_frontlaser_offset abc nohost 0\n",
       "mem:1: PARAM robot_frontlaser_offset: expected a number"},
      {"PARAM laser_front_laser_resolution 0 nohost 0\n",
       "mem:1: PARAM laser_front_laser_resolution: expected a positive"},
      {"PARAM x\n", "mem:1: PARAM needs at least 2 field(s)"},
  };
  for (const Case& c : cases) {
    CarmenLog log;
    std::string error;
    EXPECT_FALSE(ParseCarmenLog("mem", c.text, AllLasers(), &log, &error))
        << c.text;
    EXPECT_TRUE(Contains(error, c.message)) << c.text << " -> " << error;
    EXPECT_TRUE(log.scans.empty() && log.odometry.empty() &&
                log.params.empty());
  }
  // The good lines used above are accepted.
  CarmenLog log;
  std::string error;
  EXPECT_TRUE(ParseCarmenLog("mem", good_flaser + "\n" + good_robot + "\n",
                             AllLasers(), &log, &error))
      << error;
  EXPECT_EQ(log.scans.size(), 2u);

  EXPECT_FALSE(
      ReadCarmenLog("/nonexistent/log.clf", AllLasers(), &log, &error));
  EXPECT_TRUE(Contains(error, "/nonexistent/log.clf: cannot open")) << error;
}

TEST(CarmenIo, AcesLog) {
  const std::string path =
      testing::DatasetPath("laser_logs_carmen/aces.clf.bz2");
  SLAM_REQUIRE_DATASET(path);
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(ReadCarmenLog(path, CarmenReadOptions(), &log, &error)) << error;
  EXPECT_EQ(log.scans.size(), 7374u);
  EXPECT_EQ(log.odometry.size(), 7375u);
  EXPECT_EQ(log.params.size(), 4u);
  EXPECT_TRUE(log.warnings.empty());
  for (size_t i = 0; i < log.scans.size(); ++i) {
    const LaserScan& s = log.scans[i];
    ASSERT_EQ(s.tag, "FLASER");
    ASSERT_EQ(s.ranges.size(), 180u);
    ASSERT_DOUBLE_EQ(s.angle_increment, kDeg);
    ASSERT_DOUBLE_EQ(s.angle_min, -M_PI / 2);
    if (i > 0) {
      ASSERT_GT(s.stamp, log.scans[i - 1].stamp) << s.line;
    }
  }
  // The first line with a message is ODOM ... 70.179699 nohost 0.000000.
  EXPECT_GT(log.scans[0].stamp, log.odometry[0].stamp);
  EXPECT_EQ(log.odometry[0].stamp, 70179699000);
  // The 1366 s of data the issue speaks of.
  const double span =
      NsToSeconds(log.scans.back().stamp - log.scans.front().stamp);
  EXPECT_GT(span, 1300.0);
  EXPECT_LT(span, 1400.0);

  // The whole log through the writer and back.
  const std::string copy = TempDir() + "/aces.clf";
  ASSERT_TRUE(WriteCarmenLog(copy, log, &error)) << error;
  CarmenLog back;
  ASSERT_TRUE(ReadCarmenLog(copy, CarmenReadOptions(), &back, &error)) << error;
  ExpectSameLog(log, back);
}

}  // namespace
}  // namespace slam
