#include "datasets/toro_io.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

using text::CheckFieldCount;
using text::CheckMinFieldCount;
using text::ParseDoubles;
using text::ParseId;

// Scale between HOG-Man's rotation error (Euler angles) and ours (quaternion
// vector part) at zero error: qvec = rpy / 2 (see toro_io.h).
constexpr double kRpyPerQvec = 2.0;

double RotationScale(int index) { return index < 3 ? 1.0 : kRpyPerQvec; }

Eigen::Vector4d Coefficients(const Eigen::Quaterniond& q) {
  return Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
}

bool ParseLine(const std::vector<std::string_view>& tokens, int64_t line,
               text::PoseGraphBuilder* builder, std::string* problem,
               std::string* error) {
  const std::string_view tag = tokens[0];
  int64_t i = 0, j = 0;
  double v[27];
  if (tag == "VERTEX2" || tag == "VERTEX") {
    if (!CheckFieldCount(tokens, 4, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 3, v, problem)) {
      return false;
    }
    return builder->AddVertexSE2(line, i, v[0], v[1], v[2], error);
  }
  if (tag == "EDGE2" || tag == "EDGE") {
    if (!CheckFieldCount(tokens, 11, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 9, v, problem)) {
      return false;
    }
    // inf_ff inf_fs inf_ss inf_rr inf_fr inf_sr = I11 I12 I22 I33 I13 I23.
    const double* f = v + 3;
    Eigen::Matrix3d information;
    information << f[0], f[1], f[4],  //
        f[1], f[2], f[5],             //
        f[4], f[5], f[3];
    return builder->AddBetweenSE2(line, i, j, v[0], v[1], v[2], information,
                                  error);
  }
  if (tag == "VERTEX3")
    return AddVertexRpy(tokens, line, builder, problem, error);
  if (tag == "EDGE3") {
    if (!CheckFieldCount(tokens, 29, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 27, v, problem)) {
      return false;
    }
    // Omega = D Omega_h D, D = diag(1, 1, 1, 2, 2, 2).
    Eigen::Matrix<double, 6, 6> information;
    int k = 6;
    for (int r = 0; r < 6; ++r) {
      for (int c = r; c < 6; ++c) {
        const double value = v[k++] * RotationScale(r) * RotationScale(c);
        information(r, c) = value;
        information(c, r) = value;
      }
    }
    return builder->AddBetweenSE3(
        line, i, j, Eigen::Vector3d(v[0], v[1], v[2]),
        Coefficients(QuaternionFromRpy(v[3], v[4], v[5])), information, error);
  }
  if (tag == "BR") {
    // BR pose landmark bearing range sigma_bearing sigma_range (GTSAM's
    // example.graph).
    if (!CheckFieldCount(tokens, 6, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 4, v, problem)) {
      return false;
    }
    if (!(v[2] > 0.0) || !(v[3] > 0.0)) {
      *problem = "BR standard deviations must be positive";
      return false;
    }
    Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
    information(0, 0) = 1.0 / (v[3] * v[3]);  // Range.
    information(1, 1) = 1.0 / (v[2] * v[2]);  // Bearing.
    return builder->AddLandmarkFactor(
        line, 2, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeRangeBearing2(pose, point, v[1], v[0], information, f, p);
        },
        error);
  }
  if (tag == "FIX") {
    if (!CheckMinFieldCount(tokens, 1, problem)) return false;
    for (size_t k = 1; k < tokens.size(); ++k) {
      if (!ParseId(tokens, k, &i, problem)) return false;
      builder->AddFix(line, i);
    }
    return true;
  }
  if (tag == "EQUIV") {  // Node equivalences: part of TORO, not read.
    builder->SkipTag(tag);
    return true;
  }
  return builder->UnknownTag(line, tag, error);
}

void AppendValue(double value, std::string* out) {
  out->push_back(' ');
  text::AppendDouble(value, out);
}

}  // namespace

Eigen::Quaterniond QuaternionFromRpy(double roll, double pitch, double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

bool AddVertexRpy(const std::vector<std::string_view>& tokens, int64_t line,
                  text::PoseGraphBuilder* builder, std::string* problem,
                  std::string* error) {
  int64_t id = 0;
  double v[6];
  if (!CheckFieldCount(tokens, 7, problem) ||
      !ParseId(tokens, 1, &id, problem) ||
      !ParseDoubles(tokens, 2, 6, v, problem)) {
    return false;
  }
  return builder->AddVertexSE3(
      line, id, Eigen::Vector3d(v[0], v[1], v[2]),
      Coefficients(QuaternionFromRpy(v[3], v[4], v[5])), error);
}

Eigen::Vector3d RpyFromQuaternion(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  // "+ 0.0" turns -0 into 0, to keep "-0" out of the file.
  return Eigen::Vector3d(
      std::atan2(r(2, 1), r(2, 2)) + 0.0,
      std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2))) + 0.0,
      std::atan2(r(1, 0), r(0, 0)) + 0.0);
}

bool ReadToroFromText(const std::string& name, std::string_view text,
                      const GraphReadOptions& options, Graph* graph,
                      GraphReadReport* report, std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  GraphReadReport local_report;
  if (report == nullptr) report = &local_report;
  *report = GraphReadReport();
  text::PoseGraphBuilder builder(name, options);
  const text::RecordParser parse =
      [&builder](const std::vector<std::string_view>& tokens, int64_t line,
                 std::string* problem, std::string* error) {
        return ParseLine(tokens, line, &builder, problem, error);
      };
  return text::ParseRecords(text, builder, parse, error) &&
         builder.Finish(graph, report, error);
}

bool ReadToro(const std::string& path, const GraphReadOptions& options,
              Graph* graph, GraphReadReport* report, std::string* error) {
  std::string contents;
  std::string local_error;
  if (!text::ReadWholeFile(path, &contents,
                           error != nullptr ? error : &local_error)) {
    return false;
  }
  return ReadToroFromText(path, contents, options, graph, report, error);
}

bool WriteToro(const std::string& path, const Graph& graph,
               std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  text::PoseGraphContents contents;
  if (!text::CollectPoseGraph(path, graph, &contents, error)) return false;
  for (const auto& [id, factor] : graph.factors()) {
    if (factor.type == FactorType::kPriorSE2 ||
        factor.type == FactorType::kPriorSE3) {
      *error = path + ": factor " + std::to_string(id) +
               " is a prior, which the TORO format cannot hold";
      return false;
    }
    if (IsLandmarkFactor(factor.type) &&
        (factor.type != FactorType::kRangeBearing2 ||
         factor.information(0, 1) != 0.0)) {
      *error = path + ": factor " + std::to_string(id) + " (" +
               FactorTypeName(factor.type) +
               ") has no TORO record (BR holds range-bearing factors with "
               "independent range and bearing noise only)";
      return false;
    }
  }
  const bool is3 = contents.dimension == 3;
  std::string out;
  out.reserve(contents.nodes.size() * (is3 ? 180 : 80) +
              contents.factors.size() * (is3 ? 600 : 220));
  for (const Node* node : contents.nodes) {
    const std::vector<double>& x = node->value;
    out += is3 ? "VERTEX3 " : "VERTEX2 ";
    text::AppendInt(node->key.id, &out);
    if (is3) {
      const Eigen::Vector3d rpy =
          RpyFromQuaternion(Eigen::Quaterniond(x[6], x[3], x[4], x[5]));
      for (double value : {x[0], x[1], x[2], rpy[0], rpy[1], rpy[2]}) {
        AppendValue(value, &out);
      }
    } else {
      for (double value : {x[0], x[1], x[2]}) AppendValue(value, &out);
    }
    out.push_back('\n');
  }
  for (const Node* node : contents.nodes) {
    if (!node->fixed) continue;
    out += "FIX ";
    text::AppendInt(node->key.id, &out);
    out.push_back('\n');
  }
  for (const Factor* factor : contents.factors) {
    const Eigen::VectorXd& z = factor->measurement;
    const Eigen::MatrixXd& m = factor->information;
    out += is3 ? "EDGE3 " : "EDGE2 ";
    text::AppendInt(factor->keys[0].id, &out);
    out.push_back(' ');
    text::AppendInt(factor->keys[1].id, &out);
    if (is3) {
      const Eigen::Vector3d rpy =
          RpyFromQuaternion(Eigen::Quaterniond(z[6], z[3], z[4], z[5]));
      for (double value : {z[0], z[1], z[2], rpy[0], rpy[1], rpy[2]}) {
        AppendValue(value, &out);
      }
      // Omega_h = D^-1 Omega D^-1.
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) {
          AppendValue(m(r, c) / (RotationScale(r) * RotationScale(c)), &out);
        }
      }
    } else {
      for (double value : {z[0], z[1], z[2], m(0, 0), m(0, 1), m(1, 1), m(2, 2),
                           m(0, 2), m(1, 2)}) {
        AppendValue(value, &out);
      }
    }
    out.push_back('\n');
  }
  for (const Factor* factor : contents.landmark_factors) {
    const Eigen::VectorXd& z = factor->measurement;
    out += "BR ";
    text::AppendInt(factor->keys[0].id, &out);
    out.push_back(' ');
    text::AppendInt(factor->keys[1].id, &out);
    for (double value : {z[1], z[0], 1.0 / std::sqrt(factor->information(1, 1)),
                         1.0 / std::sqrt(factor->information(0, 0))}) {
      AppendValue(value, &out);
    }
    out.push_back('\n');
  }
  return WriteFileAtomically(path, out, error);
}

}  // namespace slam
