#include "datasets/isam_io.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/information.h"
#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "datasets/toro_io.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

using text::CheckFieldCount;
using text::ParseDoubles;
using text::ParseId;

constexpr char kSingular[] =
    "square-root information has a zero on its diagonal";

// R from the upper triangle, row-major; false if a diagonal entry is zero.
template <int N>
bool SqrtFromUpper(const double* v, Eigen::Matrix<double, N, N>* r) {
  r->setZero();
  int k = 0;
  for (int row = 0; row < N; ++row) {
    for (int col = row; col < N; ++col) (*r)(row, col) = v[k++];
    if ((*r)(row, row) == 0.0) return false;
  }
  return true;
}

// Reads the optional square-root information of EDGE3/POINT3 (identity when
// the record has none, as in iSAM): Omega_iSAM = R^T R.
template <int N>
bool InformationFromOptionalSqrt(const double* v, bool present,
                                 Eigen::Matrix<double, N, N>* info,
                                 std::string* problem) {
  if (!present) {
    info->setIdentity();
    return true;
  }
  Eigen::Matrix<double, N, N> r;
  if (!SqrtFromUpper<N>(v, &r)) {
    *problem = kSingular;
    return false;
  }
  *info = r.transpose() * r;
  return true;
}

// J with e_iSAM = J e for ODOMETRY (see isam_io.h): exact.
Eigen::Matrix3d OdometryJacobian(double theta_z) {
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(theta_z).toRotationMatrix();
  return j;
}

// J with e_iSAM = J e for EDGE3, rows and columns over (t, roll, pitch, yaw)
// and (t, qvec): diag(R_z, 2 W^-1). For R = Rz(yaw) Ry(pitch) Rx(roll) the
// body rate is omega = W d(roll, pitch, yaw)/dt with
//   W = [1 0 -sin(p); 0 cos(r) sin(r) cos(p); 0 -sin(r) cos(r) cos(p)],
// and qvec = omega / 2 to first order. False at pitch = +-90 degrees.
bool Edge3Jacobian(const Eigen::Vector3d& rpy, const Eigen::Matrix3d& rot,
                   Eigen::Matrix<double, 6, 6>* j) {
  const double sr = std::sin(rpy[0]), cr = std::cos(rpy[0]);
  const double sp = std::sin(rpy[1]), cp = std::cos(rpy[1]);
  if (std::abs(cp) < 1e-9) return false;
  Eigen::Matrix3d w;
  w << 1, 0, -sp, 0, cr, sr * cp, 0, -sr, cr * cp;
  j->setZero();
  j->topLeftCorner<3, 3>() = rot;
  j->bottomRightCorner<3, 3>() = 2.0 * w.inverse();
  return true;
}

// J^T Omega J, exactly symmetric (the products round differently on the
// two sides of the diagonal).
template <int N>
Eigen::Matrix<double, N, N> Congruence(const Eigen::Matrix<double, N, N>& j,
                                       const Eigen::Matrix<double, N, N>& o) {
  const Eigen::Matrix<double, N, N> a = j.transpose() * o * j;
  return 0.5 * (a + a.transpose());
}

Eigen::Vector4d Coefficients(const Eigen::Quaterniond& q) {
  return Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
}

// iSAM's EDGE3 and POINT3 come with or without their square-root
// information: `full` or `short` fields after the tag.
bool CheckOptionalFields(const std::vector<std::string_view>& tokens,
                         size_t short_count, size_t full_count, bool* full,
                         std::string* problem) {
  const size_t found = tokens.size() - 1;
  *full = found == full_count;
  if (*full || found == short_count) return true;
  *problem = text::Printable(tokens[0]) + " needs " +
             std::to_string(short_count) + " or " + std::to_string(full_count) +
             " fields after the tag, found " + std::to_string(found);
  return false;
}

bool ParseOdometry(const std::vector<std::string_view>& tokens, int64_t line,
                   text::PoseGraphBuilder* builder, std::string* problem,
                   std::string* error) {
  int64_t i = 0, j = 0;
  double v[9];
  if (!CheckFieldCount(tokens, 11, problem) ||
      !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
      !ParseDoubles(tokens, 3, 9, v, problem)) {
    return false;
  }
  Eigen::Matrix3d r;
  if (!SqrtFromUpper<3>(v + 3, &r)) {
    *problem = kSingular;
    return false;
  }
  const Eigen::Matrix3d jac = OdometryJacobian(v[2]);
  return builder->AddBetweenSE2(line, i, j, v[0], v[1], v[2],
                                Congruence<3>(jac, r.transpose() * r), error);
}

bool ParseEdge3(const std::vector<std::string_view>& tokens, int64_t line,
                text::PoseGraphBuilder* builder, std::string* problem,
                std::string* error) {
  bool with_sqrt = false;
  if (!CheckOptionalFields(tokens, 8, 29, &with_sqrt, problem)) return false;
  int64_t i = 0, j = 0;
  double v[27];
  if (!ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
      !ParseDoubles(tokens, 3, with_sqrt ? 27 : 6, v, problem)) {
    return false;
  }
  Eigen::Matrix<double, 6, 6> info_isam;
  if (!InformationFromOptionalSqrt<6>(v + 6, with_sqrt, &info_isam, problem)) {
    return false;
  }
  Eigen::Quaterniond q = QuaternionFromRpy(v[3], v[4], v[5]);
  Eigen::Vector3d t(v[0], v[1], v[2]);
  Eigen::Vector3d rpy(v[3], v[4], v[5]);
  if (i > j) {
    // iSAM keeps its edges from the lower to the higher id: z^-1, same R.
    std::swap(i, j);
    q = q.conjugate();
    t = -(q * t);
    rpy = RpyFromQuaternion(q);
  }
  Eigen::Matrix<double, 6, 6> jac;
  if (!Edge3Jacobian(rpy, q.toRotationMatrix(), &jac)) {
    *problem = "EDGE3 measurement at pitch +-90 degrees (Euler singularity)";
    return false;
  }
  return builder->AddBetweenSE3(line, i, j, t, Coefficients(q),
                                Congruence<6>(jac, info_isam), error);
}

bool ParseLine(const std::vector<std::string_view>& tokens, int64_t line,
               text::PoseGraphBuilder* builder, std::string* problem,
               std::string* error) {
  const std::string_view tag = tokens[0];
  int64_t i = 0, j = 0;
  double v[9];
  if (tag == "ODOMETRY" || tag == "EDGE2" || tag == "Constraint2") {
    return ParseOdometry(tokens, line, builder, problem, error);
  }
  if (tag == "EDGE3") return ParseEdge3(tokens, line, builder, problem, error);
  if (tag == "LANDMARK") {
    if (!CheckFieldCount(tokens, 7, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 5, v, problem)) {
      return false;
    }
    Eigen::Matrix2d info;
    if (!InformationFromOptionalSqrt<2>(v + 2, true, &info, problem)) {
      return false;
    }
    return builder->AddLandmarkFactor(
        line, 2, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeRelativePoint2(pose, point, Eigen::Vector2d(v[0], v[1]),
                                    info, f, p);
        },
        error);
  }
  if (tag == "POINT3") {
    bool with_sqrt = false;
    if (!CheckOptionalFields(tokens, 5, 11, &with_sqrt, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, with_sqrt ? 9 : 3, v, problem)) {
      return false;
    }
    Eigen::Matrix3d info;
    if (!InformationFromOptionalSqrt<3>(v + 3, with_sqrt, &info, problem)) {
      return false;
    }
    return builder->AddLandmarkFactor(
        line, 3, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeRelativePoint3(pose, point,
                                    Eigen::Vector3d(v[0], v[1], v[2]), Pose3(),
                                    info, f, p);
        },
        error);
  }
  if (tag == "POSE3D_INIT") {
    return AddVertexRpy(tokens, line, builder, problem, error);
  }
  if (tag == "SOLVE" || tag == "EDGE3_INIT" || tag == "POSE3D_TRUE" ||
      tag == "EDGE3_TRUE") {
    builder->SkipTag(tag);  // iSAM's own bookkeeping: no factor.
    return true;
  }
  if (tag == "CAMERA_STEREO" || tag == "POINT_STEREO") {
    *problem = "iSAM stereo record '" + std::string(tag) +
               "' is not read (convert it to GTSAM's stereo VO format)";
    return false;
  }
  *problem = "unknown iSAM record '" + text::Printable(tag) +
             "' (ODOMETRY/EDGE2, LANDMARK, EDGE3, POINT3, POSE3D_INIT are "
             "read)";
  return false;
}

void AppendValues(const double* v, int n, std::string* out) {
  for (int k = 0; k < n; ++k) {
    out->push_back(' ');
    text::AppendDouble(v[k], out);
  }
}

}  // namespace

bool ReadIsamFromText(const std::string& name, std::string_view text,
                      const GraphReadOptions& options, Graph* graph,
                      GraphReadReport* report, std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  GraphReadReport local_report;
  if (report == nullptr) report = &local_report;
  *report = GraphReadReport();
  // iSAM files hold no values (POSE3D_INIT at most): every other node is
  // initialized from the edges.
  GraphReadOptions isam_options = options;
  isam_options.allow_missing_vertices = true;
  text::PoseGraphBuilder builder(name, isam_options);
  const text::RecordParser parse =
      [&builder](const std::vector<std::string_view>& tokens, int64_t line,
                 std::string* problem, std::string* error) {
        return ParseLine(tokens, line, &builder, problem, error);
      };
  return text::ParseRecords(text, builder, parse, error) &&
         builder.Finish(graph, report, error);
}

bool ReadIsam(const std::string& path, const GraphReadOptions& options,
              Graph* graph, GraphReadReport* report, std::string* error) {
  std::string contents;
  std::string local_error;
  if (!text::ReadWholeFile(path, &contents,
                           error != nullptr ? error : &local_error)) {
    return false;
  }
  return ReadIsamFromText(path, contents, options, graph, report, error);
}

bool WriteIsam(const std::string& path, const Graph& graph,
               std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  text::PoseGraphContents contents;
  if (!text::CollectPoseGraph(path, graph, &contents, error)) return false;
  if (contents.dimension == 3) {
    *error = path + ": the iSAM writer holds 2D graphs only";
    return false;
  }
  std::string out;
  for (const auto& [id, factor] : graph.factors()) {
    const bool odometry = factor.type == FactorType::kBetweenSE2;
    if (!odometry && factor.type != FactorType::kRelativePoint2) {
      *error = path + ": factor " + std::to_string(id) + " (" +
               FactorTypeName(factor.type) +
               ") has no iSAM record (ODOMETRY and LANDMARK only)";
      return false;
    }
    // iSAM's information: Omega_iSAM = J^-T Omega J^-1 = J Omega J^T (J is
    // orthogonal, see ParseOdometry).
    Eigen::MatrixXd info_isam = factor.information;
    if (odometry) {
      const Eigen::Matrix3d jac = OdometryJacobian(factor.measurement[2]);
      info_isam = Congruence<3>(jac.transpose(), factor.information);
    }
    Eigen::MatrixXd r;
    if (!SqrtInformation(info_isam, &r)) {
      *error = path + ": factor " + std::to_string(id) +
               " has an information matrix that is not positive definite";
      return false;
    }
    out += odometry ? "ODOMETRY " : "LANDMARK ";
    text::AppendInt(factor.keys[0].id, &out);
    out.push_back(' ');
    text::AppendInt(factor.keys[1].id, &out);
    AppendValues(factor.measurement.data(), odometry ? 3 : 2, &out);
    for (int row = 0; row < r.rows(); ++row) {
      for (int col = row; col < r.cols(); ++col) {
        out.push_back(' ');
        text::AppendDouble(r(row, col), &out);
      }
    }
    out.push_back('\n');
  }
  return WriteFileAtomically(path, out, error);
}

}  // namespace slam
