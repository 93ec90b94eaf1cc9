#include "datasets/imu_io.h"

#include <cmath>
#include <filesystem>
#include <string_view>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"

namespace slam {
namespace {

// Comma-separated lines: skips blank lines and lines whose first non-blank
// character is '#'; splits at ',' and trims blanks around every field.
class CsvLines {
 public:
  explicit CsvLines(std::string_view text)
      : text_(text), pos_(text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0) {}

  bool Next() {
    while (pos_ < text_.size()) {
      size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = Trim(text_.substr(pos_, end - pos_));
      pos_ = end + 1;
      ++line_;
      if (line.empty() || line[0] == '#') continue;
      fields_.clear();
      size_t start = 0;
      while (true) {
        const size_t comma = line.find(',', start);
        fields_.push_back(Trim(line.substr(
            start, comma == std::string_view::npos ? std::string_view::npos
                                                   : comma - start)));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
      }
      return true;
    }
    return false;
  }
  int64_t line() const { return line_; }
  const std::vector<std::string_view>& fields() const { return fields_; }

 private:
  static std::string_view Trim(std::string_view s) {
    const char* blanks = " \t\r\v\f";
    const size_t b = s.find_first_not_of(blanks);
    if (b == std::string_view::npos) return {};
    const size_t e = s.find_last_not_of(blanks);
    return s.substr(b, e - b + 1);
  }

  std::string_view text_;
  size_t pos_;
  int64_t line_ = 0;
  std::vector<std::string_view> fields_;
};

std::string Where(const std::string& path, int64_t line) {
  return path + ":" + std::to_string(line) + ": ";
}

// Parses fields[first .. first + n) as doubles.
bool ParseFields(const CsvLines& csv, size_t first, size_t n, double* out,
                 const std::string& path, std::string* error) {
  const auto& f = csv.fields();
  for (size_t k = 0; k < n; ++k) {
    if (!text::ParseDouble(f[first + k], &out[k])) {
      *error = Where(path, csv.line()) + "field " +
               std::to_string(first + k + 1) + " is not a finite number: '" +
               text::Printable(f[first + k]) + "'";
      return false;
    }
  }
  return true;
}

bool CheckCount(const CsvLines& csv, size_t expected, const std::string& what,
                const std::string& path, std::string* error) {
  if (csv.fields().size() == expected) return true;
  *error = Where(path, csv.line()) + what + " needs " +
           std::to_string(expected) + " comma-separated fields, found " +
           std::to_string(csv.fields().size());
  return false;
}

bool Quaternion(const CsvLines& csv, double x, double y, double z, double w,
                Eigen::Quaterniond* q, const std::string& path,
                std::string* error) {
  if (text::UnitQuaternion(x, y, z, w, q)) return true;
  *error = Where(path, csv.line()) + "the quaternion has zero norm";
  return false;
}

// A stamp in integer nanoseconds in field 0, strictly after *last.
bool ParseStamp(const CsvLines& csv, TimeNs* last, bool* has_last,
                TimeNs* stamp, const std::string& path, std::string* error) {
  if (!text::ParseInt64(csv.fields()[0], stamp)) {
    *error = Where(path, csv.line()) +
             "the timestamp is not an integer number of nanoseconds: '" +
             text::Printable(csv.fields()[0]) + "'";
    return false;
  }
  if (*has_last && *stamp <= *last) {
    *error = Where(path, csv.line()) + "timestamp " + std::to_string(*stamp) +
             " does not increase (previous " + std::to_string(*last) + ")";
    return false;
  }
  *last = *stamp;
  *has_last = true;
  return true;
}

// Reads the rows of an EuRoC CSV file: `fields` comma-separated fields, an
// integer nanosecond stamp strictly increasing, then numbers; calls
// row(stamp, numbers, csv) for each (it may fail with *error set).
template <typename RowFn>
bool ReadStampedRows(const std::string& path, size_t fields, const char* what,
                     std::string* error, RowFn row) {
  std::string contents;
  if (!text::ReadWholeFile(path, &contents, error)) return false;
  CsvLines csv(contents);
  TimeNs last = 0, stamp = 0;
  bool has_last = false;
  std::vector<double> v(fields - 1);
  while (csv.Next()) {
    if (!CheckCount(csv, fields, what, path, error) ||
        !ParseStamp(csv, &last, &has_last, &stamp, path, error) ||
        !ParseFields(csv, 1, fields - 1, v.data(), path, error) ||
        !row(stamp, v.data(), csv)) {
      return false;
    }
  }
  return true;
}

void AppendFields(const double* values, int n, std::string* out) {
  for (int k = 0; k < n; ++k) {
    out->push_back(',');
    text::AppendDouble(values[k], out);
  }
}

bool AllFinite(const InertialData& data) {
  for (const ImuSample& s : data.imu) {
    if (!s.accel.allFinite() || !s.gyro.allFinite()) return false;
  }
  for (const PositionFix& f : data.positions) {
    if (!f.position.allFinite() || !f.orientation.coeffs().allFinite()) {
      return false;
    }
  }
  for (const InertialGroundTruth& g : data.ground_truth) {
    if (!g.pose.t.allFinite() || !g.pose.q.coeffs().allFinite() ||
        !g.velocity.allFinite() || !g.bias.allFinite()) {
      return false;
    }
  }
  return data.initial_state.pose.t.allFinite() &&
         data.initial_state.pose.q.coeffs().allFinite() &&
         data.initial_state.velocity.allFinite();
}

// An IMU reading no IMU produces: "PATH:LINE: accelerometer reading
// 9.2e18 m/s^2 (field 5) is beyond 2000 m/s^2".
bool CheckImuRanges(const CsvLines& csv, const Eigen::Vector3d& accel,
                    int accel_field, const Eigen::Vector3d& gyro,
                    int gyro_field, const std::string& path,
                    std::string* error) {
  for (int k = 0; k < 3; ++k) {
    const bool bad_accel = std::abs(accel[k]) > kMaxImuAccel;
    if (bad_accel || std::abs(gyro[k]) > kMaxImuGyro) {
      const int field = (bad_accel ? accel_field : gyro_field) + k;
      *error = Where(path, csv.line()) +
               (bad_accel ? "accelerometer" : "gyroscope") + " reading '" +
               text::Printable(csv.fields()[field - 1]) + "' " +
               (bad_accel ? "m/s^2" : "rad/s") + " (field " +
               std::to_string(field) + ") is beyond what an IMU measures (" +
               (bad_accel ? "2000 m/s^2" : "100 rad/s") + ")";
      return false;
    }
  }
  return true;
}

template <typename T>
bool StrictlyIncreasing(const std::vector<T>& v) {
  for (size_t k = 1; k < v.size(); ++k) {
    if (v[k].stamp <= v[k - 1].stamp) return false;
  }
  return true;
}

}  // namespace

bool ReadGtsamImuCsv(const std::string& path, double imu_dt, InertialData* data,
                     std::string* error) {
  if (!(imu_dt > 0.0) || !std::isfinite(imu_dt)) {
    *error = path + ": the IMU period must be positive";
    return false;
  }
  std::string contents;
  if (!text::ReadWholeFile(path, &contents, error)) return false;
  InertialData out;
  out.gravity = Eigen::Vector3d::Zero();
  out.interpolation = ImuInterpolation::kHold;
  CsvLines csv(contents);
  int64_t num_imu = 0;
  double v[10];
  while (csv.Next()) {
    const std::string_view type = csv.fields()[0];
    if (!out.has_initial_state) {
      if (type != "i") {
        *error = Where(path, csv.line()) +
                 "the first row must be the initial state 'i,x,y,z,qx,qy,qz,"
                 "qw,vx,vy,vz'";
        return false;
      }
      if (!CheckCount(csv, 11, "the initial state", path, error) ||
          !ParseFields(csv, 1, 10, v, path, error)) {
        return false;
      }
      Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
      const bool zero_q =
          v[3] == 0.0 && v[4] == 0.0 && v[5] == 0.0 && v[6] == 0.0;
      if (!zero_q &&
          !Quaternion(csv, v[3], v[4], v[5], v[6], &q, path, error)) {
        return false;
      }
      out.initial_state.pose = Pose3(Eigen::Vector3d(v[0], v[1], v[2]), q);
      out.initial_state.velocity = Eigen::Vector3d(v[7], v[8], v[9]);
      out.has_initial_state = true;
    } else if (type == "0") {
      if (!CheckCount(csv, 7, "an IMU row", path, error) ||
          !ParseFields(csv, 1, 6, v, path, error)) {
        return false;
      }
      ImuSample s;
      s.stamp = SecondsToNs(static_cast<double>(num_imu) * imu_dt);
      s.accel = Eigen::Vector3d(v[0], v[1], v[2]);
      s.gyro = Eigen::Vector3d(v[3], v[4], v[5]);
      if (!CheckImuRanges(csv, s.accel, 2, s.gyro, 5, path, error)) {
        return false;
      }
      out.imu.push_back(s);
      ++num_imu;
    } else if (type == "1") {
      if (!CheckCount(csv, 8, "a GPS row", path, error) ||
          !ParseFields(csv, 1, 7, v, path, error)) {
        return false;
      }
      PositionFix f;
      f.stamp = SecondsToNs(static_cast<double>(num_imu) * imu_dt);
      if (!out.positions.empty() && out.positions.back().stamp == f.stamp) {
        *error = Where(path, csv.line()) +
                 "two GPS rows without an IMU row between them";
        return false;
      }
      f.position = Eigen::Vector3d(v[0], v[1], v[2]);
      f.has_orientation = true;
      if (!Quaternion(csv, v[3], v[4], v[5], v[6], &f.orientation, path,
                      error)) {
        return false;
      }
      out.positions.push_back(f);
    } else {
      *error = Where(path, csv.line()) + "unknown row type '" +
               text::Printable(type) +
               "' (expected 0 = IMU, 1 = GPS; 'i' only on the first row)";
      return false;
    }
  }
  if (!out.has_initial_state) {
    *error = path + ": no initial state row";
    return false;
  }
  if (out.imu.empty()) {
    *error = path + ": no IMU rows ('0,ax,ay,az,wx,wy,wz')";
    return false;
  }
  *data = std::move(out);
  return true;
}

bool WriteGtsamImuCsv(const std::string& path, const InertialData& data,
                      std::string* error) {
  if (!data.has_initial_state) {
    *error = path + ": the GTSAM format needs an initial state";
    return false;
  }
  if (!AllFinite(data) || !StrictlyIncreasing(data.imu) ||
      !StrictlyIncreasing(data.positions)) {
    *error = path + ": non-finite values or stamps not strictly increasing";
    return false;
  }
  std::string out;
  out.reserve(64 * (data.imu.size() + data.positions.size() + 1));
  const NavState& s0 = data.initial_state;
  const double init[10] = {s0.pose.t.x(),  s0.pose.t.y(),   s0.pose.t.z(),
                           s0.pose.q.x(),  s0.pose.q.y(),   s0.pose.q.z(),
                           s0.pose.q.w(),  s0.velocity.x(), s0.velocity.y(),
                           s0.velocity.z()};
  out += "i";
  AppendFields(init, 10, &out);
  out.push_back('\n');
  size_t next_fix = 0;
  auto write_fixes_before = [&](TimeNs stamp, bool all) {
    while (next_fix < data.positions.size() &&
           (all || data.positions[next_fix].stamp <= stamp)) {
      const PositionFix& f = data.positions[next_fix++];
      const Eigen::Quaterniond q =
          f.has_orientation ? f.orientation : Eigen::Quaterniond::Identity();
      const double values[7] = {f.position.x(), f.position.y(), f.position.z(),
                                q.x(),          q.y(),          q.z(),
                                q.w()};
      out += "1";
      AppendFields(values, 7, &out);
      out.push_back('\n');
    }
  };
  for (const ImuSample& s : data.imu) {
    write_fixes_before(s.stamp, false);
    const double values[6] = {s.accel.x(), s.accel.y(), s.accel.z(),
                              s.gyro.x(),  s.gyro.y(),  s.gyro.z()};
    out += "0";
    AppendFields(values, 6, &out);
    out.push_back('\n');
  }
  write_fixes_before(0, true);
  return WriteFileAtomically(path, out, error);
}

namespace {

std::string Mav0(const std::string& folder) {
  std::error_code ec;
  if (std::filesystem::is_directory(folder + "/mav0", ec)) {
    return folder + "/mav0";
  }
  return folder;
}

bool FileExists(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

}  // namespace

bool ReadEurocInertial(const std::string& folder, InertialData* data,
                       std::string* error) {
  const std::string mav0 = Mav0(folder);
  InertialData out;
  out.gravity = DefaultGravity();

  const std::string imu_path = mav0 + "/imu0/data.csv";
  out.imu_path = imu_path;
  if (!FileExists(imu_path)) {
    *error = folder + ": no mav0/imu0/data.csv (not an EuRoC folder)";
    return false;
  }
  if (!ReadStampedRows(
          imu_path, 7, "an IMU row", error,
          [&](TimeNs stamp, const double* v, const CsvLines& csv) {
            ImuSample s;
            s.stamp = stamp;
            s.gyro = Eigen::Vector3d(v[0], v[1], v[2]);
            s.accel = Eigen::Vector3d(v[3], v[4], v[5]);
            if (!CheckImuRanges(csv, s.accel, 5, s.gyro, 2, imu_path, error)) {
              return false;
            }
            // Stamps increase (checked): the unsigned
            // difference cannot overflow.
            const uint64_t gap =
                out.imu.empty()
                    ? 0
                    : static_cast<uint64_t>(stamp) -
                          static_cast<uint64_t>(out.imu.back().stamp);
            if (gap > static_cast<uint64_t>(kMaxImuGap)) {
              *error = Where(imu_path, csv.line()) + "a gap of " +
                       std::to_string(static_cast<double>(gap) * 1e-9) +
                       " s since the previous IMU reading "
                       "(more than 1 s of missing IMU data)";
              return false;
            }
            out.imu.push_back(s);
            out.imu_lines.push_back(csv.line());
            return true;
          })) {
    return false;
  }
  if (out.imu.empty()) {
    *error = imu_path + ": no IMU readings";
    return false;
  }

  const std::string gt_path = mav0 + "/state_groundtruth_estimate0/data.csv";
  if (FileExists(gt_path) &&
      !ReadStampedRows(gt_path, 17, "a ground-truth row", error,
                       [&](TimeNs stamp, const double* v, const CsvLines& csv) {
                         InertialGroundTruth g;
                         g.stamp = stamp;
                         Eigen::Quaterniond q;
                         // EuRoC writes the quaternion w first.
                         if (!Quaternion(csv, v[4], v[5], v[6], v[3], &q,
                                         gt_path, error)) {
                           return false;
                         }
                         g.pose = Pose3(Eigen::Vector3d(v[0], v[1], v[2]), q);
                         g.velocity = Eigen::Vector3d(v[7], v[8], v[9]);
                         g.bias << v[10], v[11], v[12], v[13], v[14], v[15];
                         out.ground_truth.push_back(g);
                         return true;
                       })) {
    return false;
  }

  const std::string fix_path = mav0 + "/leica0/data.csv";
  if (FileExists(fix_path) &&
      !ReadStampedRows(fix_path, 4, "a position row", error,
                       [&](TimeNs stamp, const double* v, const CsvLines&) {
                         PositionFix f;
                         f.stamp = stamp;
                         f.position = Eigen::Vector3d(v[0], v[1], v[2]);
                         out.positions.push_back(f);
                         return true;
                       })) {
    return false;
  }
  *data = std::move(out);
  return true;
}

bool WriteEurocInertial(const std::string& folder, const InertialData& data,
                        std::string* error) {
  if (!AllFinite(data) || !StrictlyIncreasing(data.imu) ||
      !StrictlyIncreasing(data.positions) ||
      !StrictlyIncreasing(data.ground_truth)) {
    *error = folder + ": non-finite values or stamps not strictly increasing";
    return false;
  }
  const std::string mav0 = folder + "/mav0";
  std::error_code ec;
  for (const char* sub : {"/imu0", "/state_groundtruth_estimate0", "/leica0"}) {
    if (std::string(sub) == "/state_groundtruth_estimate0" &&
        data.ground_truth.empty()) {
      continue;
    }
    if (std::string(sub) == "/leica0" && data.positions.empty()) continue;
    std::filesystem::create_directories(mav0 + sub, ec);
    if (ec) {
      *error = mav0 + sub + ": cannot create the folder: " + ec.message();
      return false;
    }
  }

  std::string out =
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],"
      "w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],"
      "a_RS_S_z [m s^-2]\n";
  for (const ImuSample& s : data.imu) {
    text::AppendInt(s.stamp, &out);
    const double values[6] = {s.gyro.x(),  s.gyro.y(),  s.gyro.z(),
                              s.accel.x(), s.accel.y(), s.accel.z()};
    AppendFields(values, 6, &out);
    out.push_back('\n');
  }
  if (!WriteFileAtomically(mav0 + "/imu0/data.csv", out, error)) return false;

  if (!data.ground_truth.empty()) {
    out =
        "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], "
        "q_RS_x [], q_RS_y [], q_RS_z [], v_RS_R_x [m s^-1], "
        "v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], "
        "b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], "
        "b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
    for (const InertialGroundTruth& g : data.ground_truth) {
      text::AppendInt(g.stamp, &out);
      const Eigen::Quaterniond& q = g.pose.q;
      const double values[16] = {
          g.pose.t.x(),   g.pose.t.y(),   g.pose.t.z(), q.w(),
          q.x(),          q.y(),          q.z(),        g.velocity.x(),
          g.velocity.y(), g.velocity.z(), g.bias[0],    g.bias[1],
          g.bias[2],      g.bias[3],      g.bias[4],    g.bias[5]};
      AppendFields(values, 16, &out);
      out.push_back('\n');
    }
    if (!WriteFileAtomically(mav0 + "/state_groundtruth_estimate0/data.csv",
                             out, error)) {
      return false;
    }
  }

  if (!data.positions.empty()) {
    out = "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m]\n";
    for (const PositionFix& f : data.positions) {
      text::AppendInt(f.stamp, &out);
      AppendFields(f.position.data(), 3, &out);
      out.push_back('\n');
    }
    if (!WriteFileAtomically(mav0 + "/leica0/data.csv", out, error)) {
      return false;
    }
  }
  return true;
}

}  // namespace slam
