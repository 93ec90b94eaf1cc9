#include "datasets/relations_io.h"

#include <Eigen/Geometry>
#include <cmath>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "datasets/trajectory_io.h"

namespace slam {

bool ReadRelations(const std::string& path,
                   std::vector<PoseRelation>* relations, std::string* error,
                   std::vector<int>* lines) {
  relations->clear();
  if (lines != nullptr) lines->clear();
  std::string data;
  if (!text::ReadWholeFile(path, &data, error)) return false;
  text::LineTokenizer tokenizer(data);
  std::vector<PoseRelation> result;
  std::vector<int> result_lines;
  while (tokenizer.Next()) {
    const auto& tokens = tokenizer.tokens();
    const std::string where =
        path + ":" + std::to_string(tokenizer.line()) + ": ";
    if (tokens.size() != 8) {
      *error = where +
               "expected 8 fields 't1 t2 x y z roll pitch yaw', found " +
               std::to_string(tokens.size());
      return false;
    }
    PoseRelation r;
    for (int k = 0; k < 2; ++k) {
      if (!ParseStampSeconds(std::string(tokens[k]), k == 0 ? &r.t1 : &r.t2)) {
        *error = where + "bad timestamp '" + text::Printable(tokens[k]) +
                 "' in field " + std::to_string(k + 1);
        return false;
      }
    }
    double v[6];
    for (int k = 0; k < 6; ++k) {
      if (!text::ParseDouble(tokens[2 + k], &v[k])) {
        *error = where + "bad or non-finite number '" +
                 text::Printable(tokens[2 + k]) + "' in field " +
                 std::to_string(k + 3);
        return false;
      }
    }
    const Eigen::Quaterniond q =
        Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
        Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX());
    r.delta = Pose3(Eigen::Vector3d(v[0], v[1], v[2]), q);
    result.push_back(r);
    result_lines.push_back(static_cast<int>(tokenizer.line()));
  }
  if (result.empty()) {
    *error =
        path + ": no relations (expected lines 't1 t2 x y z roll pitch yaw')";
    return false;
  }
  relations->swap(result);
  if (lines != nullptr) lines->swap(result_lines);
  return true;
}

bool WriteRelations(const std::string& path,
                    const std::vector<PoseRelation>& relations,
                    std::string* error) {
  std::string out;
  for (const PoseRelation& r : relations) {
    const Eigen::Matrix3d m = r.delta.q.toRotationMatrix();
    const double yaw = std::atan2(m(1, 0), m(0, 0));
    const double pitch = std::atan2(-m(2, 0), std::hypot(m(2, 1), m(2, 2)));
    const double roll = std::atan2(m(2, 1), m(2, 2));
    out += FormatStampSeconds(r.t1) + " " + FormatStampSeconds(r.t2);
    for (double v :
         {r.delta.t.x(), r.delta.t.y(), r.delta.t.z(), roll, pitch, yaw}) {
      out.push_back(' ');
      text::AppendDouble(v, &out);
    }
    out.push_back('\n');
  }
  return WriteFileAtomically(path, out, error);
}

}  // namespace slam
