#include "deploy_files.h"

namespace loom::deploy_test {

std::filesystem::path RepoDir() { return LOOM_SOURCE_DIR; }
std::filesystem::path DeployDir() { return RepoDir() / "deploy"; }

std::vector<YAML::Node> LoadYamlDocuments(const std::filesystem::path& path) {
  return YAML::LoadAllFromFile(path.string());
}

YAML::Node At(const YAML::Node& node, std::initializer_list<std::string> keys) {
  YAML::Node current = node;
  for (const std::string& key : keys) {
    if (!current.IsMap() || !current[key]) return YAML::Node(YAML::NodeType::Undefined);
    // reset, not operator=: assigning a Node writes through into the document.
    current.reset(current[key]);
  }
  return current;
}

std::vector<std::string> Strings(const YAML::Node& sequence) {
  std::vector<std::string> strings;
  if (!sequence) return strings;
  for (const YAML::Node& item : sequence) strings.push_back(item.as<std::string>());
  return strings;
}

const Dockerfile& LoomDockerfile() {
  static const Dockerfile dockerfile = Dockerfile::Read(DeployDir() / "docker" / "Dockerfile");
  return dockerfile;
}

const std::map<std::string, DockerImage>& LoomImages() {
  static const std::map<std::string, DockerImage> images = LoomDockerfile().Images();
  return images;
}

ImageReference ParseImageReference(const std::string& reference) {
  std::string rest = reference;
  if (const size_t digest = rest.find('@'); digest != std::string::npos) rest = rest.substr(0, digest);
  const size_t slash = rest.rfind('/');
  std::string last = slash == std::string::npos ? rest : rest.substr(slash + 1);
  const size_t colon = last.find(':');
  if (colon == std::string::npos) return {last, ""};
  return {last.substr(0, colon), last.substr(colon + 1)};
}

}  // namespace loom::deploy_test
