#include "apps/yaml_writer.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace slam {

// Shortest text that reads back as exactly `value`, with a decimal point so
// that it reads as a float.
std::string FormatDouble(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

// A YAML double-quoted string.
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out.push_back('\\');
    out.push_back(c);
  }
  return out + "\"";
}

void YamlWriter::Line(int indent, const std::string& text,
                      const std::string& comment) {
  std::string line = std::string(indent, ' ') + text;
  if (!comment.empty()) {
    constexpr size_t kCommentColumn = 34;
    line.resize(std::max(line.size() + 1, kCommentColumn), ' ');
    line += "# " + comment;
  }
  out_ << line << "\n";
}

}  // namespace slam
