// The relation-based error of Kuemmerle et al. 2009: the .relations reader
// and writer, the metric on handmade cases with a known answer (planar and
// 3D, stamp matching, interpolation) and `slam eval --relations`.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/metrics/relation_error.h"
#include "datasets/relations_io.h"
#include "datasets/trajectory_io.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::ReadText;
using testing::RunSlam;
using testing::TempDir;
using testing::WriteText;

constexpr double kDeg = M_PI / 180.0;

Pose3 PoseXyzRpy(double x, double y, double z, double roll, double pitch,
                 double yaw) {
  return Pose3(
      Eigen::Vector3d(x, y, z),
      Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX())));
}

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return RotationAngle(a.conjugate() * b);
}

TEST(Relations, ReadsTheFormat) {
  const std::string path = TempDir() + "/r.relations";
  WriteText(path,
            "# t1 t2 x y z roll pitch yaw\n"
            "90.239599 90.719599 0.422330 -0.000750 0.000000 0.000000 "
            "0.000000 0.017260\n"
            "\n"
            "1.5 2.000000001 1 2 3 0.1 -0.2 0.3\n");
  std::vector<PoseRelation> relations;
  std::vector<int> lines;
  std::string error;
  ASSERT_TRUE(ReadRelations(path, &relations, &error, &lines)) << error;
  ASSERT_EQ(relations.size(), 2u);
  EXPECT_EQ(lines, (std::vector<int>{2, 4}));
  EXPECT_EQ(relations[0].t1, 90239599000);
  EXPECT_EQ(relations[0].t2, 90719599000);
  EXPECT_EQ(relations[1].t2, 2000000001);
  EXPECT_DOUBLE_EQ(relations[0].delta.t.x(), 0.42233);
  EXPECT_DOUBLE_EQ(relations[0].delta.t.y(), -0.00075);
  // A planar relation: a rotation about z by yaw.
  EXPECT_NEAR(AngleBetween(relations[0].delta.q,
                           Eigen::Quaterniond(Eigen::AngleAxisd(
                               0.01726, Eigen::Vector3d::UnitZ()))),
              0.0, 1e-15);
  // R = Rz(yaw) Ry(pitch) Rx(roll): the body x axis after roll, pitch, yaw.
  const Eigen::Vector3d x_axis =
      relations[1].delta.q * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x_axis.x(), std::cos(0.3) * std::cos(-0.2), 1e-15);
  EXPECT_NEAR(x_axis.y(), std::sin(0.3) * std::cos(-0.2), 1e-15);
  EXPECT_NEAR(x_axis.z(), -std::sin(-0.2), 1e-15);
  EXPECT_EQ(relations[1].delta.t, Eigen::Vector3d(1, 2, 3));
}

TEST(Relations, RoundTrip) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<PoseRelation> relations;
  for (int i = 0; i < 50; ++i) {
    PoseRelation r;
    r.t1 = 1000000000ll * i + 123456789;
    r.t2 = r.t1 + 500000001;
    r.delta = PoseXyzRpy(u(rng), u(rng), u(rng), u(rng), 0.5 * u(rng), u(rng));
    relations.push_back(r);
  }
  const std::string path = TempDir() + "/out.relations";
  std::string error;
  ASSERT_TRUE(WriteRelations(path, relations, &error)) << error;
  std::vector<PoseRelation> back;
  ASSERT_TRUE(ReadRelations(path, &back, &error)) << error;
  ASSERT_EQ(back.size(), relations.size());
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].t1, relations[i].t1);
    EXPECT_EQ(back[i].t2, relations[i].t2);
    EXPECT_EQ(back[i].delta.t, relations[i].delta.t);
    EXPECT_LT(AngleBetween(back[i].delta.q, relations[i].delta.q), 1e-14);
  }
}

TEST(Relations, BadInput) {
  const std::string dir = TempDir();
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"1 2 0 0 0 0 0\n", ":1: expected 8 fields"},
      {"1 2 0 0 0 0 0 0\n1 2 0 0 0 0 0 0 9\n", ":2: expected 8 fields"},
      {"1 2 0 0 x 0 0 0\n", ":1: bad or non-finite number 'x' in field 5"},
      {"1 2 0 0 0 nan 0 0\n", ":1: bad or non-finite number 'nan'"},
      {"1 2s 0 0 0 0 0 0\n", ":1: bad timestamp '2s' in field 2"},
      {"# nothing\n", ": no relations"},
  };
  for (const Case& c : cases) {
    const std::string path = dir + "/bad.relations";
    WriteText(path, c.text);
    std::vector<PoseRelation> relations;
    std::string error;
    EXPECT_FALSE(ReadRelations(path, &relations, &error)) << c.text;
    EXPECT_EQ(error.rfind(path, 0), 0u) << error;
    EXPECT_TRUE(Contains(error, c.message)) << c.text << " -> " << error;
    EXPECT_TRUE(relations.empty());
  }
}

// Relation k links the poses at 2k and 2k + 1 s; the estimate is built so
// that delta*^-1 delta_est = errors[k] exactly, hence trans = |t(errors[k])|
// and rot = angle(errors[k]).
void BuildKnownCase(bool planar, Trajectory* est,
                    std::vector<PoseRelation>* relations) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double d[4] = {0.1, 0.2, 0.3, 0.4};  // m
  const double a[4] = {1.0, 2.0, 3.0, 4.0};  // deg
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d axis =
        planar ? Eigen::Vector3d::UnitZ()
               : Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Vector3d dir =
        planar ? Eigen::Vector3d(std::cos(k), std::sin(k), 0.0)
               : Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Pose3 error(d[k] * dir,
                      Eigen::Quaterniond(Eigen::AngleAxisd(a[k] * kDeg, axis)));
    const Pose3 x1 =
        planar ? PoseXyzRpy(u(rng), u(rng), 0, 0, 0, u(rng))
               : PoseXyzRpy(u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    PoseRelation r;
    r.t1 = SecondsToNs(2.0 * k);
    r.t2 = SecondsToNs(2.0 * k + 1.0);
    r.delta = planar
                  ? PoseXyzRpy(u(rng), u(rng), 0, 0, 0, u(rng))
                  : PoseXyzRpy(u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    relations->push_back(r);
    est->push_back({r.t1, x1});
    est->push_back({r.t2, x1 * r.delta * error});
  }
}

void ExpectKnownAnswer(const RelationErrorResult& r) {
  ASSERT_EQ(r.used.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(r.translation[k], 0.1 * (k + 1), 1e-12);
    EXPECT_NEAR(r.rotation_deg[k], 1.0 * (k + 1), 1e-9);
  }
  // |trans| = 0.1 .. 0.4: mean 0.25, sample std sqrt(0.05 / 3).
  EXPECT_NEAR(r.translation_abs.mean, 0.25, 1e-12);
  EXPECT_NEAR(r.translation_abs.std, std::sqrt(0.05 / 3.0), 1e-12);
  // trans^2 = 0.01, 0.04, 0.09, 0.16: mean 0.075, squared deviations
  // 0.0042250, 0.0012250, 0.0002250, 0.0072250 (sum 0.0129).
  EXPECT_NEAR(r.translation_sq.mean, 0.075, 1e-12);
  EXPECT_NEAR(r.translation_sq.std, std::sqrt(0.0129 / 3.0), 1e-12);
  // |rot| = 1 .. 4 deg: mean 2.5, std sqrt(5 / 3); rot^2 = 1, 4, 9, 16:
  // mean 7.5, squared deviations 42.25, 12.25, 2.25, 72.25 (sum 129).
  EXPECT_NEAR(r.rotation_abs.mean, 2.5, 1e-9);
  EXPECT_NEAR(r.rotation_abs.std, std::sqrt(5.0 / 3.0), 1e-9);
  EXPECT_NEAR(r.rotation_sq.mean, 7.5, 1e-8);
  EXPECT_NEAR(r.rotation_sq.std, std::sqrt(129.0 / 3.0), 1e-8);
}

TEST(Relations, KnownAnswerPlanar) {
  Trajectory est;
  std::vector<PoseRelation> relations;
  BuildKnownCase(true, &est, &relations);
  RelationErrorResult r;
  std::string error;
  ASSERT_TRUE(ComputeRelationError(est, relations, {}, &r, &error)) << error;
  EXPECT_EQ(r.relations, 4u);
  EXPECT_EQ(r.unmatched, 0u);
  EXPECT_EQ(r.interpolated, 0u);
  ExpectKnownAnswer(r);
}

TEST(Relations, KnownAnswer3d) {
  Trajectory est;
  std::vector<PoseRelation> relations;
  BuildKnownCase(false, &est, &relations);
  RelationErrorResult r;
  std::string error;
  ASSERT_TRUE(ComputeRelationError(est, relations, {}, &r, &error)) << error;
  ExpectKnownAnswer(r);
}

TEST(Relations, StampMatchingAndInterpolation) {
  // Poses at 0, 1, ..., 10 s moving 1 m/s along x, turning 0.1 rad/s.
  Trajectory est;
  for (int i = 0; i <= 10; ++i) {
    est.push_back({SecondsToNs(i), PoseXyzRpy(i, 0, 0, 0, 0, 0.1 * i)});
  }
  const auto relation = [](double t1, double t2, const Pose3& delta) {
    PoseRelation r;
    r.t1 = SecondsToNs(t1);
    r.t2 = SecondsToNs(t2);
    r.delta = delta;
    return r;
  };
  // Exact between the poses at 2 and 3 s (within 1 ms), between the
  // interpolated poses at 0.5 and 1.5 s, and off the trajectory's end.
  const Pose3 x2 = est[2].pose, x3 = est[3].pose;
  const Pose3 x05 = PoseXyzRpy(0.5, 0, 0, 0, 0, 0.05);
  const Pose3 x15 = PoseXyzRpy(1.5, 0, 0, 0, 0, 0.15);
  const std::vector<PoseRelation> relations = {
      relation(2.0009, 2.9991, x2.Inverse() * x3),
      relation(0.5, 1.5, x05.Inverse() * x15),
      relation(9.5, 10.5, Pose3()),
  };
  RelationErrorResult r;
  std::string error;
  ASSERT_TRUE(ComputeRelationError(est, relations, {}, &r, &error)) << error;
  EXPECT_EQ(r.used, (std::vector<size_t>{0}));
  EXPECT_EQ(r.unmatched, 2u);
  EXPECT_NEAR(r.translation[0], 0.0, 1e-12);

  RelationErrorOptions interpolate;
  interpolate.interpolate = true;
  ASSERT_TRUE(ComputeRelationError(est, relations, interpolate, &r, &error));
  EXPECT_EQ(r.used, (std::vector<size_t>{0, 1}));
  EXPECT_EQ(r.unmatched, 1u);  // 10.5 s is after the last pose.
  EXPECT_EQ(r.interpolated, 1u);
  EXPECT_NEAR(r.translation[1], 0.0, 1e-12);
  EXPECT_NEAR(r.rotation_deg[1], 0.0, 1e-9);

  // A tighter tolerance leaves the first relation out too.
  RelationErrorOptions tight;
  tight.t_max_diff = 0.0005;
  EXPECT_FALSE(ComputeRelationError(est, relations, tight, &r, &error));
  EXPECT_TRUE(Contains(error, "none of the 3 relations")) << error;

  // The estimate's stamps must increase.
  Trajectory bad = est;
  bad[4].stamp = bad[3].stamp;
  EXPECT_FALSE(ComputeRelationError(bad, relations, {}, &r, &error));
  EXPECT_TRUE(Contains(error, "must increase strictly")) << error;
}

TEST(Relations, EvalCommand) {
  Trajectory est;
  std::vector<PoseRelation> relations;
  BuildKnownCase(true, &est, &relations);
  const std::string dir = TempDir();
  std::string error;
  ASSERT_TRUE(
      WriteTrajectory(dir + "/est.tum", est, TrajectoryFormat::kTum, &error))
      << error;
  ASSERT_TRUE(WriteRelations(dir + "/gt.relations", relations, &error));
  ASSERT_EQ(RunSlam("eval --relations " + dir + "/gt.relations --est " + dir +
                        "/est.tum --report " + dir + "/report.json",
                    dir + "/log.txt"),
            0)
      << ReadText(dir + "/log.txt");
  const std::string log = ReadText(dir + "/log.txt");
  EXPECT_TRUE(Contains(log, "4 of 4 relations used, 0 unmatched")) << log;
  EXPECT_TRUE(Contains(log, "translation abs     0.250000 +-    0.129099  m"))
      << log;
  EXPECT_TRUE(Contains(log, "rotation abs        2.500000 +-    1.290994  deg"))
      << log;
  const YAML::Node report = YAML::LoadFile(dir + "/report.json");
  const YAML::Node rel = report["relation_error"];
  EXPECT_EQ(rel["used"].as<int>(), 4);
  EXPECT_NEAR(rel["translation_abs"]["mean"].as<double>(), 0.25, 1e-12);
  EXPECT_NEAR(rel["rotation_sq"]["mean"].as<double>(), 7.5, 1e-8);
  EXPECT_EQ(rel["rotation_sq"]["unit"].as<std::string>(), "deg^2");

  // The estimate as a positional argument.
  EXPECT_EQ(
      RunSlam("eval --relations " + dir + "/gt.relations " + dir + "/est.tum",
              dir + "/log2.txt"),
      0)
      << ReadText(dir + "/log2.txt");
  // --ref makes no sense with --relations: usage error.
  EXPECT_EQ(RunSlam("eval --relations " + dir + "/gt.relations --ref " + dir +
                        "/est.tum --est " + dir + "/est.tum",
                    dir + "/log3.txt"),
            2);
  // A bad relations file: its line, exit 1, no report.
  WriteText(dir + "/bad.relations", "0 1 0 0 0 0 0 0\n0 1 0 0\n");
  EXPECT_EQ(RunSlam("eval --relations " + dir + "/bad.relations --est " + dir +
                        "/est.tum --report " + dir + "/bad.json",
                    dir + "/log4.txt"),
            1);
  EXPECT_TRUE(Contains(ReadText(dir + "/log4.txt"),
                       dir + "/bad.relations:2: expected 8 fields"))
      << ReadText(dir + "/log4.txt");
  EXPECT_FALSE(testing::Exists(dir + "/bad.json"));
  // The options come from the eval: section of a config too.
  WriteText(dir + "/config.yaml", "eval:\n  relations_t_max_diff: -1\n");
  EXPECT_EQ(RunSlam("eval --config " + dir + "/config.yaml --relations " + dir +
                        "/gt.relations --est " + dir + "/est.tum",
                    dir + "/log6.txt"),
            2);
  EXPECT_TRUE(Contains(ReadText(dir + "/log6.txt"),
                       "relations_t_max_diff must be >= 0"))
      << ReadText(dir + "/log6.txt");
  // The options are in --dump_config.
  EXPECT_EQ(
      RunSlam("eval --dump_config --relations_interpolate", dir + "/log5.txt"),
      0);
  EXPECT_TRUE(
      Contains(ReadText(dir + "/log5.txt"), "relations_interpolate: true"));
}

TEST(Relations, AcesRelationsFile) {
  const std::string path =
      testing::DatasetPath("laser_logs_carmen/aces.relations");
  SLAM_REQUIRE_DATASET(path);
  std::vector<PoseRelation> relations;
  std::string error;
  ASSERT_TRUE(ReadRelations(path, &relations, &error)) << error;
  EXPECT_EQ(relations.size(), 1279u);
  for (const PoseRelation& r : relations) {
    // Planar displacements between stamps inside the log.
    EXPECT_EQ(r.delta.t.z(), 0.0);
    EXPECT_LT(std::abs((r.delta.q * Eigen::Vector3d::UnitZ()).z() - 1.0),
              1e-12);
    EXPECT_GT(r.t1, SecondsToNs(70.0));
  }
}

}  // namespace
}  // namespace slam
