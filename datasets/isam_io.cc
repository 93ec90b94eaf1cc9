#include "datasets/isam_io.h"

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/information.h"
#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

using text::CheckFieldCount;
using text::ParseDoubles;
using text::ParseId;

// Omega = R^T R from the upper triangle of R, row-major.
template <int N>
Eigen::Matrix<double, N, N> InformationFromSqrt(const double* v) {
  Eigen::Matrix<double, N, N> r = Eigen::Matrix<double, N, N>::Zero();
  int k = 0;
  for (int row = 0; row < N; ++row) {
    for (int col = row; col < N; ++col) r(row, col) = v[k++];
  }
  return r.transpose() * r;
}

bool SingularSqrt(const double* v, int n) {
  // Diagonal entries of the upper triangle: 0, n, n + (n - 1), ...
  int k = 0;
  for (int row = 0; row < n; ++row) {
    if (v[k] == 0.0) return true;
    k += n - row;
  }
  return false;
}

bool ParseLine(const std::vector<std::string_view>& tokens, int64_t line,
               text::PoseGraphBuilder* builder, std::string* problem,
               std::string* error) {
  const std::string_view tag = tokens[0];
  int64_t i = 0, j = 0;
  double v[9];
  if (tag == "ODOMETRY") {
    if (!CheckFieldCount(tokens, 11, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 9, v, problem)) {
      return false;
    }
    if (SingularSqrt(v + 3, 3)) {
      *problem = "square-root information has a zero on its diagonal";
      return false;
    }
    return builder->AddBetweenSE2(line, i, j, v[0], v[1], v[2],
                                  InformationFromSqrt<3>(v + 3), error);
  }
  if (tag == "LANDMARK") {
    if (!CheckFieldCount(tokens, 7, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 5, v, problem)) {
      return false;
    }
    if (SingularSqrt(v + 2, 2)) {
      *problem = "square-root information has a zero on its diagonal";
      return false;
    }
    const Eigen::Matrix2d info = InformationFromSqrt<2>(v + 2);
    return builder->AddLandmarkFactor(
        line, 2, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeRelativePoint2(pose, point, Eigen::Vector2d(v[0], v[1]),
                                    info, f, p);
        },
        error);
  }
  *problem = "unknown iSAM record '" + text::Printable(tag) +
             "' (only the 2D ODOMETRY and LANDMARK records are read)";
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
  text::PoseGraphBuilder builder(name, options);
  builder.set_shared_id_space(true);
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
    Eigen::MatrixXd r;
    if (!SqrtInformation(factor.information, &r)) {
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
