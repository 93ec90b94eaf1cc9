// Helpers shared by the text pose-graph readers and writers (g2o_io.cc,
// toro_io.cc): whole-file reading, a fast line tokenizer, strict number
// parsing, round-trip number printing, atomic file replacement, and the builder
// that turns parsed records into a Graph with the checks and the
// initialization common to both formats.
#ifndef SLAM_DATASETS_TEXT_UTIL_H_
#define SLAM_DATASETS_TEXT_UTIL_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/graph.h"
#include "core/keys.h"
#include "datasets/g2o_io.h"

namespace slam::text {

// Reads the whole file into *contents. Error: "PATH: cannot open: reason",
// or "PATH: larger than N bytes" past max_bytes (a bound for inputs that
// must be small, such as configs; every reader passes what its format can
// plausibly need). A pipe or device (/dev/stdin, /dev/zero: no size known
// in advance) is read up to min(max_bytes, kMaxStreamedBytes); a FIFO is
// opened without waiting for a writer, and one without a writer is an error
// (nothing to read), never a hang.
constexpr size_t kMaxStreamedBytes = size_t{256} << 20;  // 256 MiB.
bool ReadWholeFile(const std::string& path, std::string* contents,
                   std::string* error, size_t max_bytes = SIZE_MAX);

// Splits text into lines ('\n'; a trailing '\r' is whitespace) and each line
// into tokens separated by spaces, tabs, '\r', '\v' or '\f'. A token starting
// with '#' starts a comment that runs to the end of the line. A UTF-8 byte
// order mark at the start of the text is skipped.
// 3 if `text` starts with a UTF-8 byte order mark (skipped by every reader),
// else 0.
inline size_t Utf8BomLength(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
}

class LineTokenizer {
 public:
  explicit LineTokenizer(std::string_view text)
      : text_(text), pos_(Utf8BomLength(text)) {}
  // A later piece of a text read in pieces (whole lines), after
  // `lines_before` lines: numbering goes on from there, no mark is skipped.
  LineTokenizer(std::string_view text, int64_t lines_before)
      : text_(text),
        pos_(lines_before == 0 ? Utf8BomLength(text) : 0),
        line_(lines_before) {}

  // Advances to the next line with at least one token; false at the end.
  bool Next();
  // 1-based number of the current line.
  int64_t line() const { return line_; }
  const std::vector<std::string_view>& tokens() const { return tokens_; }

 private:
  std::string_view text_;
  size_t pos_;
  int64_t line_ = 0;
  std::vector<std::string_view> tokens_;
};

// Strict parsers: the whole token must be a number ("1.2.3", "abc", "1e" are
// rejected; one leading '+' is accepted). ParseDouble rejects nan, inf and
// values out of the double range.
bool ParseDouble(std::string_view token, double* value);
bool ParseInt64(std::string_view token, int64_t* value);

// A token made safe for an error message: at most 40 characters, control and
// non-ASCII bytes replaced by '?'.
std::string Printable(std::string_view token);

// Checks that `tag` has `expected` fields after it; otherwise sets *problem
// ("EDGE_SE2 needs 11 fields after the tag, found 10 (missing fields)").
bool CheckFieldCount(const std::vector<std::string_view>& tokens,
                     size_t expected, std::string* problem);
// Same with a minimum (for FIX id [id ...]).
bool CheckMinFieldCount(const std::vector<std::string_view>& tokens,
                        size_t minimum, std::string* problem);

// Parses tokens[first], ..., tokens[first + n - 1] into out[0..n-1];
// otherwise sets *problem naming the field (1-based, after the tag).
bool ParseDoubles(const std::vector<std::string_view>& tokens, size_t first,
                  size_t n, double* out, std::string* problem);
bool ParseId(const std::vector<std::string_view>& tokens, size_t index,
             int64_t* id, std::string* problem);

// Appends the shortest decimal that reads back as the same double, bit for
// bit (std::to_chars without a precision: 0.05, not %.17g's
// 0.050000000000000003; up to 17 digits where needed; an integer when the
// value is one; exponent notation when shorter).
void AppendDouble(double value, std::string* out);
void AppendInt(int64_t value, std::string* out);

// Angle wrapped to [-pi, pi); angles already in range are returned as they
// are (NormalizeAngle may move the last bit of values close to pi).
double WrapAngle(double angle);

// Unit quaternion from (x, y, z, w) as read from a file: kept bit for bit if
// its squared norm is within kUnitQuaternionTolerance of 1, else divided by
// its norm. False if the norm is zero or not finite.
constexpr double kUnitQuaternionTolerance = 2e-15;
bool UnitQuaternion(double x, double y, double z, double w,
                    Eigen::Quaterniond* q);

// The parts of a graph the pose-graph writers write, checked: SE(2) or SE(3)
// pose nodes (not both) with finite values, in key order, and the
// between/prior factors over them with well-formed, finite measurements and
// information matrices, in FactorId order. Other nodes and factors are left
// out. Errors: "PATH: problem".
struct PoseGraphContents {
  int dimension = 0;  // 2, 3, or 0 for a graph without pose nodes.
  std::vector<const Node*> nodes;
  std::vector<const Factor*> factors;
  bool has_prior = false;
  // Landmark point nodes (kPoint2 in 2D, kPoint3 in 3D) in key order and the
  // landmark/camera factors (factors/landmark_factors.h) in FactorId order,
  // checked like the rest. Poses and points have separate id spaces (the
  // tags say which is meant), except in FIX lines: a fixed point whose id is
  // also a pose id is an error.
  std::vector<const Node*> points;
  std::vector<const Factor*> landmark_factors;
};
bool CollectPoseGraph(const std::string& path, const Graph& graph,
                      PoseGraphContents* contents, std::string* error);

// Builds a pose graph from the records of a file, in file order, with the
// checks common to the g2o and TORO readers. Every Add* call names the line
// of the record; on failure it sets *error to "NAME:LINE: problem".
class PoseGraphBuilder {
 public:
  PoseGraphBuilder(const std::string& name, const GraphReadOptions& options);

  // Vertex values: SE(2) (x, y, theta); SE(3) t and q (any non-zero norm).
  bool AddVertexSE2(int64_t line, int64_t id, double x, double y, double theta,
                    std::string* error);
  bool AddVertexSE3(int64_t line, int64_t id, const Eigen::Vector3d& t,
                    const Eigen::Vector4d& q_xyzw, std::string* error);
  // Between and prior edges with the measurement and the information in our
  // factors' conventions (symmetric; checked for positive definiteness).
  bool AddBetweenSE2(int64_t line, int64_t i, int64_t j, double x, double y,
                     double theta, const Eigen::Matrix3d& information,
                     std::string* error);
  bool AddBetweenSE3(int64_t line, int64_t i, int64_t j,
                     const Eigen::Vector3d& t, const Eigen::Vector4d& q_xyzw,
                     const Eigen::Matrix<double, 6, 6>& information,
                     std::string* error);
  bool AddPriorSE2(int64_t line, int64_t id, double x, double y, double theta,
                   const Eigen::Matrix3d& information, std::string* error);
  bool AddPriorSE3(int64_t line, int64_t id, const Eigen::Vector3d& t,
                   const Eigen::Vector4d& q_xyzw,
                   const Eigen::Matrix<double, 6, 6>& information,
                   std::string* error);
  // Landmark ids: by default poses and landmarks have separate id spaces
  // (GTSAM's reading of g2o and TORO files, whose examples reuse pose ids
  // for landmarks: the tag or the field position says which is meant). With
  // a shared id space (iSAM) an id used for both is an error.
  void set_shared_id_space(bool shared) { shared_id_space_ = shared; }
  // Landmark vertex (2 values: Point2, 3: Point3).
  bool AddVertexPoint(int64_t line, int64_t id, const Eigen::VectorXd& p,
                      std::string* error);
  // A landmark or camera factor from pose `pose_id` to point `point_id` in
  // `dimension` (2 or 3); make(pose_key, point_key, &factor, &problem)
  // builds it (factors/landmark_factors.h). Points without a vertex line are
  // created and initialized from their observations in Finish
  // (factors/landmark_init.h), whatever allow_missing_vertices says.
  template <typename Make>
  bool AddLandmarkFactor(int64_t line, int dimension, int64_t pose_id,
                         int64_t point_id, Make make, std::string* error) {
    ++edges_;
    if (!SetDimension(line, dimension, error)) return false;
    const Key pose = MakeKey(pose_id);
    const Key point =
        dimension == 3 ? Point3Key(point_id) : Point2Key(point_id);
    return QueueFactor(
        line,
        [&](Factor* factor, std::string* problem) {
          return make(pose, point, factor, problem);
        },
        error);
  }
  // Repairs or rejects an information matrix that is not positive definite.
  template <int N>
  bool CheckInformation(int64_t line, Eigen::Matrix<double, N, N>* information,
                        std::string* error);
  // FIX of one id; resolved in Finish.
  void AddFix(int64_t line, int64_t id);
  // A line whose tag the reader does not know: an error ("NAME:LINE: unknown
  // tag"), or counted and skipped with options.skip_unknown_tags.
  bool UnknownTag(int64_t line, std::string_view tag, std::string* error);
  // A line of the format that the reader does not read (TORO's EQUIV):
  // counted and skipped with a warning.
  void SkipTag(std::string_view tag);

  // Creates the nodes, the factors, applies the FIX lines, initializes the
  // nodes without vertex, fills the report and moves the result into *graph
  // (which must be empty). A file without a single record (empty, only
  // comments or skipped tags) is an error: there is nothing to do.
  bool Finish(Graph* graph, GraphReadReport* report, std::string* error);

  // "NAME:LINE: problem".
  std::string LineError(int64_t line, const std::string& problem) const;

 private:
  struct PendingFactor {
    int64_t line;
    Factor factor;
  };

  // Records the dimension (2 or 3) of a record; fails on a mix.
  bool SetDimension(int64_t line, int dimension, std::string* error);
  bool CheckEdgeIds(int64_t line, int64_t i, int64_t j, std::string* error);
  bool AddVertex(int64_t line, int64_t id, std::vector<double> value,
                 std::string* error);
  Key MakeKey(int64_t id) const;
  // Queues the factor built by make(&factor, &problem); a failure becomes
  // "NAME:LINE: problem".
  template <typename Make>
  bool QueueFactor(int64_t line, Make make, std::string* error) {
    PendingFactor pending{line, Factor()};
    std::string problem;
    if (!make(&pending.factor, &problem)) {
      *error = LineError(line, problem);
      return false;
    }
    factors_.push_back(std::move(pending));
    return true;
  }

  std::string name_;
  GraphReadOptions options_;
  int dimension_ = 0;  // 0 until the first pose record.
  int64_t dimension_line_ = 0;
  std::vector<std::pair<int64_t, std::vector<double>>> vertices_;
  std::vector<std::pair<int64_t, std::vector<double>>> points_;
  std::unordered_map<int64_t, int64_t> vertex_lines_;  // id -> line.
  std::unordered_map<int64_t, int64_t> point_lines_;   // Landmarks.
  bool shared_id_space_ = false;
  std::vector<PendingFactor> factors_;
  std::vector<std::pair<int64_t, int64_t>> fixes_;             // (line, id).
  std::vector<std::pair<std::string, int64_t>> unknown_tags_;  // Tag, lines.
  int edges_ = 0;
  int repaired_ = 0;
};

// One record parser of a pose-graph reader: parses `tokens` (line `line`)
// into the builder it captures. On failure it sets either *problem (turned
// into "NAME:LINE: problem" by ParseRecords) or *error (already complete).
using RecordParser =
    std::function<bool(const std::vector<std::string_view>& tokens,
                       int64_t line, std::string* problem, std::string* error)>;

// Runs `parse` on every record of `text` in order; false at the first
// failure, with *error set.
bool ParseRecords(std::string_view text, const PoseGraphBuilder& builder,
                  const RecordParser& parse, std::string* error);

}  // namespace slam::text

#endif  // SLAM_DATASETS_TEXT_UTIL_H_
