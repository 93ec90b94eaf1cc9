#include "apps/json.h"

#include <cmath>
#include <cstdio>

namespace slam {

std::string JsonQuote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", value);
  return buf;
}

JsonObject& JsonObject::Add(const std::string& key, double value) {
  return AddRaw(key, JsonNumber(value));
}
JsonObject& JsonObject::Add(const std::string& key, int value) {
  return AddRaw(key, std::to_string(value));
}
JsonObject& JsonObject::Add(const std::string& key, int64_t value) {
  return AddRaw(key, std::to_string(value));
}
JsonObject& JsonObject::Add(const std::string& key, size_t value) {
  return AddRaw(key, std::to_string(value));
}
JsonObject& JsonObject::Add(const std::string& key, bool value) {
  return AddRaw(key, value ? "true" : "false");
}
JsonObject& JsonObject::Add(const std::string& key, const char* value) {
  return AddRaw(key, JsonQuote(value));
}
JsonObject& JsonObject::Add(const std::string& key, const std::string& value) {
  return AddRaw(key, JsonQuote(value));
}
JsonObject& JsonObject::Add(const std::string& key, const JsonObject& value) {
  entries_.emplace_back(key, "\x01");  // Marker: nested, rendered on output.
  nested_.push_back(value);
  return *this;
}
JsonObject& JsonObject::Add(const std::string& key,
                            const std::vector<double>& values) {
  std::string json = "[";
  for (size_t i = 0; i < values.size(); ++i) {
    json += (i ? ", " : "") + JsonNumber(values[i]);
  }
  return AddRaw(key, json + "]");
}
JsonObject& JsonObject::AddRaw(const std::string& key,
                               const std::string& json) {
  entries_.emplace_back(key, json);
  return *this;
}

JsonObject& JsonObject::AddObjectEntries(const JsonObject& other) {
  size_t nested_index = 0;
  for (const auto& [key, json] : other.entries_) {
    if (json == "\x01") {
      Add(key, other.nested_[nested_index++]);
    } else {
      AddRaw(key, json);
    }
  }
  return *this;
}

std::string JsonObject::ToString(int indent) const {
  const std::string pad(indent + 2, ' ');
  std::string out = "{\n";
  size_t nested_index = 0;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const auto& [key, json] = entries_[i];
    out += pad + JsonQuote(key) + ": ";
    out += json == "\x01" ? nested_[nested_index++].ToString(indent + 2) : json;
    out += i + 1 < entries_.size() ? ",\n" : "\n";
  }
  return out + std::string(indent, ' ') + "}";
}

}  // namespace slam
