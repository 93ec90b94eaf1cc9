#include "datasets/trajectory_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <Eigen/SVD>

#include "datasets/atomic_file.h"
#include "datasets/g2o_io.h"
#include "datasets/text_util.h"

namespace slam {
namespace {

constexpr double kMaxSecondsStamp = 1e12;  // Larger: not seconds.

bool ReadWholeFile(const std::string& path, std::string* content,
                   std::string* error) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    *error = path + ": is a directory, not a trajectory file";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = path + ": cannot open (" + std::strerror(errno) + ")";
    return false;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  *content = ss.str();
  return true;
}

// Calls fn(line_number, line) for every line (without '\n' or '\r').
template <typename Fn>
bool ForEachLine(const std::string& content, Fn fn) {
  size_t pos = text::Utf8BomLength(content);  // Skipped as by every reader.
  int line_number = 0;
  while (pos < content.size()) {
    size_t end = content.find('\n', pos);
    if (end == std::string::npos) end = content.size();
    size_t stop = end;
    if (stop > pos && content[stop - 1] == '\r') --stop;
    ++line_number;
    if (!fn(line_number, content.substr(pos, stop - pos))) return false;
    pos = end + 1;
  }
  return true;
}

std::string Trim(const std::string& s) {
  size_t a = 0;
  size_t b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// Blank or '#' comment.
bool IsSkippable(const std::string& line) {
  const std::string t = Trim(line);
  return t.empty() || t[0] == '#';
}

std::vector<std::string> SplitWhitespace(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream ss(line);
  std::string token;
  while (ss >> token) tokens.push_back(token);
  return tokens;
}

std::vector<std::string> SplitCommas(const std::string& line) {
  std::vector<std::string> tokens;
  size_t pos = 0;
  while (true) {
    const size_t comma = line.find(',', pos);
    tokens.push_back(Trim(line.substr(
        pos, comma == std::string::npos ? std::string::npos : comma - pos)));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (!tokens.empty() && tokens.back().empty()) tokens.pop_back();  // "a,b,"
  return tokens;
}

// The readers' strict decimal parser (no hex floats, nan or inf).
bool ParseDouble(const std::string& token, double* value) {
  return text::ParseDouble(token, value);
}

bool ParseInt64(const std::string& token, int64_t* value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(token.c_str(), &end, 10);
  if (end != token.c_str() + token.size() || errno == ERANGE) return false;
  *value = v;
  return true;
}

std::string Where(const std::string& path, int line) {
  return path + ":" + std::to_string(line) + ": ";
}

// Parses tokens[first, first + count) as doubles; names the bad one.
bool ParseValues(const std::vector<std::string>& tokens, size_t first,
                 size_t count, double* out, const std::string& where,
                 std::string* error) {
  for (size_t i = 0; i < count; ++i) {
    if (!ParseDouble(tokens[first + i], &out[i])) {
      *error = where + "field " + std::to_string(first + i + 1) + " ('" +
               text::Printable(tokens[first + i]) + "') is not a finite number";
      return false;
    }
  }
  return true;
}

bool MakeQuaternion(double x, double y, double z, double w,
                    const std::string& where, Eigen::Quaterniond* q,
                    std::string* error) {
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  if (!(norm > 1e-6)) {
    *error = where + "the quaternion has (near) zero length";
    return false;
  }
  *q = Eigen::Quaterniond(w / norm, x / norm, y / norm, z / norm);
  return true;
}

// Stamps must increase strictly; `lines` holds the line of each stamp.
bool CheckIncreasing(const Trajectory& t, const std::vector<int>& lines,
                     const std::string& path, std::string* error) {
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i].stamp <= t[i - 1].stamp) {
      *error = Where(path, lines[i]) + "timestamp " +
               FormatStampSeconds(t[i].stamp) + " s is " +
               (t[i].stamp == t[i - 1].stamp ? "a duplicate of" : "before") +
               " the one on line " + std::to_string(lines[i - 1]) + " (" +
               FormatStampSeconds(t[i - 1].stamp) +
               " s): stamps must increase strictly (sort the file and "
               "remove duplicates)";
      return false;
    }
  }
  return true;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return tail == suffix;
}

bool IsG2oKeyword(const std::string& token) {
  return token.rfind("VERTEX", 0) == 0 || token.rfind("EDGE", 0) == 0 ||
         token == "FIX" || token.rfind("PARAMS", 0) == 0;
}

std::string ResolveEurocPath(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) return path;
  for (const char* sub :
       {"state_groundtruth_estimate0/data.csv",
        "mav0/state_groundtruth_estimate0/data.csv", "data.csv"}) {
    const std::string candidate = path + "/" + sub;
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
  }
  return path;
}

}  // namespace

const char* TrajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kAuto:
      return "auto";
    case TrajectoryFormat::kTum:
      return "tum";
    case TrajectoryFormat::kKitti:
      return "kitti";
    case TrajectoryFormat::kEuroc:
      return "euroc";
    case TrajectoryFormat::kG2o:
      return "g2o";
  }
  return "?";
}

bool ParseTrajectoryFormat(const std::string& name, TrajectoryFormat* format) {
  for (TrajectoryFormat f : {TrajectoryFormat::kAuto, TrajectoryFormat::kTum,
                             TrajectoryFormat::kKitti, TrajectoryFormat::kEuroc,
                             TrajectoryFormat::kG2o}) {
    if (name == TrajectoryFormatName(f)) {
      *format = f;
      return true;
    }
  }
  return false;
}

std::string FormatStampSeconds(TimeNs stamp) {
  const bool negative = stamp < 0;
  // Avoid overflow on INT64_MIN by working with the unsigned magnitude.
  const uint64_t mag = negative ? static_cast<uint64_t>(-(stamp + 1)) + 1
                                : static_cast<uint64_t>(stamp);
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%s%" PRIu64 ".%09" PRIu64,
                negative ? "-" : "", static_cast<uint64_t>(mag / 1000000000ull),
                static_cast<uint64_t>(mag % 1000000000ull));
  return buf;
}

bool ParseStampSeconds(const std::string& text, TimeNs* stamp) {
  if (text.empty()) return false;
  size_t i = 0;
  bool negative = false;
  if (text[0] == '-' || text[0] == '+') {
    negative = text[0] == '-';
    i = 1;
  }
  int64_t whole = 0;
  int64_t frac = 0;
  int frac_digits = 0;
  bool round_up = false;
  bool any_digit = false;
  bool plain = true;
  for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]));
       ++i) {
    any_digit = true;
    whole = whole * 10 + (text[i] - '0');
    // Checked after the digit (fuzzing: "74480544800" overflowed below).
    if (whole > 9000000000ll) {
      plain = false;  // Too large for nanoseconds in int64.
      break;
    }
  }
  if (plain && i < text.size() && text[i] == '.') {
    ++i;
    for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]));
         ++i) {
      any_digit = true;
      if (frac_digits < 9) {
        frac = frac * 10 + (text[i] - '0');
        ++frac_digits;
      } else if (frac_digits == 9) {
        round_up = text[i] >= '5';
        ++frac_digits;
      }
    }
  }
  if (plain && i == text.size() && any_digit) {
    for (int k = std::min(frac_digits, 9); k < 9; ++k) frac *= 10;
    TimeNs ns = whole * kNanosecondsPerSecond + frac + (round_up ? 1 : 0);
    *stamp = negative ? -ns : ns;
    return true;
  }
  // Exponent notation (or huge): through double.
  double value = 0.0;
  if (!ParseDouble(text, &value) || std::fabs(value) > 9.2e9) return false;
  *stamp = SecondsToNs(value);
  return true;
}

bool DetectTrajectoryFormat(const std::string& path, TrajectoryFormat* format,
                            std::string* error) {
  const std::string file = ResolveEurocPath(path);
  if (file != path) {
    *format = TrajectoryFormat::kEuroc;
    return true;
  }
  std::ifstream in(file);
  if (!in) {
    *error = path + ": cannot open (" + std::strerror(errno) + ")";
    return false;
  }
  std::string line;
  int line_number = 0;
  bool euroc_header = false;
  while (std::getline(in, line) && line_number < 1000) {
    ++line_number;
    if (line_number == 1) line.erase(0, text::Utf8BomLength(line));
    const std::string t = Trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      if (t.find(',') != std::string::npos) euroc_header = true;
      continue;
    }
    const std::vector<std::string> tokens = SplitWhitespace(t);
    if (IsG2oKeyword(tokens[0])) {
      *format = TrajectoryFormat::kG2o;
      return true;
    }
    if (t.find(',') != std::string::npos) {
      *format = TrajectoryFormat::kEuroc;
      return true;
    }
    if (tokens.size() == 12) {
      *format = TrajectoryFormat::kKitti;
      return true;
    }
    if (tokens.size() == 8) {
      *format = TrajectoryFormat::kTum;
      return true;
    }
    if (EndsWith(file, ".g2o")) {
      *format = TrajectoryFormat::kG2o;
      return true;
    }
    *error = Where(path, line_number) +
             "cannot tell the trajectory format from this line (" +
             std::to_string(tokens.size()) +
             " fields; TUM has 8, KITTI 12, EuRoC is comma separated, g2o "
             "starts with VERTEX/EDGE): give the format explicitly";
    return false;
  }
  if (euroc_header || EndsWith(file, ".csv")) {
    *format = TrajectoryFormat::kEuroc;
    return true;
  }
  if (EndsWith(file, ".g2o")) {
    *format = TrajectoryFormat::kG2o;
    return true;
  }
  *error = path + ": no data lines, cannot tell the trajectory format";
  return false;
}

bool ReadTumTrajectory(const std::string& path, Trajectory* trajectory,
                       std::string* error) {
  trajectory->clear();
  std::string content;
  if (!ReadWholeFile(path, &content, error)) return false;
  std::vector<int> lines;
  const bool ok = ForEachLine(content, [&](int n, const std::string& line) {
    if (IsSkippable(line)) return true;
    const std::string where = Where(path, n);
    const std::vector<std::string> tokens = SplitWhitespace(line);
    if (tokens.size() != 8) {
      *error = where + "expected 8 values (t x y z qx qy qz qw), found " +
               std::to_string(tokens.size());
      return false;
    }
    double v[8];
    if (!ParseValues(tokens, 0, 8, v, where, error)) return false;
    if (std::fabs(v[0]) > kMaxSecondsStamp) {
      *error = where + "timestamp " + text::Printable(tokens[0]) +
               " is too large for seconds: it looks like nanoseconds (or "
               "microseconds); TUM stamps are seconds - divide by 1e9 (EuRoC "
               "CSV files with nanosecond stamps: use the euroc format)";
      return false;
    }
    StampedPose p;
    if (!ParseStampSeconds(tokens[0], &p.stamp)) {
      *error = where + "bad timestamp '" + text::Printable(tokens[0]) + "'";
      return false;
    }
    Eigen::Quaterniond q;
    if (!MakeQuaternion(v[4], v[5], v[6], v[7], where, &q, error)) {
      return false;
    }
    p.pose = Pose3(Eigen::Vector3d(v[1], v[2], v[3]), q);
    trajectory->push_back(p);
    lines.push_back(n);
    return true;
  });
  if (!ok) return false;
  if (trajectory->empty()) {
    *error = path + ": no poses (expected lines 't x y z qx qy qz qw')";
    return false;
  }
  return CheckIncreasing(*trajectory, lines, path, error);
}

bool ReadKittiPoses(const std::string& path, const std::string& times_path,
                    Trajectory* trajectory, bool* has_stamps,
                    std::string* error) {
  trajectory->clear();
  std::string content;
  if (!ReadWholeFile(path, &content, error)) return false;
  const bool ok = ForEachLine(content, [&](int n, const std::string& line) {
    if (IsSkippable(line)) return true;
    const std::string where = Where(path, n);
    const std::vector<std::string> tokens = SplitWhitespace(line);
    if (tokens.size() != 12) {
      *error = where + "expected 12 values (3x4 row-major pose), found " +
               std::to_string(tokens.size());
      return false;
    }
    double v[12];
    if (!ParseValues(tokens, 0, 12, v, where, error)) return false;
    Eigen::Matrix3d r;
    r << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
    const double orth =
        (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (orth > 1e-3 || r.determinant() <= 0.0) {
      char buf[96];
      std::snprintf(buf, sizeof(buf),
                    "the 3x3 part is not a rotation (|R^T R - I| = %.3g, "
                    "det = %.6g)",
                    orth, r.determinant());
      *error = where + buf;
      return false;
    }
    // Nearest rotation (published files keep ~7 significant digits).
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(
        r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d rp = svd.matrixU() * svd.matrixV().transpose();
    StampedPose p;
    p.stamp = static_cast<TimeNs>(trajectory->size()) * kNanosecondsPerSecond;
    p.pose = Pose3(Eigen::Vector3d(v[3], v[7], v[11]), Eigen::Quaterniond(rp));
    trajectory->push_back(p);
    return true;
  });
  if (!ok) return false;
  if (trajectory->empty()) {
    *error = path + ": no poses (expected 12 values per line)";
    return false;
  }
  *has_stamps = false;
  if (times_path.empty()) return true;

  if (!ReadWholeFile(times_path, &content, error)) return false;
  std::vector<TimeNs> stamps;
  std::vector<int> lines;
  const bool times_ok =
      ForEachLine(content, [&](int n, const std::string& line) {
        if (IsSkippable(line)) return true;
        const std::vector<std::string> tokens = SplitWhitespace(line);
        TimeNs t = 0;
        double v = 0.0;
        if (tokens.size() != 1 || !ParseDouble(tokens[0], &v) ||
            !ParseStampSeconds(tokens[0], &t)) {
          *error = Where(times_path, n) + "expected one stamp in seconds";
          return false;
        }
        if (std::fabs(v) > kMaxSecondsStamp) {
          *error = Where(times_path, n) + "stamp " +
                   text::Printable(tokens[0]) +
                   " is too large for seconds (nanoseconds?)";
          return false;
        }
        stamps.push_back(t);
        lines.push_back(n);
        return true;
      });
  if (!times_ok) return false;
  if (stamps.size() != trajectory->size()) {
    *error = times_path + ": " + std::to_string(stamps.size()) +
             " stamps for " + std::to_string(trajectory->size()) +
             " poses in " + path;
    return false;
  }
  for (size_t i = 0; i < stamps.size(); ++i) (*trajectory)[i].stamp = stamps[i];
  if (!CheckIncreasing(*trajectory, lines, times_path, error)) return false;
  *has_stamps = true;
  return true;
}

bool ReadEurocTrajectory(const std::string& path_in, Trajectory* trajectory,
                         std::string* error) {
  trajectory->clear();
  const std::string path = ResolveEurocPath(path_in);
  std::string content;
  if (!ReadWholeFile(path, &content, error)) return false;
  std::vector<int> lines;
  bool first_data_line = true;
  const bool ok = ForEachLine(content, [&](int n, const std::string& line) {
    if (IsSkippable(line)) return true;
    const std::string where = Where(path, n);
    const std::vector<std::string> tokens = SplitCommas(line);
    const bool is_first = first_data_line;
    first_data_line = false;
    if (is_first && !tokens.empty() && !tokens[0].empty() &&
        std::isalpha(static_cast<unsigned char>(tokens[0][0]))) {
      return true;  // A header of column names without '#'.
    }
    if (tokens.size() < 8) {
      *error = where +
               "expected at least 8 comma-separated values "
               "(timestamp [ns], px, py, pz, qw, qx, qy, qz), found " +
               std::to_string(tokens.size());
      return false;
    }
    int64_t ns = 0;
    if (!ParseInt64(tokens[0], &ns)) {
      double v = 0.0;
      *error = where + "timestamp '" + text::Printable(tokens[0]) +
               "' is not an integer" +
               (ParseDouble(tokens[0], &v)
                    ? ": EuRoC stamps are integer nanoseconds (a file with "
                      "seconds is not EuRoC; convert it or write TUM)"
                    : "");
      return false;
    }
    double v[7];
    if (!ParseValues(tokens, 1, 7, v, where, error)) return false;
    Eigen::Quaterniond q;
    if (!MakeQuaternion(v[4], v[5], v[6], v[3], where, &q, error)) {
      return false;
    }
    StampedPose p;
    p.stamp = ns;
    p.pose = Pose3(Eigen::Vector3d(v[0], v[1], v[2]), q);
    trajectory->push_back(p);
    lines.push_back(n);
    return true;
  });
  if (!ok) return false;
  if (trajectory->empty()) {
    *error = path +
             ": no poses (expected CSV lines 'timestamp,px,py,pz,qw,"
             "qx,qy,qz')";
    return false;
  }
  return CheckIncreasing(*trajectory, lines, path, error);
}

bool ReadG2oPoses(const std::string& path, Trajectory* trajectory,
                  std::string* error) {
  trajectory->clear();
  // The project's pose-graph reader (g2o, or TORO by content): the same
  // parsing, normalization and errors as `slam optimize`. Information
  // matrices do not matter here, so bad ones are repaired, not fatal.
  Graph graph;
  GraphReadOptions options;
  options.repair_information = true;
  GraphReadReport report;
  if (!ReadPoseGraph(path, options, &graph, &report, error)) return false;
  if (report.initialized_from_edges) {
    *error = path +
             ": no VERTEX_SE2 or VERTEX_SE3:QUAT lines (a g2o file "
             "without vertices holds no poses: optimize it and evaluate the "
             "output)";
    return false;
  }
  if (!TrajectoryFromGraph(graph, false, trajectory, error)) {
    *error = path + ": " + *error;
    return false;
  }
  if (trajectory->empty()) {
    *error = path + ": no pose vertices";
    return false;
  }
  return true;
}

bool ReadTrajectory(const std::string& path,
                    const TrajectoryReadOptions& options, TrajectoryData* data,
                    std::string* error) {
  *data = TrajectoryData();
  data->path = path;
  TrajectoryFormat format = options.format;
  if (format == TrajectoryFormat::kAuto &&
      !DetectTrajectoryFormat(path, &format, error)) {
    return false;
  }
  data->format = format;
  data->has_stamps = true;
  switch (format) {
    case TrajectoryFormat::kTum:
      return ReadTumTrajectory(path, &data->poses, error);
    case TrajectoryFormat::kKitti:
      return ReadKittiPoses(path, options.kitti_times_path, &data->poses,
                            &data->has_stamps, error);
    case TrajectoryFormat::kEuroc:
      data->path = ResolveEurocPath(path);
      return ReadEurocTrajectory(path, &data->poses, error);
    case TrajectoryFormat::kG2o:
      return ReadG2oPoses(path, &data->poses, error);
    case TrajectoryFormat::kAuto:
      break;
  }
  *error = path + ": no trajectory format";
  return false;
}

bool WriteTrajectory(const std::string& path, const Trajectory& trajectory,
                     TrajectoryFormat format, std::string* error) {
  std::string out;
  char buf[512];
  switch (format) {
    case TrajectoryFormat::kTum:
      out = "# timestamp tx ty tz qx qy qz qw\n";
      for (const StampedPose& p : trajectory) {
        const Eigen::Quaterniond& q = p.pose.q;
        std::snprintf(buf, sizeof(buf),
                      " %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                      p.pose.t.x(), p.pose.t.y(), p.pose.t.z(), q.x(), q.y(),
                      q.z(), q.w());
        out += FormatStampSeconds(p.stamp) + buf;
      }
      break;
    case TrajectoryFormat::kKitti:
      for (const StampedPose& p : trajectory) {
        const Eigen::Matrix3d r = p.pose.q.toRotationMatrix();
        const Eigen::Vector3d& t = p.pose.t;
        std::snprintf(buf, sizeof(buf),
                      "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g "
                      "%.17g %.17g %.17g\n",
                      r(0, 0), r(0, 1), r(0, 2), t.x(), r(1, 0), r(1, 1),
                      r(1, 2), t.y(), r(2, 0), r(2, 1), r(2, 2), t.z());
        out += buf;
      }
      break;
    case TrajectoryFormat::kEuroc:
      out =
          "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],"
          "q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n";
      for (const StampedPose& p : trajectory) {
        const Eigen::Quaterniond& q = p.pose.q;
        std::snprintf(buf, sizeof(buf),
                      "%" PRId64 ",%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                      static_cast<int64_t>(p.stamp), p.pose.t.x(), p.pose.t.y(),
                      p.pose.t.z(), q.w(), q.x(), q.y(), q.z());
        out += buf;
      }
      break;
    case TrajectoryFormat::kG2o: {
      bool whole = true;
      for (const StampedPose& p : trajectory) {
        whole = whole && p.stamp % kNanosecondsPerSecond == 0;
      }
      for (size_t i = 0; i < trajectory.size(); ++i) {
        const StampedPose& p = trajectory[i];
        const int64_t id =
            whole ? p.stamp / kNanosecondsPerSecond : static_cast<int64_t>(i);
        const Eigen::Quaterniond& q = p.pose.q;
        std::snprintf(buf, sizeof(buf),
                      "VERTEX_SE3:QUAT %" PRId64
                      " %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                      id, p.pose.t.x(), p.pose.t.y(), p.pose.t.z(), q.x(),
                      q.y(), q.z(), q.w());
        out += buf;
      }
      break;
    }
    case TrajectoryFormat::kAuto:
      *error = path + ": give a trajectory format to write";
      return false;
  }
  return WriteFileAtomically(path, out, error);
}

bool WriteKittiTimes(const std::string& path, const Trajectory& trajectory,
                     std::string* error) {
  std::string out;
  for (const StampedPose& p : trajectory) {
    out += FormatStampSeconds(p.stamp) + "\n";
  }
  return WriteFileAtomically(path, out, error);
}

bool TrajectoryFromGraph(const Graph& graph, bool use_node_stamps,
                         Trajectory* trajectory, std::string* error) {
  trajectory->clear();
  for (const auto& [key, node] : graph.nodes()) {
    if (key.kind != NodeKind::kPose2 && key.kind != NodeKind::kPose3) continue;
    StampedPose p;
    p.stamp = use_node_stamps && node->has_stamp
                  ? node->stamp
                  : key.id * kNanosecondsPerSecond;
    p.pose = key.kind == NodeKind::kPose2 ? LiftPose2(NodePose2(*node))
                                          : NodePose3(*node);
    trajectory->push_back(p);
  }
  std::stable_sort(trajectory->begin(), trajectory->end(),
                   [](const StampedPose& a, const StampedPose& b) {
                     return a.stamp < b.stamp;
                   });
  for (size_t i = 1; i < trajectory->size(); ++i) {
    if ((*trajectory)[i].stamp == (*trajectory)[i - 1].stamp) {
      *error = "two pose nodes share the stamp " +
               FormatStampSeconds((*trajectory)[i].stamp) +
               " s (a pose2 and a pose3 node with the same id?)";
      return false;
    }
  }
  return true;
}

}  // namespace slam
