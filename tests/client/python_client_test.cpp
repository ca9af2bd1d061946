// examples/python/loom_client.py, a client written from the protos alone, against
// a server in this process: what a user of another language starts from must keep
// working (issue 22). Needs Debian's python3-grpcio and python3-protobuf
// (scripts/setup.sh installs them) and protoc with grpc_python_plugin.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include <cstdlib>

#include "core/util/file_io.h"
#include "tests/server/service_fixture.h"

namespace loom::server {
namespace {

TEST_F(ServiceTest, ThePythonExampleClientRendersAFrameThroughTheService) {
  StartServer();
  const auto output = data_dir_ / "python-client.json";
  const std::string command = std::string("/usr/bin/python3 ") + LOOM_SOURCE_DIR +
                              "/examples/python/loom_client.py --server " + server_->address() + " --out " +
                              (data_dir_ / "out").string() + " > " + output.string() + " 2>&1";
  const int status = std::system(command.c_str());
  const std::string text = ReadFile(output);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  const nlohmann::json report = nlohmann::json::parse(text);
  EXPECT_EQ(report["state"], "JOB_STATE_SUCCEEDED") << text;
  EXPECT_EQ(report["uploaded_meshes"], 1) << text;
  EXPECT_EQ(report["fabric_precomputes"].size(), 1u) << text;
  EXPECT_TRUE(report["frame"]["png"].get<bool>()) << text;
  EXPECT_GT(report["frame"]["bytes"].get<int>(), 100) << text;
  EXPECT_EQ(report["empty_job_id"]["code"], "INVALID_ARGUMENT") << text;
}

}  // namespace
}  // namespace loom::server
