// deploy/compose.yaml against the code: images, flags, ports, health checks and
// secrets (tests/deploy/container_checks.h), the data volume, the GPU reservation;
// and deploy/compose.postgresql.yaml on top of it: several servers on the PostgreSQL
// it runs.

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "binary_options.h"
#include "container_checks.h"
#include "deploy_files.h"

namespace loom::deploy_test {
namespace {

class ComposeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto documents = LoadYamlDocuments(DeployDir() / "compose.yaml");
    ASSERT_EQ(documents.size(), 1u);
    compose_ = documents[0];
    ASSERT_TRUE(compose_["services"].IsMap());
    for (const auto& service : compose_["services"]) {
      const std::string image = service.second["image"].as<std::string>("");
      if (ParseImageReference(image).name == "loom-server") server_names_.insert(service.first.as<std::string>());
    }
  }

  ContainerSpec Container(const std::string& name) const {
    const YAML::Node service = compose_["services"][name];
    ContainerSpec container{"compose.yaml services." + name, service["image"].as<std::string>(""),
                            bool(service["command"]), Strings(service["command"]), {}, {}, server_names_};
    if (const YAML::Node test = At(service, {"healthcheck", "test"})) {
      container.liveness = Strings(test);
      if (!container.liveness.empty() && container.liveness[0] == "CMD") container.liveness.erase(container.liveness.begin());
    }
    return container;
  }

  YAML::Node compose_;
  std::set<std::string> server_names_;
};

TEST_F(ComposeTest, HasOneServerAGpuWorkerAndACpuWorker) {
  EXPECT_EQ(server_names_, std::set<std::string>{"loom-server"});
  EXPECT_TRUE(compose_["services"]["worker-gpu"]);
  EXPECT_TRUE(compose_["services"]["worker-cpu"]);
}

TEST_F(ComposeTest, EveryServiceMatchesTheCode) {
  for (const auto& service : compose_["services"]) {
    const std::string name = service.first.as<std::string>();
    for (const std::string& problem : ContainerProblems(Container(name))) ADD_FAILURE() << problem;
    const YAML::Node build = service.second["build"];
    ASSERT_TRUE(build) << name;
    EXPECT_EQ(build["dockerfile"].as<std::string>(), "deploy/docker/Dockerfile") << name;
    EXPECT_TRUE(std::filesystem::exists(DeployDir() / build["context"].as<std::string>() / "deploy/docker/Dockerfile"));
    const std::string stage = build["target"].as<std::string>();
    const auto image = LoomImages().find(ParseImageReference(service.second["image"].as<std::string>()).name);
    ASSERT_NE(image, LoomImages().end()) << name;
    EXPECT_EQ(stage, image->second.stage) << name << " builds a stage other than its image's";
  }
}

TEST_F(ComposeTest, PublishedPortsAreTheServersPortItsDashboardsAndItsMetrics) {
  const int port = DefaultServerPort();
  const std::vector<std::string> command = Strings(compose_["services"]["loom-server"]["command"]);
  const std::optional<std::string> http = OptionValue(command, "--http");
  const std::optional<std::string> metrics = OptionValue(command, "--metrics");
  ASSERT_TRUE(http && metrics);
  const std::set<int> served = {port, SplitAddress(*http).port, SplitAddress(*metrics).port};
  int published = 0;
  for (const auto& service : compose_["services"]) {
    for (const std::string& mapping : Strings(service.second["ports"])) {
      ++published;
      EXPECT_TRUE(served.contains(SplitAddress(mapping).port)) << service.first.as<std::string>() << ": " << mapping;
    }
  }
  EXPECT_EQ(published, 3);
}

TEST_F(ComposeTest, SecretsUsedAreDefinedAndMounted) {
  const YAML::Node secrets = compose_["secrets"];
  ASSERT_TRUE(secrets.IsMap());
  for (const auto& secret : secrets) {
    // Token files live in deploy/tokens/, which git ignores (deploy/make_tokens.sh makes them).
    EXPECT_EQ(secret.second["file"].as<std::string>().rfind("tokens/", 0), 0u) << secret.first.as<std::string>();
  }
  std::ifstream gitignore(DeployDir() / ".gitignore");
  std::string ignored((std::istreambuf_iterator<char>(gitignore)), std::istreambuf_iterator<char>());
  EXPECT_NE(ignored.find("tokens/"), std::string::npos);

  for (const auto& service : compose_["services"]) {
    const std::string name = service.first.as<std::string>();
    const std::vector<std::string> mounted = Strings(service.second["secrets"]);
    for (const std::string& secret : mounted) EXPECT_TRUE(secrets[secret]) << name << " uses undefined secret " << secret;
    for (const std::string& file : SecretFilesNamed(EffectiveArgs(Container(name)))) {
      EXPECT_NE(std::find(mounted.begin(), mounted.end(), file), mounted.end())
          << name << " reads /run/secrets/" << file << " but does not mount that secret";
    }
  }
}

TEST_F(ComposeTest, ServerDataIsANamedVolume) {
  const YAML::Node server = compose_["services"]["loom-server"];
  const std::string data = OptionValue(Strings(server["command"]), "--data").value_or("");
  bool mounted = false;
  for (const std::string& volume : Strings(server["volumes"])) {
    const size_t colon = volume.find(':');
    if (volume.substr(colon + 1) != data) continue;
    mounted = true;
    EXPECT_TRUE(compose_["volumes"][volume.substr(0, colon)]) << volume << " is not a named volume";
  }
  EXPECT_TRUE(mounted) << "nothing mounted at --data " << data;
}

TEST_F(ComposeTest, GpuWorkerReservesAGpuWithGraphicsAndCpuWorkerUsesLlvmpipe) {
  const YAML::Node gpu = compose_["services"]["worker-gpu"];
  const YAML::Node device = At(gpu, {"deploy", "resources", "reservations", "devices"})[0];
  ASSERT_TRUE(device);
  EXPECT_EQ(device["driver"].as<std::string>(), "nvidia");
  EXPECT_EQ(device["count"].as<int>(), 1);
  const std::vector<std::string> capabilities = Strings(device["capabilities"]);
  EXPECT_NE(std::find(capabilities.begin(), capabilities.end(), "gpu"), capabilities.end());
  EXPECT_NE(std::find(capabilities.begin(), capabilities.end(), "graphics"), capabilities.end());
  EXPECT_NE(At(gpu, {"environment", "NVIDIA_DRIVER_CAPABILITIES"}).as<std::string>("").find("graphics"),
            std::string::npos);
  EXPECT_FALSE(HasFlag(Strings(gpu["command"]), "--software"));

  const YAML::Node cpu = compose_["services"]["worker-cpu"];
  EXPECT_TRUE(HasFlag(Strings(cpu["command"]), "--software"));
  EXPECT_FALSE(At(cpu, {"deploy", "resources", "reservations", "devices"}));
  EXPECT_GE(At(cpu, {"deploy", "replicas"}).as<int>(0), 1);
}

// compose.postgresql.yaml over compose.yaml: the servers' command is compose.yaml's
// with --store added, that store is the postgres service's database, and each port
// the servers serve is published as a range of one host port per server.
class ComposePostgresTest : public ComposeTest {
 protected:
  void SetUp() override {
    ComposeTest::SetUp();
    const auto documents = LoadYamlDocuments(DeployDir() / "compose.postgresql.yaml");
    ASSERT_EQ(documents.size(), 1u);
    over_ = documents[0];
  }
  YAML::Node over_;
};

TEST_F(ComposePostgresTest, TheServersRunComposeYamlsCommandWithTheStoreAdded) {
  const YAML::Node server = over_["services"]["loom-server"];
  std::vector<std::string> command = Strings(server["command"]);
  ContainerSpec spec = Container("loom-server");
  spec.where = "compose.postgresql.yaml services.loom-server";
  spec.args = command;
  for (const std::string& problem : ContainerProblems(spec)) ADD_FAILURE() << problem;
  const auto store = std::find(command.begin(), command.end(), "--store");
  ASSERT_NE(store, command.end());
  command.erase(store, store + 2);
  EXPECT_EQ(command, Strings(compose_["services"]["loom-server"]["command"]));
  EXPECT_TRUE(At(server, {"environment", "PGPASSWORD"})) << "libpq's password";
}

TEST_F(ComposePostgresTest, TheStoreIsThePostgresService) {
  const std::string store = OptionValue(Strings(over_["services"]["loom-server"]["command"]), "--store").value_or("");
  const std::optional<PostgresUri> uri = ParsePostgresUri(store);
  ASSERT_TRUE(uri) << store << ": not postgresql://USER@HOST:PORT/DB without a password";
  const YAML::Node postgres = over_["services"][uri->server.host];
  ASSERT_TRUE(postgres) << store << " names no service";
  EXPECT_EQ(uri->server.port, 5432);
  EXPECT_EQ(At(postgres, {"environment", "POSTGRES_USER"}).as<std::string>(""), uri->user);
  EXPECT_EQ(At(postgres, {"environment", "POSTGRES_DB"}).as<std::string>(""), uri->database);
  const std::string password_file = At(postgres, {"environment", "POSTGRES_PASSWORD_FILE"}).as<std::string>("");
  ASSERT_TRUE(password_file.starts_with("/run/secrets/")) << password_file;
  const std::string secret = password_file.substr(std::string("/run/secrets/").size());
  EXPECT_EQ(Strings(postgres["secrets"]), std::vector<std::string>{secret});
  EXPECT_EQ(At(over_, {"secrets", secret, "file"}).as<std::string>("").rfind("tokens/", 0), 0u);
  EXPECT_TRUE(At(over_["services"]["loom-server"], {"depends_on", uri->server.host}));
}

TEST_F(ComposePostgresTest, EachServedPortIsARangeOfOneHostPortPerServer) {
  const YAML::Node server = over_["services"]["loom-server"];
  const int replicas = At(server, {"deploy", "replicas"}).as<int>(0);
  EXPECT_GE(replicas, 2);
  const std::vector<std::string> command = Strings(server["command"]);
  std::set<int> served = {DefaultServerPort(), SplitAddress(OptionValue(command, "--http").value_or("")).port,
                          SplitAddress(OptionValue(command, "--metrics").value_or("")).port};
  for (const std::string& mapping : Strings(server["ports"])) {
    const size_t last = mapping.rfind(':');
    const std::string host = mapping.substr(0, last);
    const std::string range = host.substr(host.rfind(':') == std::string::npos ? 0 : host.rfind(':') + 1);
    const size_t dash = range.find('-');
    ASSERT_NE(dash, std::string::npos) << mapping << ": one host port for " << replicas << " servers";
    EXPECT_EQ(std::stoi(range.substr(dash + 1)) - std::stoi(range.substr(0, dash)) + 1, replicas) << mapping;
    EXPECT_EQ(served.erase(std::stoi(mapping.substr(last + 1))), 1u) << mapping << " publishes no port served";
  }
  EXPECT_TRUE(served.empty()) << served.size() << " served ports not published";
}

}  // namespace
}  // namespace loom::deploy_test
