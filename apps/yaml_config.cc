#include "apps/yaml_config.h"

#include <filesystem>

namespace slam {

bool CheckKnownKeys(const YAML::Node& node,
                    std::initializer_list<const char*> known,
                    const std::string& where, std::string* error) {
  if (!node) return true;
  if (!node.IsMap()) {
    *error = where + ": expected a mapping of settings";
    return false;
  }
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found) {
      std::string list;
      for (const char* k : known)
        list += (list.empty() ? "" : ", ") + std::string(k);
      *error = where + ":" + std::to_string(entry.first.Mark().line + 1) +
               ": unknown key '" + key + "' (known: " + list + ")";
      return false;
    }
  }
  return true;
}

bool CheckTopLevelSections(const YAML::Node& root, const std::string& where,
                           std::string* error) {
  return CheckKnownKeys(
      root, {"optimize", "simulate", "eval", "run", "inertial", "loops"}, where, error);
}

bool LoadYamlFile(const std::string& path, YAML::Node* root,
                  std::string* error) {
  if (!std::filesystem::exists(path)) {
    *error = path + ": no such file";
    return false;
  }
  try {
    *root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    *error = path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg;
    return false;
  }
  return true;
}

}  // namespace slam
