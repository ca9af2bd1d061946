// Every YAML file under deploy/ parses, and every Kubernetes manifest names its
// apiVersion, kind and metadata.name.

#include <gtest/gtest.h>

#include "deploy_files.h"

namespace loom::deploy_test {
namespace {

TEST(YamlFiles, EveryFileUnderDeployParses) {
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(DeployDir())) {
    const std::string extension = entry.path().extension();
    if (extension != ".yaml" && extension != ".yml") continue;
    ++files;
    std::vector<YAML::Node> documents;
    try {
      documents = LoadYamlDocuments(entry.path());
    } catch (const YAML::Exception& error) {
      ADD_FAILURE() << entry.path() << ": " << error.what();
      continue;
    }
    ASSERT_FALSE(documents.empty()) << entry.path();
    const bool kubernetes = entry.path().parent_path().filename() == "k8s" ||
                            entry.path().parent_path().parent_path().filename() == "k8s";
    for (const YAML::Node& document : documents) {
      EXPECT_TRUE(document.IsMap()) << entry.path();
      if (!kubernetes) continue;
      EXPECT_TRUE(document["apiVersion"] && document["kind"]) << entry.path();
      if (document["kind"].as<std::string>("") != "Kustomization") {
        EXPECT_TRUE(At(document, {"metadata", "name"})) << entry.path();
      }
    }
  }
  EXPECT_GE(files, 5);
}

}  // namespace
}  // namespace loom::deploy_test
