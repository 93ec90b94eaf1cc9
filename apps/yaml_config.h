// Helpers for config structs loaded from YAML. A config is a plain struct with
// defaults; its loader reads only the keys it knows and reports every
// unknown key as an error (a misspelt setting must never be ignored).
#ifndef SLAM_APPS_YAML_CONFIG_H_
#define SLAM_APPS_YAML_CONFIG_H_

#include <initializer_list>
#include <string>

#include <yaml-cpp/yaml.h>

namespace slam {

// Fails with "FILE: unknown key 'x' in SECTION (known: a, b, c)".
bool CheckKnownKeys(const YAML::Node& node,
                    std::initializer_list<const char*> known,
                    const std::string& where, std::string* error);

// Reads node[key] into *value when present; false with a message naming
// `where` and the key when it has the wrong type.
template <typename T>
bool ReadOptional(const YAML::Node& node, const char* key,
                  const std::string& where, T* value, std::string* error) {
  const YAML::Node child = node[key];
  if (!child) return true;
  try {
    *value = child.as<T>();
  } catch (const YAML::Exception& e) {
    *error = where + ": key '" + key + "' (line " +
             std::to_string(child.Mark().line + 1) +
             ") has a value of the wrong type";
    return false;
  }
  return true;
}

// One config file may hold the sections of several subcommands; each loader
// reads its own and accepts the others, but an unknown top-level key (a typo
// such as "optimise:") is an error naming the file and line.
bool CheckTopLevelSections(const YAML::Node& root, const std::string& where,
                           std::string* error);

// Loads a YAML file; false with "FILE:LINE: message" on a syntax error.
bool LoadYamlFile(const std::string& path, YAML::Node* root,
                  std::string* error);

}  // namespace slam

#endif  // SLAM_APPS_YAML_CONFIG_H_
