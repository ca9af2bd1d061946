#include "kustomization.h"

#include <stdexcept>

#include "deploy_files.h"

namespace loom::deploy_test {

Kustomized Kustomize(const std::filesystem::path& dir) {
  const std::vector<YAML::Node> documents = LoadYamlDocuments(dir / "kustomization.yaml");
  if (documents.size() != 1) throw std::runtime_error((dir / "kustomization.yaml").string() + ": not one document");
  const YAML::Node& kustomization = documents[0];
  Kustomized built;
  for (const std::string& resource : Strings(kustomization["resources"])) {
    const std::filesystem::path path = dir / resource;
    if (!std::filesystem::exists(path)) throw std::runtime_error(path.string() + " does not exist");
    if (std::filesystem::is_directory(path)) {
      Kustomized base = Kustomize(path);
      for (Manifest& manifest : base.manifests) {
        manifest.file = (std::filesystem::path(resource) / manifest.file).lexically_normal().string();
        built.manifests.push_back(std::move(manifest));
      }
      built.secrets.merge(base.secrets);
      continue;
    }
    for (const YAML::Node& node : LoadYamlDocuments(path)) built.manifests.push_back({resource, node});
  }
  for (const YAML::Node& patch : kustomization["patches"]) {
    const YAML::Node target = YAML::Load(patch["patch"].as<std::string>());
    if (target["$patch"].as<std::string>("") != "delete") continue;
    // Copied into a new vector, never assigned: assigning a YAML::Node writes through
    // into the document it refers to.
    std::vector<Manifest> kept;
    for (const Manifest& manifest : built.manifests) {
      if (manifest.Kind() != target["kind"].as<std::string>() ||
          manifest.Name() != target["metadata"]["name"].as<std::string>()) {
        kept.push_back(manifest);
      }
    }
    built.manifests.swap(kept);
  }
  for (const YAML::Node& generator : kustomization["secretGenerator"]) {
    GeneratedSecret& secret = built.secrets[generator["name"].as<std::string>()];
    for (const std::string& literal : Strings(generator["literals"])) {
      const size_t equals = literal.find('=');
      secret.literals[literal.substr(0, equals)] = literal.substr(equals + 1);
    }
    for (const std::string& file : Strings(generator["files"])) {
      const size_t equals = file.find('=');
      const std::string key =
          equals == std::string::npos ? std::filesystem::path(file).filename().string() : file.substr(0, equals);
      secret.files[key] = equals == std::string::npos ? file : file.substr(equals + 1);
    }
  }
  return built;
}

}  // namespace loom::deploy_test
