// A minimal ordered JSON object writer for reports (keys keep their insertion
// order; doubles are written with 17 significant digits so that figures
// round-trip; non-finite numbers become null).
#ifndef SLAM_APPS_JSON_H_
#define SLAM_APPS_JSON_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace slam {

class JsonObject {
 public:
  JsonObject& Add(const std::string& key, double value);
  JsonObject& Add(const std::string& key, int value);
  JsonObject& Add(const std::string& key, int64_t value);
  JsonObject& Add(const std::string& key, size_t value);
  JsonObject& Add(const std::string& key, bool value);
  JsonObject& Add(const std::string& key, const char* value);
  JsonObject& Add(const std::string& key, const std::string& value);
  JsonObject& Add(const std::string& key, const JsonObject& value);
  JsonObject& Add(const std::string& key, const std::vector<double>& values);
  JsonObject& AddRaw(const std::string& key, const std::string& json);
  // Appends every entry of `other` to this object.
  JsonObject& AddObjectEntries(const JsonObject& other);

  std::string ToString(int indent = 0) const;
  bool empty() const { return entries_.empty(); }

 private:
  std::vector<std::pair<std::string, std::string>> entries_;  // key -> JSON.
  std::vector<JsonObject> nested_;  // Values of the nested entries, in order.
};

std::string JsonQuote(const std::string& text);
std::string JsonNumber(double value);

}  // namespace slam

#endif  // SLAM_APPS_JSON_H_
