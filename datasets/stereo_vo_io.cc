#include "datasets/stereo_vo_io.h"

#include <Eigen/Core>
#include <Eigen/SVD>
#include <map>
#include <vector>

#include "datasets/text_util.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

using text::CheckFieldCount;
using text::ParseDoubles;
using text::ParseId;

std::string LineError(const std::string& path, int64_t line,
                      const std::string& problem) {
  return path + ":" + std::to_string(line) + ": " + problem;
}

bool ReadCalibration(const std::string& path, StereoCalibration* c,
                     std::string* error) {
  std::string contents;
  if (!text::ReadWholeFile(path, &contents, error)) return false;
  text::LineTokenizer lines(contents);
  std::string problem;
  if (!lines.Next()) {
    *error = path + ": no calibration line";
    return false;
  }
  double v[6];
  // "fx fy skew cx cy baseline": six numbers, no tag.
  if (lines.tokens().size() != 6) {
    *error = LineError(path, lines.line(),
                       "calibration needs 6 numbers (fx fy skew cx cy "
                       "baseline), found " +
                           std::to_string(lines.tokens().size()));
    return false;
  }
  for (int k = 0; k < 6; ++k) {
    if (!text::ParseDouble(lines.tokens()[k], &v[k])) {
      *error = LineError(path, lines.line(),
                         "field " + std::to_string(k + 1) + " '" +
                             text::Printable(lines.tokens()[k]) +
                             "' is not a finite number");
      return false;
    }
  }
  if (v[2] != 0.0) {
    *error = LineError(path, lines.line(), "skew must be 0");
    return false;
  }
  if (!(v[0] > 0.0 && v[1] > 0.0 && v[5] > 0.0)) {
    *error =
        LineError(path, lines.line(), "fx, fy and baseline must be positive");
    return false;
  }
  if (lines.Next()) {
    *error = LineError(path, lines.line(), "extra line after the calibration");
    return false;
  }
  *c = StereoCalibration{v[0], v[1], v[3], v[4], v[5]};
  return true;
}

// Numbers of a tag-less line: the first field is an id.
bool ParseNumberLine(const std::vector<std::string_view>& tokens, size_t count,
                     int64_t* id, double* v, std::string* problem) {
  if (tokens.size() != count) {
    *problem = "needs " + std::to_string(count) + " fields, found " +
               std::to_string(tokens.size());
    return false;
  }
  if (!text::ParseInt64(tokens[0], id)) {
    *problem = "field 1 '" + text::Printable(tokens[0]) + "' is not an id";
    return false;
  }
  for (size_t k = 1; k < count; ++k) {
    if (!text::ParseDouble(tokens[k], &v[k - 1])) {
      *problem = "field " + std::to_string(k + 1) + " '" +
                 text::Printable(tokens[k]) + "' is not a finite number";
      return false;
    }
  }
  return true;
}

bool ReadPoses(const std::string& path, std::map<int64_t, Pose3>* poses,
               std::string* error) {
  std::string contents;
  if (!text::ReadWholeFile(path, &contents, error)) return false;
  text::LineTokenizer lines(contents);
  std::string problem;
  double v[16];
  int64_t id = 0;
  while (lines.Next()) {
    if (!ParseNumberLine(lines.tokens(), 17, &id, v, &problem)) {
      *error = LineError(path, lines.line(), "camera pose " + problem);
      return false;
    }
    Eigen::Matrix4d m;
    for (int k = 0; k < 16; ++k) m(k / 4, k % 4) = v[k];
    if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
      *error = LineError(path, lines.line(),
                         "the last row of the pose matrix is not 0 0 0 1");
      return false;
    }
    // Nearest rotation (the file prints 6 digits).
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(
        m.topLeftCorner<3, 3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
    if (r.determinant() < 0.0 ||
        (r - m.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff() > 1e-3) {
      *error = LineError(path, lines.line(),
                         "the pose matrix does not hold a rotation");
      return false;
    }
    if (id < 0 || id >= kStereoVoLandmarkIdOffset) {
      *error = LineError(path, lines.line(),
                         "pose id out of range [0, " +
                             std::to_string(kStereoVoLandmarkIdOffset) + ")");
      return false;
    }
    if (!poses
             ->emplace(id,
                       Pose3(m.topRightCorner<3, 1>(), Eigen::Quaterniond(r)))
             .second) {
      *error = LineError(path, lines.line(),
                         "duplicate pose id " + std::to_string(id));
      return false;
    }
  }
  if (poses->empty()) {
    *error = path + ": no camera poses";
    return false;
  }
  return true;
}

}  // namespace

bool ReadStereoVo(const std::string& factors_path,
                  const std::string& calibration_path,
                  const std::string& poses_path, Graph* graph,
                  StereoVoReport* report, std::string* error) {
  if (graph->NumNodes() != 0) {
    *error = factors_path + ": the graph to read into is not empty";
    return false;
  }
  StereoVoReport local_report;
  if (report == nullptr) report = &local_report;
  *report = StereoVoReport();
  StereoCalibration calibration;
  std::map<int64_t, Pose3> poses;
  if (!ReadCalibration(calibration_path, &calibration, error) ||
      !ReadPoses(poses_path, &poses, error)) {
    return false;
  }
  std::string contents;
  if (!text::ReadWholeFile(factors_path, &contents, error)) return false;
  Graph result;
  for (const auto& [id, pose] : poses) {
    result.AddNode(Pose3Key(id), Pose3Value(pose));
  }
  text::LineTokenizer lines(contents);
  std::string problem;
  double v[7];
  const Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  while (lines.Next()) {
    const auto& tokens = lines.tokens();
    int64_t pose_id = 0, landmark_id = 0;
    if (tokens.size() != 8 || !text::ParseInt64(tokens[1], &landmark_id) ||
        !ParseNumberLine({tokens[0], tokens[2], tokens[3], tokens[4], tokens[5],
                          tokens[6], tokens[7]},
                         7, &pose_id, v, &problem)) {
      if (problem.empty()) {
        problem =
            tokens.size() != 8
                ? "needs 8 fields (pose landmark uL uR v X Y Z), found " +
                      std::to_string(tokens.size())
                : "field 2 '" + text::Printable(tokens[1]) + "' is not an id";
      }
      *error =
          LineError(factors_path, lines.line(), "stereo factor " + problem);
      return false;
    }
    const auto pose = poses.find(pose_id);
    if (pose == poses.end()) {
      *error = LineError(factors_path, lines.line(),
                         "unknown camera pose id " + std::to_string(pose_id));
      return false;
    }
    if (landmark_id < 0 ||
        landmark_id > INT64_MAX - kStereoVoLandmarkIdOffset) {
      *error =
          LineError(factors_path, lines.line(), "landmark id out of range");
      return false;
    }
    const Key point = Point3Key(landmark_id + kStereoVoLandmarkIdOffset);
    if (!result.HasNode(point)) {
      const Eigen::Vector3d p =
          pose->second * Eigen::Vector3d(v[3], v[4], v[5]);
      result.AddNode(point, {p.x(), p.y(), p.z()});
      ++report->landmarks;
    }
    Factor factor;
    if (!MakeStereo(Pose3Key(pose_id), point, calibration,
                    Eigen::Vector3d(v[0], v[1], v[2]), information, &factor,
                    &problem) ||
        result.AddFactor(std::move(factor)) < 0) {
      *error = LineError(factors_path, lines.line(),
                         problem.empty() ? "cannot add the factor" : problem);
      return false;
    }
    ++report->measurements;
  }
  if (report->measurements == 0) {
    *error = factors_path +
             ": no stereo factors (lines 'pose landmark uL uR v X Y Z'): "
             "nothing to optimize";
    return false;
  }
  report->poses = static_cast<int>(poses.size());
  report->calibration = calibration;
  *graph = std::move(result);
  return true;
}

}  // namespace slam
