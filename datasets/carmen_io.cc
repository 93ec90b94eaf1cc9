#include "datasets/carmen_io.h"

#include <bzlib.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <string_view>
#include <tuple>
#include <utility>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "datasets/trajectory_io.h"

namespace slam {
namespace {

constexpr double kDegree = M_PI / 180.0;
constexpr int64_t kMaxReadings = 1 << 20;
constexpr double kMaxCoordinate = 1e7;  // Metres.
// Progress is reported about this many times per phase.
constexpr int kProgressSteps = 100;

// Geometry of the FLASER or RLASER lasers as the PARAM lines set it.
struct OldLaserParams {
  const char* fov_key;
  const char* resolution_key;
  const char* max_key;
  const char* offset_key;
  double fov_deg = 0.0;         // 0: not given.
  double resolution_deg = 0.0;  // 0: not given.
  double max_range = 0.0;       // 0: not given.
  double offset = 0.0;
};

// Increment CARMEN assumes for a laser line without configuration.
double GuessIncrement(int64_t n, double fov) {
  if (n == 180 || n == 181) return kDegree;
  if (n == 360 || n == 361) return 0.5 * kDegree;
  if (n == 400 || n == 401) return 0.25 * kDegree;
  return n > 1 ? fov / static_cast<double>(n - 1) : 0.0;
}

class Parser {
 public:
  Parser(const std::string& name, const CarmenReadOptions& options,
         CarmenLog* log)
      : name_(name), options_(options), log_(log) {
    front_ = {"laser_front_laser_fov", "laser_front_laser_resolution",
              "robot_front_laser_max", "robot_frontlaser_offset"};
    rear_ = {"laser_rear_laser_fov", "laser_rear_laser_resolution",
             "robot_rear_laser_max", "robot_rearlaser_offset"};
  }

  bool Parse(std::string_view text, const ProgressCallback& progress,
             double progress_start, std::string* error) {
    if (!ParseLines(text, 0, progress, progress_start, error)) return false;
    Finish();
    if (progress) progress(1.0);
    return true;
  }

  // Parses whole lines that follow `lines_before` lines of the log.
  bool ParseLines(std::string_view text, int64_t lines_before,
                  const ProgressCallback& progress, double progress_start,
                  std::string* error) {
    text::LineTokenizer tokenizer(text, lines_before);
    size_t next_report = 0;
    const size_t step = std::max<size_t>(1, text.size() / kProgressSteps);
    while (tokenizer.Next()) {
      line_ = tokenizer.line();
      const auto& tokens = tokenizer.tokens();
      if (progress) {
        const size_t done = static_cast<size_t>(tokens[0].data() - text.data());
        if (done >= next_report) {
          progress(progress_start + (1.0 - progress_start) *
                                        static_cast<double>(done) /
                                        static_cast<double>(text.size()));
          next_report = done + step;
        }
      }
      std::string problem;
      if (!ParseLine(tokens, &problem)) {
        *error = name_ + ":" + std::to_string(line_) + ": " + problem;
        return false;
      }
    }
    return true;
  }

  // The warnings about the whole log.
  void Finish() {
    for (const auto& [tag, count] : skipped_) {
      log_->warnings.push_back(name_ + ": skipped " + std::to_string(count) +
                               " " + tag + " line(s) (tag not read)");
    }
    const std::vector<LaserScan>& scans = log_->scans;
    for (size_t i = 1; i < scans.size(); ++i) {
      if (scans[i].stamp <= scans[i - 1].stamp) ++log_->scans_out_of_order;
    }
    if (log_->scans_out_of_order > 0) {
      log_->warnings.push_back(
          name_ + ": " + std::to_string(log_->scans_out_of_order) + " of " +
          std::to_string(scans.size()) +
          " laser scans have a stamp not after the previous scan's (first at "
          "line " +
          std::to_string(FirstOutOfOrderLine()) + "); processed in log order");
    }
  }

 private:
  using Tokens = std::vector<std::string_view>;

  int FirstOutOfOrderLine() const {
    const std::vector<LaserScan>& scans = log_->scans;
    for (size_t i = 1; i < scans.size(); ++i) {
      if (scans[i].stamp <= scans[i - 1].stamp) return scans[i].line;
    }
    return 0;
  }

  bool ParseLine(const Tokens& tokens, std::string* problem) {
    const std::string_view tag = tokens[0];
    if (tag == "PARAM") return ParseParam(tokens, problem);
    if (tag == "ODOM") return ParseOdom(tokens, problem);
    if (tag == "FLASER") {
      return !options_.front_laser ||
             ParseOldLaser(tokens, front_, Pose2(front_.offset, 0.0, 0.0),
                           problem);
    }
    if (tag == "RLASER") {
      return !options_.rear_laser ||
             ParseOldLaser(tokens, rear_, Pose2(-rear_.offset, 0.0, M_PI),
                           problem);
    }
    if (tag == "ROBOTLASER1") {
      return !options_.robot_laser || ParseRobotLaser(tokens, problem);
    }
    ++skipped_[text::Printable(tag)];
    return true;
  }

  bool ParseParam(const Tokens& tokens, std::string* problem) {
    if (!text::CheckMinFieldCount(tokens, 2, problem)) return false;
    const std::string key(tokens[1]);
    const std::string value(tokens[2]);
    log_->params[key] = value;
    for (OldLaserParams* laser : {&front_, &rear_}) {
      double* target = nullptr;
      bool positive = true;
      if (key == laser->fov_key) target = &laser->fov_deg;
      if (key == laser->resolution_key) target = &laser->resolution_deg;
      if (key == laser->max_key) target = &laser->max_range;
      if (key == laser->offset_key) {
        target = &laser->offset;
        positive = false;
      }
      if (target == nullptr) continue;
      double v = 0.0;
      if (!text::ParseDouble(tokens[2], &v) || (positive && v <= 0.0)) {
        *problem = "PARAM " + key + ": expected a " +
                   (positive ? "positive " : "") + "number, found '" +
                   text::Printable(tokens[2]) + "'";
        return false;
      }
      *target = v;
    }
    return true;
  }

  // Pose coordinates (x, y of each pose in values[0..]) no robot reaches:
  // beyond kMaxCoordinate metres the grids and maps cannot hold them.
  bool CheckCoordinates(const Tokens& tokens, size_t first_field,
                        const double* values, std::initializer_list<int> xy,
                        std::string* problem) {
    for (int k : xy) {
      if (std::abs(values[k]) > kMaxCoordinate) {
        *problem = "coordinate '" + text::Printable(tokens[first_field + k]) +
                   "' in field " + std::to_string(first_field + k) + " of " +
                   text::Printable(tokens[0]) +
                   " is beyond 1e7 m (10000 km) from the origin";
        return false;
      }
    }
    return true;
  }

  // The trailing "ipc_timestamp host logger_timestamp" of a message.
  bool ParseTrailer(const Tokens& tokens, TimeNs* stamp, std::string* problem) {
    const size_t n = tokens.size();
    double logger = 0.0;
    if (!ParseStampSeconds(std::string(tokens[n - 3]), stamp)) {
      *problem = "bad ipc_timestamp '" + text::Printable(tokens[n - 3]) +
                 "' in field " + std::to_string(n - 3) + " of " +
                 text::Printable(tokens[0]);
      return false;
    }
    if (!text::ParseDouble(tokens[n - 1], &logger)) {
      *problem = "bad logger_timestamp '" + text::Printable(tokens[n - 1]) +
                 "' in field " + std::to_string(n - 1) + " of " +
                 text::Printable(tokens[0]);
      return false;
    }
    return true;
  }

  bool ParseOdom(const Tokens& tokens, std::string* problem) {
    if (!text::CheckFieldCount(tokens, 9, problem)) return false;
    double v[6];
    if (!text::ParseDoubles(tokens, 1, 6, v, problem) ||
        !CheckCoordinates(tokens, 1, v, {0, 1}, problem)) {
      return false;
    }
    OdometryReading odom;
    if (!ParseTrailer(tokens, &odom.stamp, problem)) return false;
    odom.pose = Pose2(v[0], v[1], v[2]);
    odom.tv = v[3];
    odom.rv = v[4];
    log_->odometry.push_back(odom);
    return true;
  }

  // Reads the count of readings at tokens[index] (0 .. kMaxReadings).
  bool ParseCount(const Tokens& tokens, size_t index, const char* what,
                  int64_t* n, std::string* problem) {
    if (!text::CheckMinFieldCount(tokens, index, problem)) return false;
    if (!text::ParseInt64(tokens[index], n) || *n < 0 || *n > kMaxReadings) {
      *problem = std::string("bad ") + what + " '" +
                 text::Printable(tokens[index]) + "' in field " +
                 std::to_string(index) + " of " + text::Printable(tokens[0]);
      return false;
    }
    return true;
  }

  bool ParseRanges(const Tokens& tokens, size_t first, int64_t n,
                   std::vector<float>* ranges, std::string* problem) {
    ranges->resize(static_cast<size_t>(n));
    for (int64_t k = 0; k < n; ++k) {
      double r = 0.0;
      if (!text::ParseDoubles(tokens, first + k, 1, &r, problem)) return false;
      if (r < 0.0) {
        *problem = "negative range '" + text::Printable(tokens[first + k]) +
                   "' in field " + std::to_string(first + k) + " of " +
                   text::Printable(tokens[0]);
        return false;
      }
      (*ranges)[k] = static_cast<float>(r);
    }
    return true;
  }

  bool ParseOldLaser(const Tokens& tokens, const OldLaserParams& params,
                     const Pose2& offset, std::string* problem) {
    int64_t n = 0;
    if (!ParseCount(tokens, 1, "number of readings", &n, problem) ||
        !text::CheckFieldCount(tokens, 1 + n + 9, problem)) {
      return false;
    }
    LaserScan scan;
    if (!ParseRanges(tokens, 2, n, &scan.ranges, problem)) return false;
    double v[6];
    if (!text::ParseDoubles(tokens, 2 + n, 6, v, problem) ||
        !CheckCoordinates(tokens, 2 + n, v, {0, 1, 3, 4}, problem) ||
        !ParseTrailer(tokens, &scan.stamp, problem)) {
      return false;
    }
    scan.logged_pose = Pose2(v[0], v[1], v[2]);
    scan.odom = Pose2(v[3], v[4], v[5]);
    scan.laser_offset = offset;
    const double fov =
        params.fov_deg > 0.0 ? params.fov_deg * kDegree : 180.0 * kDegree;
    scan.angle_min = -0.5 * fov;
    scan.angle_increment = params.resolution_deg > 0.0
                               ? params.resolution_deg * kDegree
                               : GuessIncrement(n, fov);
    scan.max_range =
        params.max_range > 0.0 ? params.max_range : options_.default_max_range;
    scan.tag = std::string(tokens[0]);
    scan.line = static_cast<int>(line_);
    log_->scans.push_back(std::move(scan));
    return true;
  }

  bool ParseRobotLaser(const Tokens& tokens, std::string* problem) {
    int64_t n = 0;
    int64_t n_rem = 0;
    if (!ParseCount(tokens, 8, "number of readings", &n, problem) ||
        !ParseCount(tokens, 9 + n, "number of remissions", &n_rem, problem) ||
        !text::CheckFieldCount(tokens, 23 + n + n_rem, problem)) {
      return false;
    }
    double config[7];
    double poses[6];
    double rest[5];
    LaserScan scan;
    if (!text::ParseDoubles(tokens, 1, 7, config, problem) ||
        !ParseRanges(tokens, 9, n, &scan.ranges, problem)) {
      return false;
    }
    std::vector<double> remissions(static_cast<size_t>(n_rem));
    if (!text::ParseDoubles(tokens, 10 + n, n_rem, remissions.data(),
                            problem) ||
        !text::ParseDoubles(tokens, 10 + n + n_rem, 6, poses, problem) ||
        !CheckCoordinates(tokens, 10 + n + n_rem, poses, {0, 1, 3, 4},
                          problem) ||
        !text::ParseDoubles(tokens, 16 + n + n_rem, 5, rest, problem) ||
        !ParseTrailer(tokens, &scan.stamp, problem)) {
      return false;
    }
    if (config[3] <= 0.0 && n > 1) {
      *problem = "ROBOTLASER1 angular_res must be positive, found '" +
                 text::Printable(tokens[4]) + "'";
      return false;
    }
    if (config[4] <= 0.0) {
      *problem = "ROBOTLASER1 max_range must be positive, found '" +
                 text::Printable(tokens[5]) + "'";
      return false;
    }
    scan.logged_pose = Pose2(poses[0], poses[1], poses[2]);
    scan.odom = Pose2(poses[3], poses[4], poses[5]);
    scan.laser_offset = scan.odom.Inverse() * scan.logged_pose;
    scan.angle_min = config[1];
    scan.angle_increment = config[3];
    scan.max_range = config[4];
    scan.tag = "ROBOTLASER1";
    scan.line = static_cast<int>(line_);
    log_->scans.push_back(std::move(scan));
    return true;
  }

  const std::string& name_;
  const CarmenReadOptions& options_;
  CarmenLog* log_;
  int64_t line_ = 0;
  OldLaserParams front_;
  OldLaserParams rear_;
  std::map<std::string, int64_t> skipped_;
};

bool IsBzip2(const std::string& data) {
  return data.size() >= 4 && data.compare(0, 3, "BZh") == 0 && data[3] >= '1' &&
         data[3] <= '9';
}

void AppendFloat(float value, std::string* out) {
  char buffer[32];
  const std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, r.ptr);
}

void AppendPose(const Pose2& p, std::string* out) {
  for (double v : {p.t.x(), p.t.y(), p.theta}) {
    out->push_back(' ');
    text::AppendDouble(v, out);
  }
}

void AppendTrailer(TimeNs stamp, std::string* out) {
  const std::string s = FormatStampSeconds(stamp);
  *out += ' ' + s + " nohost " + s + '\n';
}

void AppendScan(const LaserScan& scan, std::string* out) {
  *out += scan.tag;
  const bool robot_laser = scan.tag == "ROBOTLASER1";
  if (robot_laser) {
    *out += " 0";  // laser_type.
    for (double v : {scan.angle_min,
                     scan.angle_increment *
                         std::max<double>(0.0, scan.ranges.size() - 1.0),
                     scan.angle_increment, scan.max_range}) {
      out->push_back(' ');
      text::AppendDouble(v, out);
    }
    *out += " 0 0";  // accuracy, remission_mode.
  }
  out->push_back(' ');
  text::AppendInt(static_cast<int64_t>(scan.ranges.size()), out);
  for (float r : scan.ranges) {
    out->push_back(' ');
    AppendFloat(r, out);
  }
  if (robot_laser) {
    *out += " 0";  // No remissions.
    AppendPose(scan.logged_pose, out);
    AppendPose(scan.odom, out);
    *out += " 0 0 0 0 0";  // tv rv forward_safety side_safety turn_axis.
  } else {
    AppendPose(scan.logged_pose, out);
    AppendPose(scan.odom, out);
  }
  AppendTrailer(scan.stamp, out);
}

}  // namespace

bool ParseCarmenLog(const std::string& name, const std::string& text,
                    const CarmenReadOptions& options, CarmenLog* log,
                    std::string* error, ProgressCallback progress) {
  *log = CarmenLog();
  Parser parser(name, options, log);
  if (!parser.Parse(text, progress, 0.0, error)) {
    *log = CarmenLog();
    return false;
  }
  return true;
}

namespace {

// Decompresses bzip2 data (one or more concatenated streams) piece by piece,
// parsing every complete line as soon as it is out: memory holds the
// compressed file, one piece and one partial line, never the whole text.
bool ParseBzip2Log(const std::string& name, const std::string& compressed,
                   const CarmenReadOptions& options, Parser* parser,
                   const ProgressCallback& progress, std::string* error) {
  constexpr size_t kPiece = 1 << 20;
  std::string pending;  // Decompressed text not parsed yet (a partial line).
  std::vector<char> out(kPiece);
  uint64_t produced = 0;
  int64_t lines = 0;
  size_t consumed = 0;
  size_t next_report = 0;
  const size_t step = std::max<size_t>(1, compressed.size() / kProgressSteps);
  // Parses the complete lines of `pending`; all of it when `last`.
  auto parse_pending = [&](bool last) {
    const size_t newline = pending.rfind('\n');
    const size_t end = last ? pending.size()
                            : (newline == std::string::npos ? 0 : newline + 1);
    if (end == 0) {
      if (pending.size() > options.max_line_bytes) {
        *error = name + ":" + std::to_string(lines + 1) +
                 ": a line longer than " +
                 std::to_string(options.max_line_bytes) + " bytes";
        return false;
      }
      return true;
    }
    const std::string_view text(pending.data(), end);
    if (!parser->ParseLines(text, lines, nullptr, 0.0, error)) return false;
    lines += std::count(text.begin(), text.end(), '\n');
    pending.erase(0, end);
    return true;
  };
  while (consumed < compressed.size()) {
    bz_stream stream{};
    if (BZ2_bzDecompressInit(&stream, 0, 0) != BZ_OK) {
      *error = name + ": cannot start bzip2 decompression";
      return false;
    }
    stream.next_in = const_cast<char*>(compressed.data() + consumed);
    stream.avail_in = static_cast<unsigned int>(
        std::min<size_t>(compressed.size() - consumed, 1u << 30));
    int status = BZ_OK;
    while (status == BZ_OK) {
      stream.next_out = out.data();
      stream.avail_out = static_cast<unsigned int>(out.size());
      const unsigned int in_before = stream.avail_in;
      status = BZ2_bzDecompress(&stream);
      const size_t got = out.size() - stream.avail_out;
      consumed += in_before - stream.avail_in;
      produced += got;
      if (produced > options.max_log_bytes) {
        BZ2_bzDecompressEnd(&stream);
        *error = name + ": decompresses to more than " +
                 std::to_string(options.max_log_bytes) +
                 " bytes (a bzip2 bomb? CarmenReadOptions::max_log_bytes)";
        return false;
      }
      pending.append(out.data(), got);
      if (!parse_pending(false)) {
        BZ2_bzDecompressEnd(&stream);
        return false;
      }
      if (progress && consumed >= next_report) {
        progress(static_cast<double>(consumed) /
                 static_cast<double>(compressed.size()));
        next_report = consumed + step;
      }
      if (status == BZ_OK && stream.avail_in == 0 && got == 0) {
        status = BZ_UNEXPECTED_EOF;  // No progress and no more input.
      }
    }
    BZ2_bzDecompressEnd(&stream);
    if (status != BZ_STREAM_END) {
      *error =
          name + ": corrupt or truncated bzip2 data (" +
          (status == BZ_UNEXPECTED_EOF ? std::string("unexpected end")
                                       : "error " + std::to_string(status)) +
          ")";
      return false;
    }
    // Trailing bytes that are not another stream (e.g. zero padding) end
    // the data.
    if (!IsBzip2(compressed.substr(consumed, 4))) break;
  }
  if (!parse_pending(true)) return false;
  parser->Finish();
  if (progress) progress(1.0);
  return true;
}

}  // namespace

bool ReadCarmenLog(const std::string& path, const CarmenReadOptions& options,
                   CarmenLog* log, std::string* error,
                   ProgressCallback progress) {
  *log = CarmenLog();
  std::string data;
  if (!text::ReadWholeFile(path, &data, error, options.max_log_bytes)) {
    return false;
  }
  Parser parser(path, options, log);
  const bool ok = IsBzip2(data) ? ParseBzip2Log(path, data, options, &parser,
                                                progress, error)
                                : parser.Parse(data, progress, 0.0, error);
  if (!ok) {
    *log = CarmenLog();
    return false;
  }
  return true;
}

bool WriteCarmenLog(const std::string& path, const CarmenLog& log,
                    std::string* error) {
  std::string out =
      "# written by slam: PARAM, ODOM, FLASER/RLASER/ROBOTLASER1\n";
  for (const auto& [key, value] : log.params) {
    out += "PARAM " + key + " " + value + " nohost 0\n";
  }
  // (stamp, kind (0 odometry, 1 scan), index), merged by stamp.
  std::vector<std::tuple<TimeNs, int, size_t>> order;
  order.reserve(log.odometry.size() + log.scans.size());
  for (size_t i = 0; i < log.odometry.size(); ++i) {
    order.emplace_back(log.odometry[i].stamp, 0, i);
  }
  for (size_t i = 0; i < log.scans.size(); ++i) {
    const std::string& tag = log.scans[i].tag;
    if (tag != "FLASER" && tag != "RLASER" && tag != "ROBOTLASER1") {
      *error = path + ": scan " + std::to_string(i) + " has the unknown tag '" +
               text::Printable(tag) + "'";
      return false;
    }
    order.emplace_back(log.scans[i].stamp, 1, i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& a, const auto& b) {
                     return std::get<0>(a) != std::get<0>(b)
                                ? std::get<0>(a) < std::get<0>(b)
                                : std::get<1>(a) < std::get<1>(b);
                   });
  for (const auto& [stamp, kind, index] : order) {
    if (kind == 1) {
      AppendScan(log.scans[index], &out);
      continue;
    }
    const OdometryReading& o = log.odometry[index];
    out += "ODOM";
    AppendPose(o.pose, &out);
    for (double v : {o.tv, o.rv, 0.0}) {
      out.push_back(' ');
      text::AppendDouble(v, &out);
    }
    AppendTrailer(o.stamp, &out);
  }
  return WriteFileAtomically(path, out, error);
}

}  // namespace slam
