#include "datasets/kitti_sequence_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "datasets/text_util.h"

namespace slam {
namespace {

namespace fs = std::filesystem;

// What the text files can plausibly need: calib.txt holds a few lines of 12
// numbers; times.txt one stamp (about 20 bytes) a frame, for millions of
// frames. Larger files (or /dev/zero) are refused before parsing.
constexpr size_t kMaxCalibrationBytes = size_t{1} << 20;  // 1 MiB.
constexpr size_t kMaxTimesBytes = size_t{64} << 20;       // 64 MiB.

bool IsImageExtension(std::string ext) {
  for (char& c : ext) c = static_cast<char>(std::tolower(c));
  static const char* const kExtensions[] = {
      ".png", ".webp", ".jpg", ".jpeg", ".bmp", ".pgm", ".ppm", ".pnm",
      ".tif", ".tiff", ".jp2", ".exr",  ".hdr", ".sr",  ".ras"};
  for (const char* e : kExtensions) {
    if (ext == e) return true;
  }
  return false;
}

// Sort key: the first run of digits as a number (with its length to keep
// huge numbers ordered), then the whole name.
struct NameKey {
  bool has_number = false;
  std::string digits;  // Without leading zeros.
  std::string name;
  bool operator<(const NameKey& o) const {
    if (has_number != o.has_number) return has_number;
    if (digits.size() != o.digits.size())
      return digits.size() < o.digits.size();
    if (digits != o.digits) return digits < o.digits;
    return name < o.name;
  }
};

NameKey KeyOf(const std::string& name) {
  NameKey key;
  key.name = name;
  const size_t start = name.find_first_of("0123456789");
  if (start == std::string::npos) return key;
  size_t end = start;
  while (end < name.size() &&
         std::isdigit(static_cast<unsigned char>(name[end])))
    ++end;
  key.has_number = true;
  key.digits = name.substr(start, end - start);
  key.digits.erase(
      0, std::min(key.digits.find_first_not_of('0'), key.digits.size() - 1));
  return key;
}

// Days from 1970-01-01 to the given civil date (proleptic Gregorian; H.
// Hinnant's days_from_civil).
int64_t DaysFromCivil(int64_t y, int m, int d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const int64_t yoe = y - era * 400;
  const int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

// The width and height of a PNG file from its header; false if it is not
// a readable PNG.
bool PngSize(const std::string& path, int* width, int* height) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  unsigned char h[24];
  const size_t n = std::fread(h, 1, sizeof(h), f);
  std::fclose(f);
  static const unsigned char kSignature[8] = {0x89, 'P',  'N',  'G',
                                              '\r', '\n', 0x1a, '\n'};
  if (n != sizeof(h) || std::memcmp(h, kSignature, 8) != 0 ||
      std::memcmp(h + 12, "IHDR", 4) != 0) {
    return false;
  }
  auto be32 = [&](int at) {
    return static_cast<int64_t>(h[at]) << 24 | h[at + 1] << 16 |
           h[at + 2] << 8 | h[at + 3];
  };
  if (be32(16) > (1 << 20) || be32(20) > (1 << 20)) return false;
  *width = static_cast<int>(be32(16));
  *height = static_cast<int>(be32(20));
  return true;
}

// The "S_rect_00:" or "S_00:" (image size) line of calib_cam_to_cam.txt;
// false if absent or malformed.
bool CalibrationImageSize(const std::string& path, const char* label,
                          int* width, int* height) {
  std::string text, error;
  if (!text::ReadWholeFile(path, &text, &error)) return false;
  text::LineTokenizer lines(text);
  while (lines.Next()) {
    const auto& tokens = lines.tokens();
    if (tokens[0] != label || tokens.size() != 3) continue;
    double w = 0, h = 0;
    if (!text::ParseDouble(tokens[1], &w) || !text::ParseDouble(tokens[2], &h))
      return false;
    *width = static_cast<int>(std::lround(w));
    *height = static_cast<int>(std::lround(h));
    return true;
  }
  return false;
}

}  // namespace

bool ParseKittiRawTimestamp(std::string_view text, TimeNs* stamp) {
  // YYYY-MM-DD HH:MM:SS[.fraction], at most 9 fraction digits.
  auto digits = [&](size_t at, size_t count, int* value) {
    if (at + count > text.size()) return false;
    *value = 0;
    for (size_t k = at; k < at + count; ++k) {
      if (!std::isdigit(static_cast<unsigned char>(text[k]))) return false;
      *value = *value * 10 + (text[k] - '0');
    }
    return true;
  };
  int year, month, day, hour, minute, second;
  if (text.size() < 19 || !digits(0, 4, &year) || text[4] != '-' ||
      !digits(5, 2, &month) || text[7] != '-' || !digits(8, 2, &day) ||
      (text[10] != ' ' && text[10] != 'T') || !digits(11, 2, &hour) ||
      text[13] != ':' || !digits(14, 2, &minute) || text[16] != ':' ||
      !digits(17, 2, &second)) {
    return false;
  }
  if (month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 ||
      minute > 59 || second > 60) {
    return false;
  }
  int64_t nanoseconds = 0;
  if (text.size() > 19) {
    if (text[19] != '.' || text.size() == 20 || text.size() > 29) return false;
    int64_t scale = 100000000;
    for (size_t k = 20; k < text.size(); ++k, scale /= 10) {
      if (!std::isdigit(static_cast<unsigned char>(text[k]))) return false;
      nanoseconds += (text[k] - '0') * scale;
    }
  }
  const int64_t seconds = DaysFromCivil(year, month, day) * 86400 +
                          hour * 3600 + minute * 60 + second;
  *stamp = seconds * 1000000000 + nanoseconds;
  return true;
}

bool ListImageFiles(const std::string& dir, std::vector<std::string>* paths,
                    std::string* error) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = dir + ": not a directory";
    return false;
  }
  std::vector<std::pair<NameKey, std::string>> found;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    // Not only regular files: a FIFO, folder or broken link named like an
    // image is a frame whose image cannot be read (an error when decoded),
    // not a frame silently dropped (poses.txt is paired by index).
    const fs::path& p = it->path();
    if (!IsImageExtension(p.extension().string())) continue;
    found.emplace_back(KeyOf(p.filename().string()), p.string());
  }
  if (ec) {
    *error = dir + ": cannot list: " + ec.message();
    return false;
  }
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  paths->clear();
  for (auto& f : found) paths->push_back(std::move(f.second));
  return true;
}

bool ReadKittiStereoCalibration(const std::string& path,
                                StereoCalibration* calibration,
                                std::string* error) {
  std::string text;
  if (!text::ReadWholeFile(path, &text, error, kMaxCalibrationBytes))
    return false;
  text::LineTokenizer lines(text);
  double p[2][12];
  bool have[2] = {false, false};
  int64_t line_of[2] = {0, 0};
  int unlabelled = 0;
  auto fail = [&](int64_t line, const std::string& problem) {
    *error = path + ":" + std::to_string(line) + ": " + problem;
    return false;
  };
  while (lines.Next()) {
    const auto& tokens = lines.tokens();
    int which = -1;
    size_t first = 0;
    const std::string_view head = tokens[0];
    if (!head.empty() && head.back() == ':') {
      if (head == "P0:" || head == "P_rect_00:") which = 0;
      if (head == "P1:" || head == "P_rect_01:") which = 1;
      if (which < 0) continue;  // P2, P3, Tr, ...: not needed.
      first = 1;
    } else {
      if (unlabelled >= 2) continue;  // Further unlabelled lines: P2, P3.
      which = unlabelled++;
    }
    if (tokens.size() != first + 12) {
      return fail(lines.line(), "a projection matrix needs 12 numbers, found " +
                                    std::to_string(tokens.size() - first));
    }
    for (int k = 0; k < 12; ++k) {
      if (!text::ParseDouble(tokens[first + k], &p[which][k])) {
        return fail(lines.line(), "number " + std::to_string(k + 1) +
                                      " is not a finite number: '" +
                                      text::Printable(tokens[first + k]) + "'");
      }
    }
    if (have[which]) {
      return fail(lines.line(), std::string("P") + char('0' + which) +
                                    " given twice (also on line " +
                                    std::to_string(line_of[which]) + ")");
    }
    have[which] = true;
    line_of[which] = lines.line();
  }
  if (!have[0] || !have[1]) {
    *error = path +
             ": needs the projection matrices P0 and P1 (labelled "
             "'P0:'/'P1:' or 'P_rect_00:'/'P_rect_01:', or the first two "
             "unlabelled lines), found " +
             std::string(have[0]   ? "only P0"
                         : have[1] ? "only P1"
                                   : "neither");
    return false;
  }
  // Row-major 3x4: index r * 4 + c.
  const double fx = p[0][0], fy = p[0][5], cx = p[0][2], cy = p[0][6];
  const double tol = 1e-6 * std::max(1.0, std::abs(fx));
  if (!(fx > 0) || !(fy > 0)) {
    return fail(line_of[0], "P0 needs positive focal lengths P[0][0], P[1][1]");
  }
  for (int w = 0; w < 2; ++w) {
    const double* m = p[w];
    const bool shape = std::abs(m[1]) <= tol && std::abs(m[4]) <= tol &&
                       std::abs(m[8]) <= tol && std::abs(m[9]) <= tol &&
                       std::abs(m[10] - 1.0) <= 1e-9 && std::abs(m[11]) <= tol;
    if (!shape) {
      return fail(line_of[w],
                  "not the projection matrix of a rectified camera: expected "
                  "[fx 0 cx tx; 0 fy cy 0; 0 0 1 0]");
    }
    if (std::abs(m[0] - fx) > tol || std::abs(m[5] - fy) > tol ||
        std::abs(m[2] - cx) > tol || std::abs(m[6] - cy) > tol) {
      return fail(line_of[1],
                  "P1's intrinsics differ from P0's: the pair is not "
                  "rectified");
    }
    if (std::abs(m[7]) > tol) {
      return fail(line_of[w],
                  "vertical offset P[1][3] must be 0 in a "
                  "rectified pair");
    }
  }
  if (std::abs(p[0][3]) > tol) {
    return fail(line_of[0], "P0 must have no translation (P0[0][3] = 0)");
  }
  const double baseline = -p[1][3] / p[1][0];
  if (!(baseline > 0) || !std::isfinite(baseline)) {
    return fail(line_of[1],
                "the baseline -P1[0][3] / P1[0][0] must be positive (right "
                "camera to the right of the left one)");
  }
  // Plausible ranges (the image size is checked with the first image,
  // frontends/stereo/stereo_images.h): a rig from 0.1 mm to 10 km apart in
  // the calibration's unit (KITTI: metres; millimetres still fit), pixels
  // at most 4 times taller than wide.
  auto number = [](double v) {
    std::string out;
    text::AppendDouble(v, &out);
    return out;
  };
  if (baseline < 1e-4 || baseline > 1e4) {
    return fail(line_of[1],
                "baseline -P1[0][3] / P1[0][0] = " + number(baseline) +
                    " outside [1e-4, 1e4] (metres in KITTI's "
                    "calib.txt): not a stereo rig");
  }
  if (fy > 4 * fx || fx > 4 * fy) {
    return fail(line_of[0], "focal lengths fx = " + number(fx) +
                                " and fy = " + number(fy) +
                                " differ by more than a factor of 4");
  }
  calibration->fx = fx;
  calibration->fy = fy;
  calibration->cx = cx;
  calibration->cy = cy;
  calibration->baseline = baseline;
  return true;
}

bool ReadKittiSequence(const std::string& dir,
                       const KittiSequenceOptions& options,
                       KittiSequence* sequence, std::string* error) {
  KittiSequence s;
  s.dir = dir;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = dir +
             ": not a directory (expected a KITTI sequence folder with "
             "image_0/, image_1/ and calib.txt)";
    return false;
  }
  const fs::path root(dir);
  s.raw_layout = fs::is_directory(root / "image_00" / "data", ec);
  const std::string left_name = s.raw_layout ? "image_00" : "image_0";
  const std::string right_name = s.raw_layout ? "image_01" : "image_1";
  const fs::path left_dir =
      s.raw_layout ? root / "image_00" / "data" : root / "image_0";
  const fs::path right_dir =
      s.raw_layout ? root / "image_01" / "data" : root / "image_1";
  if (!ListImageFiles(left_dir.string(), &s.left_images, error) ||
      !ListImageFiles(right_dir.string(), &s.right_images, error)) {
    return false;
  }
  if (s.left_images.empty()) {
    *error = left_dir.string() + ": no image files";
    return false;
  }
  if (s.left_images.size() != s.right_images.size()) {
    *error = dir + ": " + left_name + " has " +
             std::to_string(s.left_images.size()) + " images but " +
             right_name + " has " + std::to_string(s.right_images.size());
    return false;
  }
  for (size_t k = 0; k < s.left_images.size(); ++k) {
    const std::string l = fs::path(s.left_images[k]).filename().string();
    const std::string r = fs::path(s.right_images[k]).filename().string();
    if (l != r) {
      *error = dir + ": frame " + std::to_string(k) + " is " +
               s.left_images[k] + " on the left but " + s.right_images[k] +
               " on the right (" + left_name + " and " + right_name +
               " must hold the same names)";
      return false;
    }
  }
  s.calibration_path = options.calibration_path;
  if (s.calibration_path.empty() && !s.raw_layout) {
    s.calibration_path = (root / "calib.txt").string();
  } else if (s.calibration_path.empty()) {
    // In the drive folder, else in the date folder above it (as unpacked).
    const fs::path parent = fs::absolute(root, ec).parent_path();
    s.calibration_path = (root / "calib_cam_to_cam.txt").string();
    if (!fs::exists(s.calibration_path, ec) &&
        fs::exists(parent / "calib_cam_to_cam.txt", ec)) {
      s.calibration_path = (parent / "calib_cam_to_cam.txt").string();
    }
  }
  if (!ReadKittiStereoCalibration(s.calibration_path, &s.calibration, error)) {
    return false;
  }
  const size_t n = s.left_images.size();
  if (s.raw_layout) {
    // Unrectified images (the "extract" download) have the raw sensor size
    // S_00, the rectified ones S_rect_00: P_rect only fits the latter.
    std::string name = fs::absolute(root, ec).lexically_normal().string();
    while (!name.empty() && name.back() == '/') name.pop_back();
    int w = 0, h = 0, rw = 0, rh = 0, sw = 0, sh = 0;
    const bool extract_name =
        name.size() >= 8 && name.compare(name.size() - 8, 8, "_extract") == 0;
    if (extract_name ||
        (PngSize(s.left_images[0], &w, &h) &&
         CalibrationImageSize(s.calibration_path, "S_00:", &sw, &sh) &&
         w == sw && h == sh &&
         !(CalibrationImageSize(s.calibration_path, "S_rect_00:", &rw, &rh) &&
           w == rw && h == rh))) {
      *error = dir +
               ": unrectified KITTI raw images (the 'extract' download"
               "; " +
               (extract_name ? std::string("folder name")
                             : "image size " + std::to_string(w) + "x" +
                                   std::to_string(h) + " = S_00") +
               "): the stereo frontend needs the rectified 'sync' images";
      return false;
    }
  }
  const std::string raw_times = (root / "image_00" / "timestamps.txt").string();
  const std::string times_path = !options.times_path.empty()
                                     ? options.times_path
                                 : s.raw_layout ? raw_times
                                                : (root / "times.txt").string();
  const bool date_times = s.raw_layout && options.times_path.empty();
  if (!options.times_path.empty() || fs::exists(times_path, ec)) {
    std::string text;
    if (!text::ReadWholeFile(times_path, &text, error, kMaxTimesBytes))
      return false;
    text::LineTokenizer lines(text);
    while (lines.Next()) {
      const auto& tokens = lines.tokens();
      TimeNs stamp = 0;
      if (date_times) {
        // "2011-09-26 13:02:25.967790592": two tokens.
        const std::string joined =
            std::string(tokens[0]) +
            (tokens.size() > 1 ? " " + std::string(tokens[1]) : "");
        if (tokens.size() != 2 || !ParseKittiRawTimestamp(joined, &stamp)) {
          *error = times_path + ":" + std::to_string(lines.line()) +
                   ": expected a date-time stamp 'YYYY-MM-DD "
                   "HH:MM:SS.fraction', found '" +
                   text::Printable(joined) + "'";
          return false;
        }
      } else {
        double seconds = 0.0;
        if (tokens.size() != 1 || !text::ParseDouble(tokens[0], &seconds) ||
            std::abs(seconds) > 1e10) {
          *error = times_path + ":" + std::to_string(lines.line()) +
                   ": expected one stamp in seconds (|t| <= 1e10), found '" +
                   text::Printable(tokens[0]) + "'" +
                   (tokens.size() != 1 ? " and more" : "");
          return false;
        }
        stamp = SecondsToNs(seconds);
      }
      if (s.stamps.size() == n) {
        *error = times_path + ":" + std::to_string(lines.line()) +
                 ": more stamps than the " + std::to_string(n) + " images";
        return false;
      }
      if (!s.stamps.empty() && stamp <= s.stamps.back()) {
        *error = times_path + ":" + std::to_string(lines.line()) +
                 ": stamps must increase strictly";
        return false;
      }
      s.stamps.push_back(stamp);
    }
    if (s.stamps.size() != n) {
      *error = times_path + ": " + std::to_string(s.stamps.size()) +
               " stamps for " + std::to_string(n) + " images";
      return false;
    }
    s.has_times = true;
  } else {
    if (!(options.default_frame_period > 0) ||
        !(options.default_frame_period < 1e3)) {
      *error = "default frame period must be in (0, 1000) s";
      return false;
    }
    for (size_t k = 0; k < n; ++k) {
      s.stamps.push_back(SecondsToNs(k * options.default_frame_period));
    }
  }
  const fs::path gt = root / "poses.txt";
  if (fs::is_regular_file(gt, ec)) s.ground_truth_path = gt.string();
  *sequence = std::move(s);
  return true;
}

}  // namespace slam
