#pragma once
// What `kubectl apply -k DIR` would apply, built as far as Loom's kustomizations
// need, for the deploy tests: the documents of every resource (a file, or a
// directory with a kustomization of its own, built the same way), less those a
// `$patch: delete` patch names, and the secrets the secretGenerators make.

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace loom::deploy_test {

struct Manifest {
  std::string file;  // relative to the directory built
  YAML::Node node;
  std::string Kind() const { return node["kind"].as<std::string>(); }
  std::string Name() const { return node["metadata"]["name"].as<std::string>(); }
};

struct GeneratedSecret {
  std::map<std::string, std::string> literals;  // key -> value
  std::map<std::string, std::string> files;     // key -> file, relative to its kustomization
};

struct Kustomized {
  std::vector<Manifest> manifests;
  std::map<std::string, GeneratedSecret> secrets;  // by name
};

// Throws std::runtime_error for a resource that does not exist.
Kustomized Kustomize(const std::filesystem::path& dir);

}  // namespace loom::deploy_test
