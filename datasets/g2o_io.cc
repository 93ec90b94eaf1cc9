#include "datasets/g2o_io.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "datasets/toro_io.h"

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

// Per-file state beyond the builder: the declared SE(3) sensor offsets
// (id -> is identity).
struct G2oState {
  std::unordered_map<int64_t, bool> offsets;
};

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
        !ParseId(tokens, 1, &i, problem) ||
        !ParseId(tokens, 2, &j, problem) ||
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
        !ParseId(tokens, 1, &i, problem) ||
        !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 28, v, problem)) {
      return false;
    }
    return builder->AddBetweenSE3(line, i, j,
                                  Eigen::Vector3d(v[0], v[1], v[2]),
                                  Eigen::Vector4d(v[3], v[4], v[5], v[6]),
                                  FromUpperTriangle<6>(v + 7), error);
  }
  if (tag == "EDGE_SE3_PRIOR") {
    if (!CheckFieldCount(tokens, 30, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseId(tokens, 2, &j, problem) ||
        !ParseDoubles(tokens, 3, 28, v, problem)) {
      return false;
    }
    const auto offset = state->offsets.find(j);
    if (offset == state->offsets.end()) {
      *problem = "EDGE_SE3_PRIOR uses PARAMS_SE3OFFSET " + std::to_string(j) +
                 ", which is not declared before it";
      return false;
    }
    if (!offset->second) {
      *problem = "EDGE_SE3_PRIOR with a non-identity PARAMS_SE3OFFSET " +
                 std::to_string(j) + " is not supported";
      return false;
    }
    return builder->AddPriorSE3(line, i, Eigen::Vector3d(v[0], v[1], v[2]),
                                Eigen::Vector4d(v[3], v[4], v[5], v[6]),
                                FromUpperTriangle<6>(v + 7), error);
  }
  if (tag == "PARAMS_SE3OFFSET") {
    if (!CheckFieldCount(tokens, 8, problem) ||
        !ParseId(tokens, 1, &i, problem) ||
        !ParseDoubles(tokens, 2, 7, v, problem)) {
      return false;
    }
    const bool identity = v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0 &&
                          v[3] == 0.0 && v[4] == 0.0 && v[5] == 0.0 &&
                          v[6] != 0.0;
    if (!state->offsets.emplace(i, identity).second) {
      *problem = "duplicate PARAMS_SE3OFFSET id " + std::to_string(i);
      return false;
    }
    return true;
  }
  if (tag == "FIX") {
    if (!CheckMinFieldCount(tokens, 1, problem)) return false;
    for (size_t k = 1; k < tokens.size(); ++k) {
      if (!ParseId(tokens, k, &i, problem)) return false;
      builder->AddFix(line, i);
    }
    return true;
  }
  builder->SkipUnknownTag(tag);
  return true;
}

enum class Format { kUnknown, kG2o, kToro };

Format FormatOfTag(std::string_view tag) {
  if (tag == "VERTEX_SE2" || tag == "EDGE_SE2" || tag == "VERTEX_SE3:QUAT" ||
      tag == "EDGE_SE3:QUAT" || tag == "EDGE_PRIOR_SE2" ||
      tag == "EDGE_SE2_PRIOR" || tag == "EDGE_SE3_PRIOR") {
    return Format::kG2o;
  }
  if (tag == "VERTEX2" || tag == "EDGE2" || tag == "VERTEX3" ||
      tag == "EDGE3" || tag == "VERTEX" || tag == "EDGE") {
    return Format::kToro;
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
  text::LineTokenizer lines(text);
  std::string problem;
  while (lines.Next()) {
    problem.clear();
    if (!ParseLine(lines.tokens(), lines.line(), &builder, &state, &problem,
                   error)) {
      if (!problem.empty()) *error = builder.LineError(lines.line(), problem);
      return false;
    }
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

bool WriteG2o(const std::string& path, const Graph& graph,
              std::string* error) {
  std::string local_error;
  if (error == nullptr) error = &local_error;
  text::PoseGraphContents contents;
  if (!text::CollectPoseGraph(path, graph, &contents, error)) return false;
  const bool is3 = contents.dimension == 3;
  std::string out;
  out.reserve(contents.nodes.size() * (is3 ? 200 : 80) +
              contents.factors.size() * (is3 ? 600 : 220));
  if (is3 && contents.has_prior) out += "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n";
  for (const Node* node : contents.nodes) {
    out += is3 ? "VERTEX_SE3:QUAT " : "VERTEX_SE2 ";
    text::AppendInt(node->key.id, &out);
    AppendValues(node->value.data(), static_cast<int>(node->value.size()),
                 &out);
    out.push_back('\n');
  }
  for (const Node* node : contents.nodes) {
    if (!node->fixed) continue;
    out += "FIX ";
    text::AppendInt(node->key.id, &out);
    out.push_back('\n');
  }
  for (const Factor* factor : contents.factors) {
    switch (factor->type) {
      case FactorType::kBetweenSE2: out += "EDGE_SE2"; break;
      case FactorType::kBetweenSE3: out += "EDGE_SE3:QUAT"; break;
      case FactorType::kPriorSE2: out += "EDGE_PRIOR_SE2"; break;
      case FactorType::kPriorSE3: out += "EDGE_SE3_PRIOR"; break;
      default: break;  // CollectPoseGraph keeps pose factors only.
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
  return WriteFileAtomically(path, out, error);
}

bool ReadPoseGraph(const std::string& path, const GraphReadOptions& options,
                   Graph* graph, GraphReadReport* report, std::string* error) {
  std::string contents;
  std::string local_error;
  if (!text::ReadWholeFile(path, &contents,
                           error != nullptr ? error : &local_error)) {
    return false;
  }
  Format format = Format::kUnknown;
  text::LineTokenizer lines(contents);
  while (format == Format::kUnknown && lines.Next()) {
    format = FormatOfTag(lines.tokens()[0]);
  }
  if (format == Format::kUnknown) {
    format = LowerExtension(path) == ".graph" ? Format::kToro : Format::kG2o;
  }
  if (format == Format::kToro) {
    return ReadToroFromText(path, contents, options, graph, report, error);
  }
  return ReadG2oFromText(path, contents, options, graph, report, error);
}

bool WritePoseGraph(const std::string& path, const Graph& graph,
                    std::string* error) {
  if (LowerExtension(path) == ".graph") return WriteToro(path, graph, error);
  return WriteG2o(path, graph, error);
}

}  // namespace slam
