#include "datasets/text_util.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

#include "core/information.h"
#include "core/initialization.h"
#include "core/lie.h"
#include "factors/landmark_factors.h"
#include "factors/landmark_init.h"
#include "factors/pose_factors.h"

namespace slam::text {
namespace {

// Distinct unknown tags reported one by one; the rest are summed up.
constexpr size_t kMaxUnknownTagWarnings = 20;

inline bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::string ErrnoText(int err) { return std::strerror(err); }

enum class NumberStatus { kOk, kBad, kNonFinite, kOutOfRange };

}  // namespace

bool ReadWholeFile(const std::string& path, std::string* contents,
                   std::string* error, size_t max_bytes) {
  // O_NONBLOCK: opening a FIFO that has no writer would block until one
  // comes; reading it then ends at once (cleared below for the reads).
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    *error = path + ": cannot open: " + ErrnoText(errno);
    return false;
  }
  struct stat st;
  int err = 0;
  if (::fstat(fd, &st) != 0) {
    err = errno;
  } else if (S_ISDIR(st.st_mode)) {
    err = EISDIR;
  } else {
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags < 0 || ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0) {
      err = errno;
    }
  }
  if (err != 0) {
    ::close(fd);
    *error = path + ": cannot open: " + ErrnoText(err);
    return false;
  }
  const bool regular = S_ISREG(st.st_mode);
  if (regular && static_cast<uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    *error = path + ": larger than " + std::to_string(max_bytes) + " bytes";
    return false;
  }
  // A pipe or device has no size to check: it is read up to a bound
  // (/dev/zero never ends).
  if (!regular) max_bytes = std::min(max_bytes, kMaxStreamedBytes);
  contents->clear();
  if (regular && st.st_size > 0) {
    contents->reserve(static_cast<size_t>(st.st_size));
  }
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0) {
      if (errno == EINTR) continue;
      err = errno;
      ::close(fd);
      *error = path + ": cannot open: read failed: " + ErrnoText(err);
      return false;
    }
    if (n == 0) break;
    if (static_cast<size_t>(n) > max_bytes - contents->size()) {
      ::close(fd);
      contents->clear();
      *error = path + ": larger than " + std::to_string(max_bytes) + " bytes";
      return false;
    }
    contents->append(buffer, static_cast<size_t>(n));
  }
  ::close(fd);
  if (S_ISFIFO(st.st_mode) && contents->empty()) {
    *error = path + ": a FIFO with no writer (nothing to read)";
    return false;
  }
  return true;
}

bool LineTokenizer::Next() {
  tokens_.clear();
  while (pos_ < text_.size()) {
    const char* begin = text_.data() + pos_;
    const size_t remaining = text_.size() - pos_;
    const void* nl = std::memchr(begin, '\n', remaining);
    const size_t length =
        nl != nullptr
            ? static_cast<size_t>(static_cast<const char*>(nl) - begin)
            : remaining;
    pos_ += length + 1;  // May step past the end; the loop test handles it.
    ++line_;
    size_t k = 0;
    while (k < length) {
      while (k < length && IsSpace(begin[k])) ++k;
      if (k >= length || begin[k] == '#') break;
      const size_t start = k;
      while (k < length && !IsSpace(begin[k])) ++k;
      tokens_.emplace_back(begin + start, k - start);
    }
    if (!tokens_.empty()) return true;
  }
  pos_ = text_.size();
  return false;
}

namespace {

// Strips one leading '+' (from_chars does not accept it); false if what is
// left is empty or starts with another sign.
bool StripPlus(std::string_view* token) {
  if (token->empty() || (*token)[0] != '+') return !token->empty();
  token->remove_prefix(1);
  return !token->empty() && (*token)[0] != '+' && (*token)[0] != '-';
}

NumberStatus ParseDoubleStatus(std::string_view token, double* value) {
  if (!StripPlus(&token)) return NumberStatus::kBad;
  double v = 0.0;
  const char* last = token.data() + token.size();
  const std::from_chars_result r = std::from_chars(token.data(), last, v);
  if (r.ptr != last) return NumberStatus::kBad;
  if (r.ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (r.ec != std::errc()) return NumberStatus::kBad;
  if (!std::isfinite(v)) return NumberStatus::kNonFinite;
  *value = v;
  return NumberStatus::kOk;
}

}  // namespace

bool ParseDouble(std::string_view token, double* value) {
  return ParseDoubleStatus(token, value) == NumberStatus::kOk;
}

bool ParseInt64(std::string_view token, int64_t* value) {
  if (!StripPlus(&token)) return false;
  int64_t v = 0;
  const char* last = token.data() + token.size();
  const std::from_chars_result r = std::from_chars(token.data(), last, v);
  if (r.ec != std::errc() || r.ptr != last) return false;
  *value = v;
  return true;
}

std::string Printable(std::string_view token) {
  constexpr size_t kMax = 40;
  std::string out;
  for (size_t i = 0; i < token.size() && i < kMax; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    out.push_back(c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?');
  }
  if (token.size() > kMax) out += "...";
  return out;
}

bool CheckFieldCount(const std::vector<std::string_view>& tokens,
                     size_t expected, std::string* problem) {
  const size_t found = tokens.size() - 1;
  if (found == expected) return true;
  *problem = Printable(tokens[0]) + " needs " + std::to_string(expected) +
             " fields after the tag, found " + std::to_string(found) +
             (found < expected ? " (missing fields)" : " (extra fields)");
  return false;
}

bool CheckMinFieldCount(const std::vector<std::string_view>& tokens,
                        size_t minimum, std::string* problem) {
  const size_t found = tokens.size() - 1;
  if (found >= minimum) return true;
  *problem = Printable(tokens[0]) + " needs at least " +
             std::to_string(minimum) + " field(s) after the tag, found " +
             std::to_string(found) + " (missing fields)";
  return false;
}

bool ParseDoubles(const std::vector<std::string_view>& tokens, size_t first,
                  size_t n, double* out, std::string* problem) {
  for (size_t k = 0; k < n; ++k) {
    const std::string_view token = tokens[first + k];
    const NumberStatus status = ParseDoubleStatus(token, &out[k]);
    if (status != NumberStatus::kOk) {
      const char* what = status == NumberStatus::kNonFinite    ? "non-finite"
                         : status == NumberStatus::kOutOfRange ? "out-of-range"
                                                               : "bad";
      *problem = std::string(what) + " number '" + Printable(token) +
                 "' in field " + std::to_string(first + k) + " of " +
                 Printable(tokens[0]);
      return false;
    }
  }
  return true;
}

bool ParseId(const std::vector<std::string_view>& tokens, size_t index,
             int64_t* id, std::string* problem) {
  if (ParseInt64(tokens[index], id)) return true;
  *problem = "bad vertex id '" + Printable(tokens[index]) + "' in field " +
             std::to_string(index) + " of " + Printable(tokens[0]);
  return false;
}

void AppendDouble(double value, std::string* out) {
  char buffer[64];
  const std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, r.ptr);
}

void AppendInt(int64_t value, std::string* out) {
  char buffer[32];
  const std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, r.ptr);
}

double WrapAngle(double angle) {
  if (angle >= -M_PI && angle < M_PI) return angle;
  return NormalizeAngle(angle);
}

bool UnitQuaternion(double x, double y, double z, double w,
                    Eigen::Quaterniond* q) {
  const Eigen::Quaterniond raw(w, x, y, z);
  const double squared_norm = raw.squaredNorm();
  if (!std::isfinite(squared_norm) || !(squared_norm > 0.0)) return false;
  if (std::abs(squared_norm - 1.0) <= kUnitQuaternionTolerance) {
    *q = raw;
    return true;
  }
  // Scale first so that huge or tiny inputs do not overflow or underflow.
  const double scale = raw.coeffs().cwiseAbs().maxCoeff();
  Eigen::Quaterniond scaled;
  scaled.coeffs() = raw.coeffs() / scale;
  *q = scaled.normalized();
  return std::isfinite(q->squaredNorm());
}

namespace {

bool CollectLandmarks(const std::string& path, const Graph& graph,
                      PoseGraphContents* contents, std::string* error) {
  const NodeKind pose_kind =
      contents->dimension == 3 ? NodeKind::kPose3 : NodeKind::kPose2;
  const NodeKind point_kind =
      contents->dimension == 3 ? NodeKind::kPoint3 : NodeKind::kPoint2;
  for (const auto& [key, node] : graph.nodes()) {
    if (key.kind != NodeKind::kPoint2 && key.kind != NodeKind::kPoint3) {
      continue;
    }
    if (key.kind != point_kind || contents->dimension == 0) {
      *error = path + ": landmark " + key.ToString() +
               " does not match the dimension of the poses";
      return false;
    }
    if (node->fixed && graph.HasNode(Key(pose_kind, key.id))) {
      *error = path + ": landmark " + key.ToString() +
               " is fixed and has the id of a pose: a FIX line cannot say "
               "which of the two is meant";
      return false;
    }
    for (double v : node->value) {
      if (!std::isfinite(v)) {
        *error = path + ": node " + key.ToString() + " has a non-finite value";
        return false;
      }
    }
    contents->points.push_back(node.get());
  }
  for (const auto& [id, factor] : graph.factors()) {
    if (!IsLandmarkFactor(factor.type)) continue;
    const std::string name = std::string("factor ") + std::to_string(id) +
                             " (" + FactorTypeName(factor.type) + ")";
    Factor check;
    std::string problem;
    if (!RemakeLandmarkFactor(factor, &check, &problem) ||
        factor.keys[0].kind != pose_kind || factor.keys[1].kind != point_kind) {
      *error = path + ": " + name + " is malformed" +
               (problem.empty() ? "" : ": " + problem);
      return false;
    }
    contents->landmark_factors.push_back(&factor);
  }
  return true;
}

}  // namespace

bool CollectPoseGraph(const std::string& path, const Graph& graph,
                      PoseGraphContents* contents, std::string* error) {
  *contents = PoseGraphContents();
  bool has2 = false, has3 = false;
  for (const auto& [key, node] : graph.nodes()) {
    if (key.kind != NodeKind::kPose2 && key.kind != NodeKind::kPose3) continue;
    (key.kind == NodeKind::kPose2 ? has2 : has3) = true;
    const size_t size = key.kind == NodeKind::kPose2 ? 3 : 7;
    if (node->value.size() != size) {
      *error = path + ": node " + key.ToString() + " has " +
               std::to_string(node->value.size()) + " values";
      return false;
    }
    for (double v : node->value) {
      if (!std::isfinite(v)) {
        *error = path + ": node " + key.ToString() + " has a non-finite value";
        return false;
      }
    }
    contents->nodes.push_back(node.get());
  }
  if (has2 && has3) {
    *error = path + ": the graph has both SE(2) and SE(3) pose nodes";
    return false;
  }
  contents->dimension = has3 ? 3 : (has2 ? 2 : 0);
  const NodeKind kind = has3 ? NodeKind::kPose3 : NodeKind::kPose2;
  const int n = has3 ? 6 : 3;
  for (const auto& [id, factor] : graph.factors()) {
    const bool between = factor.type == FactorType::kBetweenSE2 ||
                         factor.type == FactorType::kBetweenSE3;
    const bool prior = factor.type == FactorType::kPriorSE2 ||
                       factor.type == FactorType::kPriorSE3;
    if (!between && !prior) continue;
    const bool is3 = factor.type == FactorType::kBetweenSE3 ||
                     factor.type == FactorType::kPriorSE3;
    const std::string name = std::string("factor ") + std::to_string(id) +
                             " (" + FactorTypeName(factor.type) + ")";
    bool ok = contents->dimension == (is3 ? 3 : 2) &&
              factor.keys.size() == (between ? 2u : 1u) &&
              factor.measurement.size() == (is3 ? 7 : 3) &&
              factor.information.rows() == n && factor.information.cols() == n;
    for (const Key& key : factor.keys) {
      ok = ok && key.kind == kind && graph.HasNode(key);
    }
    if (!ok) {
      *error = path + ": " + name + " is malformed";
      return false;
    }
    if (!factor.measurement.allFinite() || !factor.information.allFinite()) {
      *error = path + ": " + name + " has a non-finite number";
      return false;
    }
    contents->has_prior = contents->has_prior || prior;
    contents->factors.push_back(&factor);
  }
  return CollectLandmarks(path, graph, contents, error);
}

// ---------------------------------------------------------------------------
// PoseGraphBuilder

PoseGraphBuilder::PoseGraphBuilder(const std::string& name,
                                   const GraphReadOptions& options)
    : name_(name), options_(options) {}

std::string PoseGraphBuilder::LineError(int64_t line,
                                        const std::string& problem) const {
  return name_ + ":" + std::to_string(line) + ": " + problem;
}

Key PoseGraphBuilder::MakeKey(int64_t id) const {
  return dimension_ == 3 ? Pose3Key(id) : Pose2Key(id);
}

bool PoseGraphBuilder::SetDimension(int64_t line, int dimension,
                                    std::string* error) {
  if (dimension_ == 0) {
    dimension_ = dimension;
    dimension_line_ = line;
    return true;
  }
  if (dimension_ == dimension) return true;
  *error = LineError(
      line, std::string("the file mixes SE(2) and SE(3) records (") +
                (dimension_ == 2 ? "SE(2)" : "SE(3)") + " record at line " +
                std::to_string(dimension_line_) + ")");
  return false;
}

bool PoseGraphBuilder::CheckEdgeIds(int64_t line, int64_t i, int64_t j,
                                    std::string* error) {
  if (i != j) return true;
  *error = LineError(line, "self-edge: vertex id " + std::to_string(i) +
                               " is joined to itself");
  return false;
}

bool PoseGraphBuilder::AddVertex(int64_t line, int64_t id,
                                 std::vector<double> value,
                                 std::string* error) {
  const auto [it, inserted] = vertex_lines_.emplace(id, line);
  if (!inserted) {
    *error = LineError(line, "duplicate vertex id " + std::to_string(id) +
                                 " (first defined at line " +
                                 std::to_string(it->second) + ")");
    return false;
  }
  vertices_.emplace_back(id, std::move(value));
  return true;
}

bool PoseGraphBuilder::AddVertexSE2(int64_t line, int64_t id, double x,
                                    double y, double theta,
                                    std::string* error) {
  if (!SetDimension(line, 2, error)) return false;
  return AddVertex(line, id, {x, y, WrapAngle(theta)}, error);
}

bool PoseGraphBuilder::AddVertexSE3(int64_t line, int64_t id,
                                    const Eigen::Vector3d& t,
                                    const Eigen::Vector4d& q_xyzw,
                                    std::string* error) {
  if (!SetDimension(line, 3, error)) return false;
  Eigen::Quaterniond q;
  if (!UnitQuaternion(q_xyzw[0], q_xyzw[1], q_xyzw[2], q_xyzw[3], &q)) {
    *error = LineError(line, "quaternion of vertex " + std::to_string(id) +
                                 " has zero length");
    return false;
  }
  return AddVertex(line, id, {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()},
                   error);
}

template <int N>
bool PoseGraphBuilder::CheckInformation(
    int64_t line, Eigen::Matrix<double, N, N>* information,
    std::string* error) {
  if (IsPositiveDefinite(*information)) return true;
  if (!options_.repair_information) {
    *error = LineError(line,
                       "information matrix is not positive definite (the "
                       "repair_information option, slam optimize "
                       "--repair_information, replaces such matrices by the "
                       "nearest positive definite ones)");
    return false;
  }
  const Eigen::MatrixXd repaired = NearestPositiveDefinite(*information);
  if (!IsPositiveDefinite(repaired)) {
    *error = LineError(line,
                       "information matrix is not positive definite "
                       "and cannot be repaired");
    return false;
  }
  *information = repaired;
  ++repaired_;
  return true;
}

template bool PoseGraphBuilder::CheckInformation<2>(
    int64_t, Eigen::Matrix<double, 2, 2>*, std::string*);
template bool PoseGraphBuilder::CheckInformation<3>(
    int64_t, Eigen::Matrix<double, 3, 3>*, std::string*);

bool PoseGraphBuilder::AddBetweenSE2(int64_t line, int64_t i, int64_t j,
                                     double x, double y, double theta,
                                     const Eigen::Matrix3d& information,
                                     std::string* error) {
  ++edges_;
  if (!SetDimension(line, 2, error) || !CheckEdgeIds(line, i, j, error)) {
    return false;
  }
  Eigen::Matrix3d info = information;
  if (!CheckInformation<3>(line, &info, error)) return false;
  // Not Pose2(x, y, theta): it would re-wrap in-range angles.
  Pose2 z;
  z.t = Eigen::Vector2d(x, y);
  z.theta = WrapAngle(theta);
  return QueueFactor(
      line,
      [&](Factor* factor, std::string* problem) {
        return MakeBetweenSE2(Pose2Key(i), Pose2Key(j), z, info, factor,
                              problem);
      },
      error);
}

bool PoseGraphBuilder::AddBetweenSE3(
    int64_t line, int64_t i, int64_t j, const Eigen::Vector3d& t,
    const Eigen::Vector4d& q_xyzw,
    const Eigen::Matrix<double, 6, 6>& information, std::string* error) {
  ++edges_;
  if (!SetDimension(line, 3, error) || !CheckEdgeIds(line, i, j, error)) {
    return false;
  }
  Eigen::Matrix<double, 6, 6> info = information;
  if (!CheckInformation<6>(line, &info, error)) return false;
  // Not Pose3(t, q): it would renormalize unit quaternions.
  Pose3 z;
  z.t = t;
  if (!UnitQuaternion(q_xyzw[0], q_xyzw[1], q_xyzw[2], q_xyzw[3], &z.q)) {
    *error = LineError(line, "edge quaternion has zero length");
    return false;
  }
  return QueueFactor(
      line,
      [&](Factor* factor, std::string* problem) {
        return MakeBetweenSE3(Pose3Key(i), Pose3Key(j), z, info, factor,
                              problem);
      },
      error);
}

bool PoseGraphBuilder::AddPriorSE2(int64_t line, int64_t id, double x, double y,
                                   double theta,
                                   const Eigen::Matrix3d& information,
                                   std::string* error) {
  ++edges_;
  if (!SetDimension(line, 2, error)) return false;
  Eigen::Matrix3d info = information;
  if (!CheckInformation<3>(line, &info, error)) return false;
  Pose2 z;
  z.t = Eigen::Vector2d(x, y);
  z.theta = WrapAngle(theta);
  return QueueFactor(
      line,
      [&](Factor* factor, std::string* problem) {
        return MakePriorSE2(Pose2Key(id), z, info, factor, problem);
      },
      error);
}

bool PoseGraphBuilder::AddPriorSE3(
    int64_t line, int64_t id, const Eigen::Vector3d& t,
    const Eigen::Vector4d& q_xyzw,
    const Eigen::Matrix<double, 6, 6>& information, std::string* error) {
  ++edges_;
  if (!SetDimension(line, 3, error)) return false;
  Eigen::Matrix<double, 6, 6> info = information;
  if (!CheckInformation<6>(line, &info, error)) return false;
  Pose3 z;
  z.t = t;
  if (!UnitQuaternion(q_xyzw[0], q_xyzw[1], q_xyzw[2], q_xyzw[3], &z.q)) {
    *error = LineError(line, "prior quaternion has zero length");
    return false;
  }
  return QueueFactor(
      line,
      [&](Factor* factor, std::string* problem) {
        return MakePriorSE3(Pose3Key(id), z, info, factor, problem);
      },
      error);
}

bool PoseGraphBuilder::AddVertexPoint(int64_t line, int64_t id,
                                      const Eigen::VectorXd& p,
                                      std::string* error) {
  if (!SetDimension(line, static_cast<int>(p.size()), error)) return false;
  const auto [it, inserted] = point_lines_.emplace(id, line);
  if (!inserted) {
    *error = LineError(line, "duplicate vertex id " + std::to_string(id) +
                                 " (first defined at line " +
                                 std::to_string(it->second) + ")");
    return false;
  }
  points_.emplace_back(id, std::vector<double>(p.data(), p.data() + p.size()));
  return true;
}

void PoseGraphBuilder::AddFix(int64_t line, int64_t id) {
  fixes_.emplace_back(line, id);
}

bool PoseGraphBuilder::UnknownTag(int64_t line, std::string_view tag,
                                  std::string* error) {
  if (!options_.skip_unknown_tags) {
    *error = LineError(line, "unknown tag '" + Printable(tag) +
                                 "' (a misspelt tag? --skip_unknown_tags "
                                 "skips lines with tags not read, as g2o "
                                 "does)");
    return false;
  }
  SkipTag(tag);
  return true;
}

void PoseGraphBuilder::SkipTag(std::string_view tag) {
  for (auto& [name, count] : unknown_tags_) {
    if (name == tag) {
      ++count;
      return;
    }
  }
  if (unknown_tags_.size() < kMaxUnknownTagWarnings) {
    unknown_tags_.emplace_back(std::string(tag), 1);
    return;
  }
  // Past the limit every further tag is summed up in one last entry.
  if (unknown_tags_.size() == kMaxUnknownTagWarnings) {
    unknown_tags_.emplace_back(std::string(), 0);
  }
  ++unknown_tags_.back().second;
}

bool PoseGraphBuilder::Finish(Graph* graph, GraphReadReport* report,
                              std::string* error) {
  if (graph->NumNodes() != 0 || graph->NumFactors() != 0) {
    *error = name_ + ": the graph to read into is not empty";
    return false;
  }
  if (vertices_.empty() && points_.empty() && factors_.empty() &&
      fixes_.empty()) {
    *error = name_ + ": no records (the file is empty" +
             (unknown_tags_.empty() ? std::string(" or only comments")
                                    : std::string(" but for skipped tags")) +
             "): nothing to read";
    return false;
  }
  Graph result;
  for (const auto& [id, value] : vertices_) {
    if (result.AddNode(MakeKey(id), value) == nullptr) {
      *error = LineError(vertex_lines_.at(id),
                         "cannot add vertex " + std::to_string(id));
      return false;
    }
  }
  for (const auto& [id, value] : points_) {
    const Key key = dimension_ == 3 ? Point3Key(id) : Point2Key(id);
    if (result.AddNode(key, value) == nullptr) {
      *error = LineError(point_lines_.at(id),
                         "cannot add vertex " + std::to_string(id));
      return false;
    }
  }
  const bool has_vertices = !vertices_.empty();
  std::set<Key> missing_points;
  const std::vector<double> identity =
      dimension_ == 3 ? std::vector<double>{0, 0, 0, 0, 0, 0, 1}
                      : std::vector<double>{0, 0, 0};
  std::set<Key> missing;
  for (PendingFactor& pending : factors_) {
    for (const Key& key : pending.factor.keys) {
      const bool is_point =
          key.kind == NodeKind::kPoint2 || key.kind == NodeKind::kPoint3;
      // Shared id space (iSAM): a pose id used as a landmark, or the reverse.
      const Key other =
          is_point ? MakeKey(key.id)
                   : (dimension_ == 3 ? Point3Key(key.id) : Point2Key(key.id));
      if (shared_id_space_ && result.HasNode(other)) {
        *error =
            LineError(pending.line,
                      "id " + std::to_string(key.id) + " is used as " +
                          (is_point ? "a landmark" : "a pose") + " and as " +
                          (is_point ? "a pose" : "a landmark"));
        return false;
      }
      if (result.HasNode(key)) continue;
      if (is_point) {
        result.AddNode(key, std::vector<double>(dimension_ == 3 ? 3 : 2, 0.0));
        missing_points.insert(key);
        continue;
      }
      if (has_vertices && !options_.allow_missing_vertices) {
        *error = LineError(pending.line,
                           "unknown vertex id " + std::to_string(key.id));
        return false;
      }
      result.AddNode(key, identity);
      missing.insert(key);
    }
    if (result.AddFactor(std::move(pending.factor)) < 0) {
      *error = LineError(pending.line, "cannot add the edge to the graph");
      return false;
    }
  }
  int fixed = 0;
  for (const auto& [line, id] : fixes_) {
    Node* node = dimension_ == 0 ? nullptr : result.FindNode(MakeKey(id));
    if (node == nullptr && dimension_ != 0) {
      node = result.FindNode(dimension_ == 3 ? Point3Key(id) : Point2Key(id));
    }
    if (node == nullptr) {
      *error =
          LineError(line, "FIX of unknown vertex id " + std::to_string(id));
      return false;
    }
    if (!node->fixed) ++fixed;
    node->fixed = true;
  }
  if (!missing.empty()) {
    std::string problem;
    if (!InitializePoses(&result, InitMethod::kSpanningTree, &problem,
                         &missing)) {
      *error =
          name_ + ": cannot initialize the vertices from the edges: " + problem;
      return false;
    }
  }
  if (!missing_points.empty()) {
    const LandmarkInitReport init =
        InitializeLandmarks(&result, &missing_points);
    if (init.failed > 0) {
      *error = name_ + ": cannot initialize " + std::to_string(init.failed) +
               " landmark(s) from their observations";
      return false;
    }
  }
  if (report != nullptr) {
    report->vertices = static_cast<int>(vertices_.size() + points_.size());
    report->landmarks_initialized = static_cast<int>(missing_points.size());
    report->edges = edges_;
    report->fixed = fixed;
    report->repaired_information = repaired_;
    report->initialized_from_edges = !missing.empty();
    for (const auto& [tag, count] : unknown_tags_) {
      const std::string lines =
          std::to_string(count) + (count == 1 ? " line" : " lines");
      report->warnings.push_back(
          tag.empty()
              ? "further unknown tags (" + lines + ") skipped"
              : "unknown tag '" + Printable(tag) + "' (" + lines + ") skipped");
    }
  }
  *graph = std::move(result);
  return true;
}

bool ParseRecords(std::string_view text, const PoseGraphBuilder& builder,
                  const RecordParser& parse, std::string* error) {
  LineTokenizer lines(text);
  std::string problem;
  while (lines.Next()) {
    problem.clear();
    if (!parse(lines.tokens(), lines.line(), &problem, error)) {
      if (!problem.empty()) *error = builder.LineError(lines.line(), problem);
      return false;
    }
  }
  return true;
}

}  // namespace slam::text
