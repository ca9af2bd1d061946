#pragma once
// The deployment files under deploy/, read for the deploy tests.

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "dockerfile.h"

namespace loom::deploy_test {

std::filesystem::path RepoDir();
std::filesystem::path DeployDir();

// Every document of a YAML file (throws YAML::Exception on a syntax error).
std::vector<YAML::Node> LoadYamlDocuments(const std::filesystem::path& path);
// node[keys[0]][keys[1]]...; an undefined node where a key is missing on the way
// (yaml-cpp throws when indexing into a missing node).
YAML::Node At(const YAML::Node& node, std::initializer_list<std::string> keys);
// A YAML sequence of scalars as strings (an absent node: none).
std::vector<std::string> Strings(const YAML::Node& sequence);

// deploy/docker/Dockerfile and the images it builds, by title (read once).
const Dockerfile& LoomDockerfile();
const std::map<std::string, DockerImage>& LoomImages();

// "registry.example/loom/loom-server:0.1.0" -> {"loom-server", "0.1.0"}.
struct ImageReference {
  std::string name;  // the last path component
  std::string tag;   // empty when there is none
};
ImageReference ParseImageReference(const std::string& reference);

}  // namespace loom::deploy_test
