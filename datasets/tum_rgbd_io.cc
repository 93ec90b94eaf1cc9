#include "datasets/tum_rgbd_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>

#include "datasets/text_util.h"

namespace slam {

namespace fs = std::filesystem;

bool ReadTumImageList(const std::string& path, const std::string& dir,
                      bool allow_equal_stamps,
                      std::vector<TumImageEntry>* entries, std::string* error) {
  entries->clear();
  std::string text;
  if (!text::ReadWholeFile(path, &text, error)) return false;
  text::LineTokenizer lines(text);
  while (lines.Next()) {
    const auto& tokens = lines.tokens();
    const std::string where = path + ":" + std::to_string(lines.line()) + ": ";
    if (tokens.size() != 2) {
      *error = where + "expected 'timestamp path', found " +
               std::to_string(tokens.size()) + " fields";
      return false;
    }
    TumImageEntry e;
    if (!text::ParseDouble(tokens[0], &e.seconds) || e.seconds < 0 ||
        e.seconds > 1e11) {
      *error = where + "'" + text::Printable(tokens[0]) +
               "' is not a timestamp in seconds";
      return false;
    }
    e.stamp = SecondsToNs(e.seconds);
    e.path = (fs::path(dir) / std::string(tokens[1])).string();
    e.line = lines.line();
    if (!entries->empty()) {
      const TumImageEntry& last = entries->back();
      if (e.seconds < last.seconds ||
          (e.seconds == last.seconds && !allow_equal_stamps)) {
        *error = where + "stamp " + std::string(tokens[0]) +
                 (e.seconds < last.seconds ? " goes backwards (line "
                                           : " repeats the stamp of line ") +
                 std::to_string(last.line) +
                 (e.seconds < last.seconds ? " is later)" : ")");
        return false;
      }
    }
    entries->push_back(std::move(e));
  }
  if (entries->empty()) {
    *error = path + ": no 'timestamp path' line";
    return false;
  }
  return true;
}

std::vector<std::pair<size_t, size_t>> AssociateStamps(
    const std::vector<double>& a, const std::vector<double>& b,
    double max_difference) {
  // The candidates: b is sorted, so each a's partners lie in one window.
  std::vector<std::tuple<double, size_t, size_t>> candidates;
  for (size_t i = 0; i < a.size(); ++i) {
    auto it = std::lower_bound(b.begin(), b.end(), a[i] - max_difference);
    for (; it != b.end() && *it < a[i] + max_difference; ++it) {
      const double d = std::abs(a[i] - *it);
      if (d < max_difference) {
        candidates.emplace_back(d, i, static_cast<size_t>(it - b.begin()));
      }
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> used_a(a.size(), false), used_b(b.size(), false);
  std::vector<std::pair<size_t, size_t>> matches;
  for (const auto& [d, i, j] : candidates) {
    if (used_a[i] || used_b[j]) continue;
    used_a[i] = used_b[j] = true;
    matches.emplace_back(i, j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

bool ReadTumRgbdSequence(const std::string& dir, const TumRgbdOptions& options,
                         TumRgbdSequence* sequence, std::string* error) {
  *sequence = TumRgbdSequence();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = dir + ": not a directory";
    return false;
  }
  sequence->dir = dir;
  sequence->rgb_list = (fs::path(dir) / "rgb.txt").string();
  sequence->depth_list = (fs::path(dir) / "depth.txt").string();
  std::vector<TumImageEntry> rgb, depth;
  if (!ReadTumImageList(sequence->rgb_list, dir, false, &rgb, error) ||
      !ReadTumImageList(sequence->depth_list, dir, true, &depth, error)) {
    return false;
  }
  std::vector<double> rgb_seconds, depth_seconds;
  for (const TumImageEntry& e : rgb) rgb_seconds.push_back(e.seconds);
  for (const TumImageEntry& e : depth) depth_seconds.push_back(e.seconds);
  const auto matches =
      AssociateStamps(rgb_seconds, depth_seconds, options.max_difference);
  if (matches.empty()) {
    *error = sequence->rgb_list + ": no colour image has a depth image in " +
             sequence->depth_list + " within " +
             std::to_string(options.max_difference) + " s (stamps " +
             std::to_string(rgb_seconds.front()) + ".." +
             std::to_string(rgb_seconds.back()) + " and " +
             std::to_string(depth_seconds.front()) + ".." +
             std::to_string(depth_seconds.back()) + ")";
    return false;
  }
  std::vector<bool> rgb_used(rgb.size(), false),
      depth_used(depth.size(), false);
  for (const auto& [i, j] : matches) {
    rgb_used[i] = depth_used[j] = true;
    sequence->frames.push_back({rgb[i], depth[j]});
  }
  for (size_t i = 0; i < rgb.size(); ++i)
    if (!rgb_used[i]) sequence->unmatched_rgb.push_back(rgb[i]);
  for (size_t j = 0; j < depth.size(); ++j)
    if (!depth_used[j]) sequence->unmatched_depth.push_back(depth[j]);
  // Every listed image of a frame must exist (checked before any work).
  for (const TumRgbdFrame& f : sequence->frames) {
    for (const auto& [e, list] :
         {std::make_pair(&f.rgb, &sequence->rgb_list),
          std::make_pair(&f.depth, &sequence->depth_list)}) {
      if (!fs::is_regular_file(e->path, ec)) {
        *error = *list + ":" + std::to_string(e->line) + ": " + e->path +
                 ": no such image file";
        return false;
      }
    }
  }
  const fs::path gt = fs::path(dir) / "groundtruth.txt";
  if (fs::is_regular_file(gt, ec)) sequence->ground_truth_path = gt.string();
  return true;
}

}  // namespace slam
