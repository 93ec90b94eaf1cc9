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
#include <limits>
#include <sstream>
#include <vector>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

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
  // One read into a string of the file's size (no stream copies).
  return text::ReadWholeFile(path, content, error);
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

// What a reader returns besides the poses (see TrajectoryData).
struct ReadExtras {
  bool allow_duplicate_stamps = false;
  bool allow_unsorted_stamps = false;
  std::vector<double> seconds;            // Stamps as parsed (float64 s).
  std::vector<Eigen::Matrix3d> matrices;  // KITTI: 3x3 blocks as read.
  size_t duplicate_stamps = 0;
  size_t unsorted_stamps = 0;
  std::string warning;
};

// Stamps must increase strictly. With extras->allow_duplicate_stamps an
// equal stamp, with extras->allow_unsorted_stamps a smaller one, is counted
// and described in extras->warning instead. `lines`: the line of each stamp.
bool CheckIncreasing(const Trajectory& t, const std::vector<int>& lines,
                     const std::string& path, ReadExtras* extras,
                     std::string* error) {
  std::string first_duplicate, first_unsorted;
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i].stamp > t[i - 1].stamp) continue;
    const bool duplicate = t[i].stamp == t[i - 1].stamp;
    const std::string what = Where(path, lines[i]) + "timestamp " +
                             FormatStampSeconds(t[i].stamp) + " s is " +
                             (duplicate ? "a duplicate of" : "before") +
                             " the one on line " + std::to_string(lines[i - 1]);
    if (extras != nullptr && duplicate && extras->allow_duplicate_stamps) {
      if (extras->duplicate_stamps++ == 0) first_duplicate = what;
      continue;
    }
    if (extras != nullptr && !duplicate && extras->allow_unsorted_stamps) {
      if (extras->unsorted_stamps++ == 0) first_unsorted = what;
      continue;
    }
    *error = what + " (" + FormatStampSeconds(t[i - 1].stamp) +
             " s): stamps must increase strictly (sort the file and "
             "remove duplicates)";
    return false;
  }
  if (extras == nullptr) return true;
  auto describe = [](size_t count, const char* kind, const std::string& first) {
    return std::to_string(count) + " " + kind + (count > 1 ? "s" : "") +
           " (first: " + first + ")";
  };
  std::string parts;
  if (extras->duplicate_stamps > 0) {
    parts =
        describe(extras->duplicate_stamps, "duplicate stamp", first_duplicate);
  }
  if (extras->unsorted_stamps > 0) {
    parts +=
        (parts.empty() ? "" : ", ") +
        describe(extras->unsorted_stamps, "decreasing stamp", first_unsorted);
  }
  if (!parts.empty()) {
    extras->warning = parts +
                      "; kept in file order, as evo does: a stamp is matched "
                      "to the first pose (in the file) with the nearest stamp";
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

namespace {

bool ParseStampSecondsView(std::string_view text, TimeNs* stamp) {
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
  if (!slam::text::ParseDouble(text, &value) || std::fabs(value) > 9.2e9) {
    return false;
  }
  *stamp = SecondsToNs(value);
  return true;
}

}  // namespace

bool ParseStampSeconds(const std::string& text, TimeNs* stamp) {
  return ParseStampSecondsView(text, stamp);
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

namespace {

// The text of a file: a read-only mapping of a regular file (no copy, no
// freshly zeroed pages: a third of the time of reading a million poses),
// else (a pipe, an empty file) the bytes read into a string.
class FileText {
 public:
  FileText() = default;
  FileText(const FileText&) = delete;
  FileText& operator=(const FileText&) = delete;
  ~FileText() {
    if (map_ != nullptr) ::munmap(map_, size_);
  }

  bool Open(const std::string& path, std::string* error) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      *error = path + ": is a directory, not a trajectory file";
      return false;
    }
    // Not blocking on a FIFO without a writer (see text::ReadWholeFile).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    struct stat st;
    if (fd >= 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
        st.st_size > 0) {
      void* map = ::mmap(nullptr, static_cast<size_t>(st.st_size), PROT_READ,
                         MAP_PRIVATE | MAP_POPULATE, fd, 0);
      if (map != MAP_FAILED) {
        ::close(fd);
        map_ = map;
        size_ = static_cast<size_t>(st.st_size);
        return true;
      }
    }
    if (fd >= 0) ::close(fd);
    return text::ReadWholeFile(path, &owned_, error);
  }
  std::string_view view() const {
    return map_ != nullptr
               ? std::string_view(static_cast<const char*>(map_), size_)
               : std::string_view(owned_);
  }

 private:
  void* map_ = nullptr;
  size_t size_ = 0;
  std::string owned_;
};

// Room for one pose per line, so that the arrays of a large file are
// allocated once (growing them copies and faults in every page again).
void ReserveForLines(std::string_view content, Trajectory* trajectory,
                     std::vector<int>* lines, ReadExtras* extras) {
  const size_t n =
      static_cast<size_t>(std::count(content.begin(), content.end(), '\n')) + 1;
  trajectory->reserve(n);
  if (lines != nullptr) lines->reserve(n);
  if (extras != nullptr) extras->seconds.reserve(n);
}

// "field 3 ('abc') is not a finite number".
std::string BadField(size_t index, std::string_view token) {
  return "field " + std::to_string(index + 1) + " ('" + text::Printable(token) +
         "') is not a finite number";
}

// Parses tokens[first, first + count) as doubles; names the bad one.
bool ParseFields(const std::vector<std::string_view>& tokens, size_t first,
                 size_t count, double* out, const std::string& path, int line,
                 std::string* error) {
  for (size_t i = 0; i < count; ++i) {
    if (!text::ParseDouble(tokens[first + i], &out[i])) {
      *error = Where(path, line) + BadField(first + i, tokens[first + i]);
      return false;
    }
  }
  return true;
}

bool ReadTum(const std::string& path, Trajectory* trajectory,
             ReadExtras* extras, std::string* error) {
  trajectory->clear();
  FileText file;
  if (!file.Open(path, error)) return false;
  const std::string_view content = file.view();
  std::vector<int> lines;
  ReserveForLines(content, trajectory, &lines, extras);
  // The number parser of the pose-graph readers (std::from_chars); lines
  // and '#' comments as there.
  text::LineTokenizer tokenizer(content);
  while (tokenizer.Next()) {
    const int n = static_cast<int>(tokenizer.line());
    const std::vector<std::string_view>& tokens = tokenizer.tokens();
    if (tokens.size() != 8) {
      *error = Where(path, n) +
               "expected 8 values (t x y z qx qy qz qw), found " +
               std::to_string(tokens.size());
      return false;
    }
    double v[8];
    if (!ParseFields(tokens, 0, 8, v, path, n, error)) return false;
    if (std::fabs(v[0]) > kMaxSecondsStamp) {
      *error = Where(path, n) + "timestamp " + text::Printable(tokens[0]) +
               " is too large for seconds: it looks like nanoseconds (or "
               "microseconds); TUM stamps are seconds - divide by 1e9 (EuRoC "
               "CSV files with nanosecond stamps: use the euroc format)";
      return false;
    }
    StampedPose p;
    if (!ParseStampSecondsView(tokens[0], &p.stamp)) {
      *error =
          Where(path, n) + "bad timestamp '" + text::Printable(tokens[0]) + "'";
      return false;
    }
    Eigen::Quaterniond q;
    if (!MakeQuaternion(v[4], v[5], v[6], v[7], Where(path, n), &q, error)) {
      return false;
    }
    p.pose = Pose3(Eigen::Vector3d(v[1], v[2], v[3]), q);
    trajectory->push_back(p);
    lines.push_back(n);
    if (extras != nullptr) extras->seconds.push_back(v[0]);
  }
  if (trajectory->empty()) {
    *error = path + ": no poses (expected lines 't x y z qx qy qz qw')";
    return false;
  }
  return CheckIncreasing(*trajectory, lines, path, extras, error);
}

}  // namespace

bool ReadTumTrajectory(const std::string& path, Trajectory* trajectory,
                       std::string* error) {
  return ReadTum(path, trajectory, nullptr, error);
}

namespace {

bool ReadKitti(const std::string& path, const std::string& times_path,
               Trajectory* trajectory, bool* has_stamps, ReadExtras* extras,
               std::string* error) {
  trajectory->clear();
  FileText file;
  if (!file.Open(path, error)) return false;
  const std::string_view content = file.view();
  ReserveForLines(content, trajectory, nullptr, extras);
  if (extras != nullptr) extras->matrices.reserve(trajectory->capacity());
  text::LineTokenizer tokenizer(content);
  while (tokenizer.Next()) {
    const int n = static_cast<int>(tokenizer.line());
    const std::vector<std::string_view>& tokens = tokenizer.tokens();
    if (tokens.size() != 12) {
      *error = Where(path, n) +
               "expected 12 values (3x4 row-major pose), found " +
               std::to_string(tokens.size());
      return false;
    }
    double v[12];
    if (!ParseFields(tokens, 0, 12, v, path, n, error)) return false;
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
      *error = Where(path, n) + buf;
      return false;
    }
    // Pose3 holds the nearest rotation (published files keep ~7 significant
    // digits); the evaluation uses the matrix as read (extras->matrices).
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(
        r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d rp = svd.matrixU() * svd.matrixV().transpose();
    StampedPose p;
    p.stamp = static_cast<TimeNs>(trajectory->size()) * kNanosecondsPerSecond;
    p.pose = Pose3(Eigen::Vector3d(v[3], v[7], v[11]), Eigen::Quaterniond(rp));
    trajectory->push_back(p);
    if (extras != nullptr) extras->matrices.push_back(r);
  }
  if (trajectory->empty()) {
    *error = path + ": no poses (expected 12 values per line)";
    return false;
  }
  *has_stamps = false;
  if (times_path.empty()) {
    if (extras != nullptr) {
      for (size_t i = 0; i < trajectory->size(); ++i) {
        extras->seconds.push_back(static_cast<double>(i));
      }
    }
    return true;
  }

  std::string times_text;
  if (!ReadWholeFile(times_path, &times_text, error)) return false;
  std::vector<TimeNs> stamps;
  std::vector<double> seconds;
  std::vector<int> lines;
  text::LineTokenizer times(times_text);
  while (times.Next()) {
    const int n = static_cast<int>(times.line());
    const std::vector<std::string_view>& tokens = times.tokens();
    TimeNs t = 0;
    double v = 0.0;
    if (tokens.size() != 1 || !text::ParseDouble(tokens[0], &v) ||
        !ParseStampSecondsView(tokens[0], &t)) {
      *error = Where(times_path, n) + "expected one stamp in seconds";
      return false;
    }
    if (std::fabs(v) > kMaxSecondsStamp) {
      *error = Where(times_path, n) + "stamp " + text::Printable(tokens[0]) +
               " is too large for seconds (nanoseconds?)";
      return false;
    }
    stamps.push_back(t);
    seconds.push_back(v);
    lines.push_back(n);
  }
  if (stamps.size() != trajectory->size()) {
    *error = times_path + ": " + std::to_string(stamps.size()) +
             " stamps for " + std::to_string(trajectory->size()) +
             " poses in " + path;
    return false;
  }
  for (size_t i = 0; i < stamps.size(); ++i) (*trajectory)[i].stamp = stamps[i];
  if (!CheckIncreasing(*trajectory, lines, times_path, extras, error)) {
    return false;
  }
  if (extras != nullptr) extras->seconds = std::move(seconds);
  *has_stamps = true;
  return true;
}

}  // namespace

bool ReadKittiPoses(const std::string& path, const std::string& times_path,
                    Trajectory* trajectory, bool* has_stamps,
                    std::string* error) {
  return ReadKitti(path, times_path, trajectory, has_stamps, nullptr, error);
}

namespace {

bool ReadEuroc(const std::string& path_in, Trajectory* trajectory,
               ReadExtras* extras, std::string* error) {
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
    // evo: the stamp column read as float64, divided by 1e9.
    if (extras != nullptr) {
      extras->seconds.push_back(static_cast<double>(ns) / 1e9);
    }
    return true;
  });
  if (!ok) return false;
  if (trajectory->empty()) {
    *error = path +
             ": no poses (expected CSV lines 'timestamp,px,py,pz,qw,"
             "qx,qy,qz')";
    return false;
  }
  return CheckIncreasing(*trajectory, lines, path, extras, error);
}

}  // namespace

bool ReadEurocTrajectory(const std::string& path, Trajectory* trajectory,
                         std::string* error) {
  return ReadEuroc(path, trajectory, nullptr, error);
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
  ReadExtras extras;
  extras.allow_duplicate_stamps = options.allow_duplicate_stamps;
  extras.allow_unsorted_stamps = options.allow_unsorted_stamps;
  bool ok = false;
  switch (format) {
    case TrajectoryFormat::kTum:
      ok = ReadTum(path, &data->poses, &extras, error);
      break;
    case TrajectoryFormat::kKitti:
      ok = ReadKitti(path, options.kitti_times_path, &data->poses,
                     &data->has_stamps, &extras, error);
      break;
    case TrajectoryFormat::kEuroc:
      data->path = ResolveEurocPath(path);
      ok = ReadEuroc(path, &data->poses, &extras, error);
      break;
    case TrajectoryFormat::kG2o:
      ok = ReadG2oPoses(path, &data->poses, error);
      break;
    case TrajectoryFormat::kAuto:
      *error = path + ": no trajectory format";
      return false;
  }
  if (!ok) return false;
  data->seconds = std::move(extras.seconds);
  data->matrices = std::move(extras.matrices);
  data->duplicate_stamps = extras.duplicate_stamps;
  data->unsorted_stamps = extras.unsorted_stamps;
  data->warning = std::move(extras.warning);
  return true;
}

EvalTrajectory ToEvalTrajectory(const TrajectoryData& data) {
  const size_t n = data.poses.size();
  const bool has_seconds = data.seconds.size() == n;
  const bool has_matrices = data.matrices.size() == n;
  EvalTrajectory out;
  out.stamps.resize(n);
  out.seconds.resize(n);
  out.poses.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const StampedPose& p = data.poses[i];
    out.stamps[i] = p.stamp;
    out.seconds[i] = has_seconds ? data.seconds[i] : NearestSeconds(p.stamp);
    out.poses[i] = has_matrices ? MatrixPose(data.matrices[i], p.pose.t)
                                : MatrixPose(p.pose);
  }
  return out;
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
    if (use_node_stamps && node->has_stamp) {
      p.stamp = node->stamp;
    } else {
      // The id is the stamp in seconds; one beyond int64 nanoseconds
      // (|id| > 9.2e9) has no stamp.
      constexpr int64_t kMaxId =
          std::numeric_limits<int64_t>::max() / kNanosecondsPerSecond;
      if (key.id > kMaxId || key.id < -kMaxId) {
        *error = std::string("the ") + NodeKindName(key.kind) + " node id " +
                 std::to_string(key.id) +
                 " is too large to be a stamp in seconds (|id| <= " +
                 std::to_string(kMaxId) + ")";
        return false;
      }
      p.stamp = key.id * kNanosecondsPerSecond;
    }
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
