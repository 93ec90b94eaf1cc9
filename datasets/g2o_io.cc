#include "datasets/g2o_io.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "datasets/atomic_file.h"
#include "datasets/isam_io.h"
#include "datasets/text_util.h"
#include "datasets/toro_io.h"
#include "factors/landmark_factors.h"

namespace slam {
namespace {

using text::CheckFieldCount;
using text::CheckMinFieldCount;
using text::ParseDoubles;
using text::ParseId;

// Symmetric N x N matrix from its upper triangle, row-major.
template <int N>
Eigen::Matrix<double, N, N> FromUpperTriangle(const double* v) {
  Eigen::Matrix<double, N, N> m;
  int k = 0;
  for (int r = 0; r < N; ++r) {
    for (int c = r; c < N; ++c) {
      m(r, c) = v[k];
      m(c, r) = v[k];
      ++k;
    }
  }
  return m;
}

void AppendUpperTriangle(const Eigen::MatrixXd& m, std::string* out) {
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = r; c < m.cols(); ++c) {
      out->push_back(' ');
      text::AppendDouble(m(r, c), out);
    }
  }
}

void AppendValues(const double* v, int n, std::string* out) {
  for (int k = 0; k < n; ++k) {
    out->push_back(' ');
    text::AppendDouble(v[k], out);
  }
}

// Per-file state beyond the builder: the declared parameter records by id.
struct G2oState {
  std::unordered_map<int64_t, Pose3> offsets;               // PARAMS_SE3OFFSET.
  std::unordered_map<int64_t, StereoCalibration> stereo;    // PARAMS_STEREO.
  std::unordered_map<int64_t, PinholeCalibration> pinhole;  // PARAMS_PINHOLE.
};

bool IsIdentity(const Pose3& p) {
  return p.t.isZero() && p.q.vec().isZero() && p.q.w() != 0.0;
}

// The parameter record `id` of a map, or *problem naming it.
template <typename Map>
bool FindParam(const Map& map, const char* tag, const char* params_tag,
               int64_t id, typename Map::mapped_type* value,
               std::string* problem) {
  const auto it = map.find(id);
  if (it == map.end()) {
    *problem = std::string(tag) + " uses " + params_tag + " " +
               std::to_string(id) + ", which the file does not declare";
    return false;
  }
  *value = it->second;
  return true;
}

template <typename Map, typename Value>
bool AddParam(Map* map, const char* tag, int64_t id, const Value& value,
              std::string* problem) {
  if (!map->emplace(id, value).second) {
    *problem = std::string("duplicate ") + tag + " id " + std::to_string(id);
    return false;
  }
  return true;
}

// Parses "TAG pose point [param_id] z(m) info(upper triangle of n x n)" with
// `fields` fields after the tag; v receives z then the information.
bool ParseLandmarkEdge(const std::vector<std::string_view>& tokens,
                       bool has_param, int m, int n, int64_t* pose,
                       int64_t* point, int64_t* param, double* v,
                       std::string* problem) {
  const size_t ids = has_param ? 3 : 2;
  const size_t count = ids + m + n * (n + 1) / 2;
  if (!CheckFieldCount(tokens, count, problem) ||
      !ParseId(tokens, 1, pose, problem) ||
      !ParseId(tokens, 2, point, problem) ||
      (has_param && !ParseId(tokens, 3, param, problem)) ||
      !ParseDoubles(tokens, 1 + ids, count - ids, v, problem)) {
    return false;
  }
  return true;
}

// The landmark edges and parameter records; false with *problem (or
// *error from the builder) on malformed input, *handled false for other
// tags.
bool ParseLandmarkLine(const std::vector<std::string_view>& tokens,
                       int64_t line, text::PoseGraphBuilder* builder,
                       G2oState* state, bool* handled, std::string* problem,
                       std::string* error) {
  const std::string_view tag = tokens[0];
  int64_t i = 0, j = 0, k = 0;
  double v[16];
  *handled = true;
  if (tag == "VERTEX_XY" || tag == "VERTEX_TRACKXYZ") {
    const int dim = tag == "VERTEX_XY" ? 2 : 3;
    if (!CheckFieldCount(tokens, 1 + dim, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, dim, v, problem)) {
      return false;
    }
    return builder->AddVertexPoint(line, i, Eigen::Map<Eigen::VectorXd>(v, dim),
                                   error);
  }
  if (tag == "EDGE_SE2_XY" || tag == "EDGE_SE2_RANGE_BEARING") {
    if (!ParseLandmarkEdge(tokens, false, 2, 2, &i, &j, &k, v, problem)) {
      return false;
    }
    Eigen::Matrix2d info = FromUpperTriangle<2>(v + 2);
    if (!builder->CheckInformation<2>(line, &info, error)) return false;
    const bool relative = tag == "EDGE_SE2_XY";
    return builder->AddLandmarkFactor(
        line, 2, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return relative
                     ? MakeRelativePoint2(
                           pose, point, Eigen::Vector2d(v[0], v[1]), info, f, p)
                     : MakeRangeBearing2(pose, point, v[0], v[1], info, f, p);
        },
        error);
  }
  if (tag == "EDGE_SE3_TRACKXYZ") {
    if (!ParseLandmarkEdge(tokens, true, 3, 3, &i, &j, &k, v, problem)) {
      return false;
    }
    Pose3 offset;
    if (!FindParam(state->offsets, "EDGE_SE3_TRACKXYZ", "PARAMS_SE3OFFSET", k,
                   &offset, problem)) {
      return false;
    }
    Eigen::Matrix3d info = FromUpperTriangle<3>(v + 3);
    if (!builder->CheckInformation<3>(line, &info, error)) return false;
    return builder->AddLandmarkFactor(
        line, 3, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeRelativePoint3(pose, point,
                                    Eigen::Vector3d(v[0], v[1], v[2]), offset,
                                    info, f, p);
        },
        error);
  }
  if (tag == "EDGE_SE3_STEREO") {
    if (!ParseLandmarkEdge(tokens, true, 3, 3, &i, &j, &k, v, problem)) {
      return false;
    }
    StereoCalibration calibration;
    if (!FindParam(state->stereo, "EDGE_SE3_STEREO", "PARAMS_STEREO", k,
                   &calibration, problem)) {
      return false;
    }
    Eigen::Matrix3d info = FromUpperTriangle<3>(v + 3);
    if (!builder->CheckInformation<3>(line, &info, error)) return false;
    return builder->AddLandmarkFactor(
        line, 3, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeStereo(pose, point, calibration,
                            Eigen::Vector3d(v[0], v[1], v[2]), info, f, p);
        },
        error);
  }
  if (tag == "EDGE_SE3_PROJECT") {
    if (!ParseLandmarkEdge(tokens, true, 2, 2, &i, &j, &k, v, problem)) {
      return false;
    }
    PinholeCalibration calibration;
    if (!FindParam(state->pinhole, "EDGE_SE3_PROJECT", "PARAMS_PINHOLE", k,
                   &calibration, problem)) {
      return false;
    }
    Eigen::Matrix2d info = FromUpperTriangle<2>(v + 2);
    if (!builder->CheckInformation<2>(line, &info, error)) return false;
    return builder->AddLandmarkFactor(
        line, 3, i, j,
        [&](const Key& pose, const Key& point, Factor* f, std::string* p) {
          return MakeReprojection(pose, point, calibration,
                                  Eigen::Vector2d(v[0], v[1]), info, f, p);
        },
        error);
  }
  if (tag == "PARAMS_SE3OFFSET") {
    if (!CheckFieldCount(tokens, 8, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 7, v, problem)) {
      return false;
    }
    Pose3 offset;
    offset.t = Eigen::Vector3d(v[0], v[1], v[2]);
    if (!text::UnitQuaternion(v[3], v[4], v[5], v[6], &offset.q)) {
      *problem = "PARAMS_SE3OFFSET quaternion has zero length";
      return false;
    }
    return AddParam(&state->offsets, "PARAMS_SE3OFFSET", i, offset, problem);
  }
  if (tag == "PARAMS_STEREO") {
    if (!CheckFieldCount(tokens, 6, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 5, v, problem)) {
      return false;
    }
    const StereoCalibration c{v[0], v[1], v[2], v[3], v[4]};
    if (!(c.fx > 0.0 && c.fy > 0.0 && c.baseline > 0.0)) {
      *problem = "PARAMS_STEREO needs positive fx, fy and baseline";
      return false;
    }
    return AddParam(&state->stereo, "PARAMS_STEREO", i, c, problem);
  }
  if (tag == "PARAMS_PINHOLE") {
    if (!CheckFieldCount(tokens, 9, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 8, v, problem)) {
      return false;
    }
    const PinholeCalibration c{v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]};
    if (!(c.fx > 0.0 && c.fy > 0.0)) {
      *problem = "PARAMS_PINHOLE needs positive fx and fy";
      return false;
    }
    return AddParam(&state->pinhole, "PARAMS_PINHOLE", i, c, problem);
  }
  *handled = false;
  return true;
}

// Parses one line; false with *problem on malformed input.
bool ParseLine(const std::vector<std::string_view>& tokens, int64_t line,
               text::PoseGraphBuilder* builder, G2oState* state,
               std::string* problem, std::string* error) {
  const std::string_view tag = tokens[0];
  int64_t i = 0, j = 0;
  double v[30];
  if (tag == "VERTEX_SE2") {
    if (!CheckFieldCount(tokens, 4, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 3, v, problem)) {
      return false;
    }
    return builder->AddVertexSE2(line, i, v[0], v[1], v[2], error);
  }
  if (tag == "EDGE_SE2") {
    if (!CheckFieldCount(tokens, 11, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 9, v, problem)) {
      return false;
    }
    return builder->AddBetweenSE2(line, i, j, v[0], v[1], v[2],
                                  FromUpperTriangle<3>(v + 3), error);
  }
  if (tag == "EDGE_PRIOR_SE2" || tag == "EDGE_SE2_PRIOR") {
    if (!CheckFieldCount(tokens, 10, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 9, v, problem)) {
      return false;
    }
    return builder->AddPriorSE2(line, i, v[0], v[1], v[2],
                                FromUpperTriangle<3>(v + 3), error);
  }
  if (tag == "VERTEX_SE3:QUAT") {
    if (!CheckFieldCount(tokens, 8, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 7, v, problem)) {
      return false;
    }
    return builder->AddVertexSE3(line, i, Eigen::Vector3d(v[0], v[1], v[2]),
                                 Eigen::Vector4d(v[3], v[4], v[5], v[6]),
                                 error);
  }
  if (tag == "EDGE_SE3:QUAT") {
    if (!CheckFieldCount(tokens, 30, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 28, v, problem)) {
      return false;
    }
    return builder->AddBetweenSE3(line, i, j, Eigen::Vector3d(v[0], v[1], v[2]),
                                  Eigen::Vector4d(v[3], v[4], v[5], v[6]),
                                  FromUpperTriangle<6>(v + 7), error);
  }
  if (tag == "EDGE_SE3_PRIOR") {
    if (!CheckFieldCount(tokens, 30, problem) ||
        !ParseId(tokens, 1, &i, problem) || !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 28, v, problem)) {
      return false;
    }
    Pose3 offset;
    if (!FindParam(state->offsets, "EDGE_SE3_PRIOR", "PARAMS_SE3OFFSET", j,
                   &offset, problem)) {
      return false;
    }
    if (!IsIdentity(offset)) {
      *problem = "EDGE_SE3_PRIOR with a non-identity PARAMS_SE3OFFSET " +
                 std::to_string(j) + " is not supported";
      return false;
    }
    return builder->AddPriorSE3(line, i, Eigen::Vector3d(v[0], v[1], v[2]),
                                Eigen::Vector4d(v[3], v[4], v[5], v[6]),
                                FromUpperTriangle<6>(v + 7), error);
  }
  bool handled = false;
  const bool ok =
      ParseLandmarkLine(tokens, line, builder, state, &handled, problem, error);
  if (handled) return ok;
  if (tag == "FIX") {
    if (!CheckMinFieldCount(tokens, 1, problem)) return false;
    for (size_t k = 1; k < tokens.size(); ++k) {
      if (!ParseId(tokens, k, &i, problem)) return false;
      builder->AddFix(line, i);
    }
    return true;
  }
  return builder->UnknownTag(line, tag, error);
}

// kEdges: EDGE2/EDGE3, which TORO and iSAM both use (with information and
// square-root information respectively).
enum class Format { kUnknown, kG2o, kToro, kIsam, kEdges };

Format FormatOfTag(std::string_view tag) {
  if (tag == "VERTEX_SE2" || tag == "EDGE_SE2" || tag == "VERTEX_SE3:QUAT" ||
      tag == "EDGE_SE3:QUAT" || tag == "EDGE_PRIOR_SE2" ||
      tag == "EDGE_SE2_PRIOR" || tag == "EDGE_SE3_PRIOR" ||
      tag == "VERTEX_XY" || tag == "EDGE_SE2_XY" || tag == "VERTEX_TRACKXYZ" ||
      tag == "EDGE_SE3_TRACKXYZ" || tag == "EDGE_SE2_RANGE_BEARING" ||
      tag == "PARAMS_STEREO" || tag == "EDGE_SE3_STEREO" ||
      tag == "PARAMS_PINHOLE" || tag == "EDGE_SE3_PROJECT") {
    return Format::kG2o;
  }
  if (tag == "EDGE2" || tag == "EDGE3") return Format::kEdges;
  if (tag == "VERTEX2" || tag == "VERTEX3" || tag == "VERTEX" ||
      tag == "EDGE" || tag == "BR" || tag == "EQUIV") {
    return Format::kToro;
  }
  if (tag == "ODOMETRY" || tag == "LANDMARK" || tag == "POINT3" ||
      tag == "Constraint2" || tag == "POSE3D_INIT") {
    return Format::kIsam;
  }
  return Format::kUnknown;
}

std::string LowerExtension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) {
    return "";
  }
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return ext;
}

}  // namespace

bool ReadG2oFromText(const std::string& name, std::string_view text,
                     const GraphReadOptions& options, Graph* graph,
                     GraphReadReport* report, std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  GraphReadReport local_report;
  if (report == nullptr) report = &local_report;
  *report = GraphReadReport();
  text::PoseGraphBuilder builder(name, options);
  G2oState state;
  // First pass: the PARAMS_* records, which edges may use before (in file
  // order) they are declared.
  const text::RecordParser parse_params =
      [&builder, &state](const std::vector<std::string_view>& tokens,
                         int64_t line, std::string* problem,
                         std::string* error) {
        if (tokens[0].substr(0, 7) != "PARAMS_") return true;
        bool handled = false;
        if (!ParseLandmarkLine(tokens, line, &builder, &state, &handled,
                               problem, error)) {
          return false;
        }
        return handled || builder.UnknownTag(line, tokens[0], error);
      };
  // Second pass: everything else.
  const text::RecordParser parse =
      [&builder, &state](const std::vector<std::string_view>& tokens,
                         int64_t line, std::string* problem,
                         std::string* error) {
        if (tokens[0].substr(0, 7) == "PARAMS_") return true;
        return ParseLine(tokens, line, &builder, &state, problem, error);
      };
  if (!text::ParseRecords(text, builder, parse_params, error) ||
      !text::ParseRecords(text, builder, parse, error)) {
    return false;
  }
  return builder.Finish(graph, report, error);
}

bool ReadG2o(const std::string& path, const GraphReadOptions& options,
             Graph* graph, GraphReadReport* report, std::string* error) {
  std::string contents;
  std::string local_error;
  if (!text::ReadWholeFile(path, &contents,
                           error != nullptr ? error : &local_error)) {
    return false;
  }
  return ReadG2oFromText(path, contents, options, graph, report, error);
}

namespace {

// Parameter records of the landmark factors, numbered in order of first use;
// equal records (bit for bit) share one id.
class ParamTable {
 public:
  // The id of the record with these values, declaring it on first use.
  int64_t Id(const char* tag, const std::vector<double>& values,
             std::string* declarations) {
    const auto [it, inserted] =
        ids_.emplace(std::make_pair(std::string(tag), values), next_);
    if (inserted) {
      ++next_;
      *declarations += tag;
      declarations->push_back(' ');
      text::AppendInt(it->second, declarations);
      AppendValues(values.data(), static_cast<int>(values.size()),
                   declarations);
      declarations->push_back('\n');
    }
    return it->second;
  }

 private:
  std::map<std::pair<std::string, std::vector<double>>, int64_t> ids_;
  int64_t next_ = 0;
};

void AppendLandmarkFactor(const Factor& f, ParamTable* params,
                          std::string* declarations, std::string* out) {
  const Eigen::VectorXd& m = f.measurement;
  int64_t param = -1;
  int z_size = 0;
  switch (f.type) {
    case FactorType::kRangeBearing2:
      *out += "EDGE_SE2_RANGE_BEARING";
      z_size = 2;
      break;
    case FactorType::kRelativePoint2:
      *out += "EDGE_SE2_XY";
      z_size = 2;
      break;
    case FactorType::kRelativePoint3:
      *out += "EDGE_SE3_TRACKXYZ";
      param = params->Id("PARAMS_SE3OFFSET",
                         std::vector<double>(m.data() + 3, m.data() + 10),
                         declarations);
      z_size = 3;
      break;
    case FactorType::kStereo:
      *out += "EDGE_SE3_STEREO";
      param = params->Id("PARAMS_STEREO",
                         std::vector<double>(m.data() + 3, m.data() + 8),
                         declarations);
      z_size = 3;
      break;
    case FactorType::kReprojection:
      *out += "EDGE_SE3_PROJECT";
      param = params->Id("PARAMS_PINHOLE",
                         std::vector<double>(m.data() + 2, m.data() + 10),
                         declarations);
      z_size = 2;
      break;
    default:
      return;
  }
  for (const Key& key : f.keys) {
    out->push_back(' ');
    text::AppendInt(key.id, out);
  }
  if (param >= 0) {
    out->push_back(' ');
    text::AppendInt(param, out);
  }
  AppendValues(m.data(), z_size, out);
  AppendUpperTriangle(f.information, out);
  out->push_back('\n');
}

}  // namespace

bool WriteG2o(const std::string& path, const Graph& graph, std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  text::PoseGraphContents contents;
  if (!text::CollectPoseGraph(path, graph, &contents, error)) return false;
  const bool is3 = contents.dimension == 3;
  ParamTable params;
  std::string declarations;
  // Id 0: the identity offset of the 3D priors.
  if (is3 && contents.has_prior) {
    params.Id("PARAMS_SE3OFFSET", {0, 0, 0, 0, 0, 0, 1}, &declarations);
  }
  std::string out;
  out.reserve(contents.nodes.size() * (is3 ? 200 : 80) +
              contents.factors.size() * (is3 ? 600 : 220) +
              contents.landmark_factors.size() * 200);
  for (const Node* node : contents.nodes) {
    out += is3 ? "VERTEX_SE3:QUAT " : "VERTEX_SE2 ";
    text::AppendInt(node->key.id, &out);
    AppendValues(node->value.data(), static_cast<int>(node->value.size()),
                 &out);
    out.push_back('\n');
  }
  for (const Node* node : contents.points) {
    out += is3 ? "VERTEX_TRACKXYZ " : "VERTEX_XY ";
    text::AppendInt(node->key.id, &out);
    AppendValues(node->value.data(), static_cast<int>(node->value.size()),
                 &out);
    out.push_back('\n');
  }
  for (const auto* list : {&contents.nodes, &contents.points}) {
    for (const Node* node : *list) {
      if (!node->fixed) continue;
      out += "FIX ";
      text::AppendInt(node->key.id, &out);
      out.push_back('\n');
    }
  }
  // All written factors in FactorId order, so that reading the file back
  // gives them in the same order.
  std::set<const Factor*> written(contents.factors.begin(),
                                  contents.factors.end());
  written.insert(contents.landmark_factors.begin(),
                 contents.landmark_factors.end());
  for (const auto& [id, f] : graph.factors()) {
    const Factor* factor = &f;
    if (written.count(factor) == 0) continue;
    if (IsLandmarkFactor(factor->type)) {
      AppendLandmarkFactor(*factor, &params, &declarations, &out);
      continue;
    }
    switch (factor->type) {
      case FactorType::kBetweenSE2:
        out += "EDGE_SE2";
        break;
      case FactorType::kBetweenSE3:
        out += "EDGE_SE3:QUAT";
        break;
      case FactorType::kPriorSE2:
        out += "EDGE_PRIOR_SE2";
        break;
      case FactorType::kPriorSE3:
        out += "EDGE_SE3_PRIOR";
        break;
      default:
        break;
    }
    for (const Key& key : factor->keys) {
      out.push_back(' ');
      text::AppendInt(key.id, &out);
    }
    if (factor->type == FactorType::kPriorSE3) out += " 0";  // Offset id.
    AppendValues(factor->measurement.data(),
                 static_cast<int>(factor->measurement.size()), &out);
    AppendUpperTriangle(factor->information, &out);
    out.push_back('\n');
  }
  return WriteFileAtomically(path, declarations + out, error);
}

bool ReadPoseGraph(const std::string& path, const GraphReadOptions& options,
                   Graph* graph, GraphReadReport* report, std::string* error) {
  std::string contents;
  std::string local_error;
  if (!text::ReadWholeFile(path, &contents,
                           error != nullptr ? error : &local_error)) {
    return false;
  }
  // The first tag that only one format uses decides; EDGE2/EDGE3 alone
  // (iSAM's sphere/torus files; TORO files have VERTEX lines) go by the
  // extension: .graph is TORO, anything else iSAM, with a warning.
  Format format = Format::kUnknown;
  bool edges_seen = false;
  text::LineTokenizer lines(contents);
  while ((format == Format::kUnknown || format == Format::kEdges) &&
         lines.Next()) {
    format = FormatOfTag(lines.tokens()[0]);
    edges_seen = edges_seen || format == Format::kEdges;
  }
  const bool toro_extension = LowerExtension(path) == ".graph";
  bool guessed_isam = false;
  if (format == Format::kUnknown || format == Format::kEdges) {
    guessed_isam = edges_seen && !toro_extension;
    format = toro_extension ? Format::kToro
             : edges_seen   ? Format::kIsam
                            : Format::kG2o;
  }
  if (format == Format::kToro) {
    return ReadToroFromText(path, contents, options, graph, report, error);
  }
  if (format == Format::kIsam) {
    if (!ReadIsamFromText(path, contents, options, graph, report, error)) {
      return false;
    }
    if (guessed_isam && report != nullptr) {
      report->warnings.push_back(
          path +
          ": EDGE2/EDGE3 lines without VERTEX lines read as iSAM's format "
          "(square-root information); name the file .graph to read it as "
          "TORO (information)");
    }
    return true;
  }
  return ReadG2oFromText(path, contents, options, graph, report, error);
}

bool WritePoseGraph(const std::string& path, const Graph& graph,
                    std::string* error) {
  if (LowerExtension(path) == ".graph") return WriteToro(path, graph, error);
  return WriteG2o(path, graph, error);
}

}  // namespace slam
