// Writing a config as YAML text, for --dump_config: numbers that read back
// exactly, quoted strings, and "key: value" lines with aligned comments.
#ifndef SLAM_APPS_YAML_WRITER_H_
#define SLAM_APPS_YAML_WRITER_H_

#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace slam {

// Shortest text that reads back as exactly `value`, with a decimal point so
// that it reads as a float.
std::string FormatDouble(double value);

// A YAML double-quoted string.
std::string Quoted(const std::string& text);

// Lines "key: value" with aligned trailing comments.
class YamlWriter {
 public:
  void Section(int indent, const std::string& name,
               const std::string& comment = "") {
    Line(indent, name + ":", comment);
  }
  template <typename T>
  void Value(int indent, const std::string& key, const T& value,
             const std::string& comment = "") {
    std::ostringstream text;
    text << key << ": " << value;
    Line(indent, text.str(), comment);
  }
  void Value(int indent, const std::string& key, double value,
             const std::string& comment = "") {
    Line(indent, key + ": " + FormatDouble(value), comment);
  }
  void Value(int indent, const std::string& key,
             const std::vector<double>& values,
             const std::string& comment = "") {
    std::string text;
    for (double v : values)
      text += (text.empty() ? "" : ", ") + FormatDouble(v);
    Line(indent, key + ": [" + text + "]", comment);
  }
  void Value(int indent, const std::string& key, bool value,
             const std::string& comment = "") {
    Line(indent, key + ": " + (value ? "true" : "false"), comment);
  }
  void Value(int indent, const std::string& key, const Eigen::Vector3d& value,
             const std::string& comment = "") {
    Line(indent,
         key + ": [" + FormatDouble(value.x()) + ", " +
             FormatDouble(value.y()) + ", " + FormatDouble(value.z()) + "]",
         comment);
  }
  std::string str() const { return out_.str(); }

 private:
  void Line(int indent, const std::string& text, const std::string& comment);

  std::ostringstream out_;
};

}  // namespace slam

#endif  // SLAM_APPS_YAML_WRITER_H_
