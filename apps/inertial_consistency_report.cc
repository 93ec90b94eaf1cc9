#include "apps/inertial_consistency_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "datasets/text_util.h"

namespace slam {
namespace {

using text::AppendDouble;
using text::AppendInt;
using text::ParseDouble;
using text::ParseInt64;
using text::Printable;

constexpr int kDim = 15;
constexpr int kUpper = kDim * (kDim + 1) / 2;  // 120

struct Axis {
  const char* name;
  const char* unit;
};
constexpr Axis kAxes[kDim] = {
    {"px", "m"},      {"py", "m"},      {"pz", "m"},      {"thx", "rad"},
    {"thy", "rad"},   {"thz", "rad"},   {"vx", "m/s"},    {"vy", "m/s"},
    {"vz", "m/s"},    {"bgx", "rad/s"}, {"bgy", "rad/s"}, {"bgz", "rad/s"},
    {"bax", "m/s^2"}, {"bay", "m/s^2"}, {"baz", "m/s^2"}};

std::string Header() {
  std::string h = "#timestamp [ns]";
  for (int i = 0; i < kDim; ++i) {
    for (int j = i; j < kDim; ++j) {
      h += ",cov(";
      h += kAxes[i].name;
      h += ",";
      h += kAxes[j].name;
      h += ") [";
      h += kAxes[i].unit;
      h += "*";
      h += kAxes[j].unit;
      h += "]";
    }
  }
  return h + "\n";
}

// Fields of a CSV line (no quoting: the header's commas are only inside the
// column names' parentheses, and header lines are skipped by the caller).
std::vector<std::string_view> SplitCommas(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    std::string_view f = line.substr(
        start, comma == std::string_view::npos ? comma : comma - start);
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) {
      f.remove_prefix(1);
    }
    while (!f.empty() &&
           (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) {
      f.remove_suffix(1);
    }
    fields.push_back(f);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

JsonObject StatsJson(const NeesStats& s, int dof) {
  JsonObject j;
  j.Add("mean", s.mean).Add("median", s.median).Add("dof", dof);
  return j;
}

JsonObject BlocksJson(const NeesSummary& s) {
  JsonObject j;
  j.Add("position", StatsJson(s.position, 3))
      .Add("pose", StatsJson(s.pose, 6))
      .Add("velocity", StatsJson(s.velocity, 3))
      .Add("bias", StatsJson(s.bias, 6))
      .Add("gyro_bias", StatsJson(s.gyro_bias, 3))
      .Add("accel_bias", StatsJson(s.accel_bias, 3));
  return j;
}

void PrintRow(const char* label, const NeesSummary& s, std::ostream& out) {
  char line[240];
  std::snprintf(line, sizeof(line),
                "  %-22s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f   (median %.2f "
                "%.2f %.2f %.2f)\n",
                label, s.position.mean, s.pose.mean, s.velocity.mean,
                s.bias.mean, s.gyro_bias.mean, s.accel_bias.mean,
                s.position.median, s.pose.median, s.velocity.median,
                s.bias.median);
  out << line;
}

}  // namespace

std::string StatesCsv(const std::vector<InertialState>& states) {
  std::string out = "#timestamp [ns],vx,vy,vz,bgx,bgy,bgz,bax,bay,baz\n";
  char buffer[64];
  for (const InertialState& s : states) {
    out += std::to_string(s.stamp);
    for (int i = 0; i < 3; ++i) {
      std::snprintf(buffer, sizeof(buffer), ",%.17g", s.state.velocity[i]);
      out += buffer;
    }
    for (int i = 0; i < 6; ++i) {
      std::snprintf(buffer, sizeof(buffer), ",%.17g", s.bias[i]);
      out += buffer;
    }
    out += "\n";
  }
  return out;
}

std::string CovarianceCsv(const std::vector<InertialState>& states,
                          const std::vector<Eigen::MatrixXd>& covariances) {
  std::string out = Header();
  for (size_t k = 0; k < states.size() && k < covariances.size(); ++k) {
    AppendInt(states[k].stamp, &out);
    const Eigen::MatrixXd& c = covariances[k];
    for (int i = 0; i < kDim; ++i) {
      for (int j = i; j < kDim; ++j) {
        out += ',';
        AppendDouble(c(i, j), &out);
      }
    }
    out += '\n';
  }
  return out;
}

bool ParseCovarianceCsv(const std::string& text, std::vector<TimeNs>* stamps,
                        std::vector<Eigen::MatrixXd>* covariances,
                        std::string* error) {
  stamps->clear();
  covariances->clear();
  size_t pos = 0;
  int line_number = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> f = SplitCommas(line);
    const std::string where = "line " + std::to_string(line_number) + ": ";
    if (f.size() != 1 + kUpper) {
      *error = where + "expected " + std::to_string(1 + kUpper) +
               " fields, found " + std::to_string(f.size());
      return false;
    }
    int64_t stamp;
    if (!ParseInt64(f[0], &stamp)) {
      *error = where + "bad stamp '" + Printable(f[0]) + "'";
      return false;
    }
    Eigen::MatrixXd c(kDim, kDim);
    size_t n = 1;
    for (int i = 0; i < kDim; ++i) {
      for (int j = i; j < kDim; ++j, ++n) {
        double v;
        if (!ParseDouble(f[n], &v)) {
          *error = where + "bad number '" + Printable(f[n]) + "' in field " +
                   std::to_string(n + 1);
          return false;
        }
        c(i, j) = c(j, i) = v;
      }
    }
    stamps->push_back(stamp);
    covariances->push_back(c);
  }
  return true;
}

bool EvaluateNees(const std::string& name,
                  const std::vector<InertialState>& states,
                  const std::vector<Eigen::MatrixXd>& covariances,
                  const std::vector<InertialGroundTruth>& reference,
                  const NeesOptions& options, double yaw_known_seconds,
                  std::ostream& out, JsonObject* json, std::string* error) {
  NeesSummary raw, aligned;
  if (!SummarizeNees(states, covariances, reference, options, &raw, error)) {
    return false;
  }
  NeesOptions yaw_options = options;
  yaw_options.yaw_offset = EstimateYawOffset(states, reference, options);
  if (!SummarizeNees(states, covariances, reference, yaw_options, &aligned,
                     error)) {
    return false;
  }
  const double yaw_deg = yaw_options.yaw_offset * 180.0 / M_PI;
  char line[240];
  std::snprintf(line, sizeof(line),
                "\nNEES of %s (%d keyframes after the first %g s; expected "
                "3, 6, 3, 6, 3, 3):\n  %-22s %8s %8s %8s %8s %8s %8s\n",
                name.c_str(), raw.keyframes, options.skip_seconds, "",
                "position", "pose", "velocity", "bias", "gyro b", "accel b");
  out << line;
  PrintRow("mean", raw, out);
  std::snprintf(line, sizeof(line), "reference yaw %+.2f deg", yaw_deg);
  PrintRow(line, aligned, out);
  *json = BlocksJson(raw);
  json->Add("keyframes", raw.keyframes)
      .Add("skip_seconds", options.skip_seconds);
  JsonObject yaw = BlocksJson(aligned);
  yaw.Add("yaw_offset_deg", yaw_deg);
  json->Add("yaw_aligned", yaw);
  // Only the keyframes from the one the heading became known: before it the
  // estimate rides on an arbitrary heading (see the initializer), and its
  // bias errors there are the alignment's, not the steady filter's.
  if (yaw_known_seconds >= 0.0) {
    NeesOptions after_options = options;
    after_options.skip_seconds =
        std::max(options.skip_seconds, yaw_known_seconds);
    NeesSummary after;
    std::string unused;
    if (SummarizeNees(states, covariances, reference, after_options, &after,
                      &unused)) {
      std::snprintf(line, sizeof(line), "after the yaw (%.1f s)",
                    after_options.skip_seconds);
      PrintRow(line, after, out);
      JsonObject after_json = BlocksJson(after);
      // The real-time rotation error once the heading is known (issue 25's
      // rotation target; before it the heading is arbitrary).
      after_json.Add("keyframes", after.keyframes)
          .Add("skip_seconds", after_options.skip_seconds)
          .Add("rotation_rmse_deg", after.rotation_rmse * 180.0 / M_PI);
      std::snprintf(line, sizeof(line),
                    "  rotation error after the yaw: %.2f deg rmse\n",
                    after.rotation_rmse * 180.0 / M_PI);
      out << line;
      json->Add("after_yaw", after_json);
    }
  }
  return true;
}

}  // namespace slam
