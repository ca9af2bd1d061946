// docs/operations.md "Limits" lists every limit (issue 22): each cap defined in
// core/spec/limits.h and the service's headers is named there, so a new cap cannot
// be added without its line in the docs.

#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "core/util/file_io.h"
#include "tests/deploy/deploy_files.h"

namespace loom {
namespace {

std::vector<std::string> CapNames(const std::string& header) {
  static const std::regex kCap(R"(inline constexpr [\w:]+ (k(?:Max|Min)\w+) =)");
  const std::string text = ReadFile(deploy_test::RepoDir() / header);
  std::vector<std::string> names;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), kCap); it != std::sregex_iterator(); ++it) {
    names.push_back((*it)[1].str());
  }
  return names;
}

TEST(OperationsDoc, NamesEveryLimit) {
  const std::string doc = ReadFile(deploy_test::RepoDir() / "docs" / "operations.md");
  size_t checked = 0;
  for (const char* header : {"core/spec/limits.h", "server/job_service.h", "server/worker_service.h",
                             "server/artifact_upload.h", "rpc/channel.h"}) {
    const std::vector<std::string> names = CapNames(header);
    EXPECT_FALSE(names.empty()) << header;
    for (const std::string& name : names) {
      EXPECT_NE(doc.find("`" + name + "`"), std::string::npos) << name << " (" << header << ") is not in the docs";
      ++checked;
    }
  }
  EXPECT_GE(checked, 50u);
}

}  // namespace
}  // namespace loom
