// deploy/k8s against the code, as kubectl apply -k builds it (kustomization.h), for
// the base (one server on SQLite) and postgresql/ (several servers on PostgreSQL):
// every container's image, flags, ports, probes and secrets match the code
// (container_checks.h); the GPU worker asks for one GPU with the graphics capability;
// the server's data is a PersistentVolumeClaim mounted at --data, shared by every
// server on PostgreSQL, whose --store reaches the PostgreSQL the overlay runs.

#include <gtest/gtest.h>

#include <fstream>

#include "binary_options.h"
#include "container_checks.h"
#include "deploy_files.h"
#include "kustomization.h"

namespace loom::deploy_test {
namespace {

struct Workload {
  std::string file;
  YAML::Node manifest;
  std::string Where() const { return file + " " + manifest["kind"].as<std::string>() + "/" + Name(); }
  std::string Name() const { return manifest["metadata"]["name"].as<std::string>(); }
  YAML::Node Pod() const { return manifest["spec"]["template"]["spec"]; }
  YAML::Node Container() const { return Pod()["containers"][0]; }
  std::vector<std::string> Args() const { return Strings(Container()["args"]); }
  bool IsLoom() const { return LoomImages().count(ParseImageReference(Container()["image"].as<std::string>()).name); }
  // The container's environment variable `name`: its value, or its secret as "secret/key".
  std::string Env(const std::string& name) const {
    for (const YAML::Node& variable : Container()["env"]) {
      if (variable["name"].as<std::string>() != name) continue;
      if (const YAML::Node ref = At(variable, {"valueFrom", "secretKeyRef"})) {
        return ref["name"].as<std::string>() + "/" + ref["key"].as<std::string>();
      }
      return variable["value"].as<std::string>("");
    }
    return "";
  }
};

// One kustomization's build (kustomization.h): its workloads, services and secrets.
class Kubernetes : public ::testing::Test {
 protected:
  void Load(const std::string& dir) {
    built_ = Kustomize(DeployDir() / dir);
    for (const Manifest& manifest : built_.manifests) {
      const std::string kind = manifest.Kind();
      if (kind == "Service") services_.push_back(manifest.node);
      if (kind == "Deployment" || kind == "StatefulSet") workloads_.push_back({manifest.file, manifest.node});
    }
    for (const auto& [name, secret] : built_.secrets) {
      std::set<std::string>& keys = secrets_[name];
      for (const auto& [key, value] : secret.literals) keys.insert(key);
      for (const auto& [key, file] : secret.files) {
        keys.insert(key);
        // Token files stay out of git (deploy/.gitignore: tokens/).
        EXPECT_EQ(file.rfind("tokens/", 0), 0u) << file;
      }
    }
    for (const YAML::Node& service : services_) service_names_.insert(service["metadata"]["name"].as<std::string>());
  }

  const Workload& Find(const std::string& name) const {
    for (const Workload& workload : workloads_) {
      if (workload.Name() == name) return workload;
    }
    throw std::runtime_error("no workload " + name);
  }
  const YAML::Node* FindManifest(const std::string& kind, const std::string& name) const {
    for (const Manifest& manifest : built_.manifests) {
      if (manifest.Kind() == kind && manifest.Name() == name) return &manifest.node;
    }
    return nullptr;
  }

  // Keys of `secret_name` the volume exposes: its items, or all the secret's keys.
  std::set<std::string> VolumeKeys(const YAML::Node& volume) const {
    const auto secret = secrets_.find(volume["secret"]["secretName"].as<std::string>());
    if (secret == secrets_.end()) return {};
    if (!volume["secret"]["items"]) return secret->second;
    std::set<std::string> keys;
    for (const YAML::Node& item : volume["secret"]["items"]) keys.insert(item["path"].as<std::string>());
    return keys;
  }

  // Whether `service` selects `workload`'s pods.
  static bool Selects(const YAML::Node& service, const Workload& workload) {
    for (const auto& label : service["spec"]["selector"]) {
      if (workload.manifest["spec"]["template"]["metadata"]["labels"][label.first.as<std::string>()].as<std::string>(
              "") != label.second.as<std::string>()) {
        return false;
      }
    }
    return true;
  }

  Kustomized built_;
  std::vector<YAML::Node> services_;
  std::vector<Workload> workloads_;
  std::map<std::string, std::set<std::string>> secrets_;  // generated secret -> keys
  std::set<std::string> service_names_;
};

// The checks every kustomization passes: the base (one server on SQLite) and
// postgresql/ (several servers on PostgreSQL).
class KubernetesTest : public Kubernetes, public ::testing::WithParamInterface<std::string> {
 protected:
  void SetUp() override { Load(GetParam()); }
};

INSTANTIATE_TEST_SUITE_P(Kustomizations, KubernetesTest, ::testing::Values("k8s", "k8s/postgresql"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param == "k8s" ? std::string("base") : std::string("postgresql");
                         });

class KubernetesBaseTest : public Kubernetes {
 protected:
  void SetUp() override { Load("k8s"); }
};

class KubernetesPostgresTest : public Kubernetes {
 protected:
  void SetUp() override { Load("k8s/postgresql"); }
};

TEST_F(KubernetesBaseTest, HasTheServerAGpuWorkerAndACpuWorker) {
  EXPECT_EQ(Find("loom-server").manifest["kind"].as<std::string>(), "StatefulSet");
  EXPECT_EQ(Find("loom-worker-gpu").manifest["kind"].as<std::string>(), "Deployment");
  EXPECT_EQ(Find("loom-worker-cpu").manifest["kind"].as<std::string>(), "Deployment");
  EXPECT_EQ(service_names_, std::set<std::string>{"loom-server"});
}

TEST_P(KubernetesTest, EveryContainerMatchesTheCode) {
  for (const Workload& workload : workloads_) {
    if (!workload.IsLoom()) continue;  // PostgreSQL's: KubernetesPostgresTest
    ASSERT_EQ(workload.Pod()["containers"].size(), 1u) << workload.Where();
    const YAML::Node container = workload.Container();
    // `command` would replace the image's ENTRYPOINT (the binary the args are for).
    EXPECT_FALSE(container["command"]) << workload.Where();
    ContainerSpec spec{workload.Where(), container["image"].as<std::string>(), bool(container["args"]),
                       workload.Args(), {}, {}, service_names_};
    for (const char* probe : {"readinessProbe", "livenessProbe"}) {
      const YAML::Node command = At(container, {probe, "exec", "command"});
      EXPECT_TRUE(command) << workload.Where() << ": no exec " << probe;
      (std::string(probe) == "livenessProbe" ? spec.liveness : spec.readiness) = Strings(command);
    }
    for (const std::string& problem : ContainerProblems(spec)) ADD_FAILURE() << problem;

    const YAML::Node requests = At(container, {"resources", "requests"});
    EXPECT_TRUE(requests["cpu"] && requests["memory"]) << workload.Where() << ": no cpu and memory requests";

    // The image's numeric USER, required to be non-root.
    const YAML::Node security = workload.Pod()["securityContext"];
    EXPECT_TRUE(security["runAsNonRoot"].as<bool>(false)) << workload.Where();
    const auto image = LoomImages().find(ParseImageReference(spec.image).name);
    ASSERT_NE(image, LoomImages().end());
    EXPECT_EQ(security["runAsUser"].as<std::string>(""), image->second.user.substr(0, image->second.user.find(':')))
        << workload.Where();
  }
}

TEST_P(KubernetesTest, ServicePortReachesTheServersPort) {
  const int port = DefaultServerPort();
  const YAML::Node* service = FindManifest("Service", "loom-server");
  ASSERT_TRUE(service);
  const YAML::Node service_port = (*service)["spec"]["ports"][0];
  EXPECT_EQ(service_port["port"].as<int>(), port);
  const Workload& server = Find("loom-server");
  EXPECT_TRUE(Selects(*service, server));
  const YAML::Node container_port = server.Container()["ports"][0];
  EXPECT_EQ(container_port["containerPort"].as<int>(), port);
  const std::string target = service_port["targetPort"].as<std::string>();
  EXPECT_TRUE(target == container_port["name"].as<std::string>("") || target == std::to_string(port)) << target;
  if (server.manifest["kind"].as<std::string>() == "StatefulSet") {
    EXPECT_EQ(server.manifest["spec"]["serviceName"].as<std::string>(), "loom-server");
  }
}

TEST_P(KubernetesTest, SecretsReadAreGeneratedAndMounted) {
  ASSERT_FALSE(secrets_.empty());
  for (const Workload& workload : workloads_) {
    for (const YAML::Node& variable : workload.Container()["env"]) {
      const YAML::Node ref = At(variable, {"valueFrom", "secretKeyRef"});
      if (!ref) continue;
      EXPECT_TRUE(secrets_[ref["name"].as<std::string>()].count(ref["key"].as<std::string>()))
          << workload.Where() << " reads " << ref["name"] << "/" << ref["key"] << ", which is not generated";
    }
    std::map<std::string, YAML::Node> volumes;
    for (const YAML::Node& volume : workload.Pod()["volumes"]) {
      volumes.emplace(volume["name"].as<std::string>(), volume);
      if (!volume["secret"]) continue;
      const std::string name = volume["secret"]["secretName"].as<std::string>();
      ASSERT_TRUE(secrets_.count(name)) << workload.Where() << " mounts secret " << name << ", which is not generated";
      for (const YAML::Node& item : volume["secret"]["items"]) {
        EXPECT_TRUE(secrets_[name].count(item["key"].as<std::string>())) << workload.Where();
      }
    }
    for (const YAML::Node& claim : workload.manifest["spec"]["volumeClaimTemplates"]) {
      volumes.emplace(claim["metadata"]["name"].as<std::string>(), claim);
    }
    std::set<std::string> readable;  // files under /run/secrets
    for (const YAML::Node& mount : workload.Container()["volumeMounts"]) {
      const auto found = volumes.find(mount["name"].as<std::string>());
      ASSERT_NE(found, volumes.end()) << workload.Where() << ": mount of undefined volume " << mount["name"];
      const YAML::Node& volume = found->second;
      if (mount["mountPath"].as<std::string>() == "/run/secrets" && volume["secret"]) {
        for (const std::string& key : VolumeKeys(volume)) readable.insert(key);
        // The service-account token would land under /run/secrets too (/var/run is /run).
        EXPECT_FALSE(workload.Pod()["automountServiceAccountToken"].as<bool>(true)) << workload.Where();
      }
    }
    for (const std::string& file : SecretFilesNamed(workload.Args())) {
      EXPECT_TRUE(readable.count(file)) << workload.Where() << " reads /run/secrets/" << file << ", which it does not mount";
    }
  }
}

TEST_F(KubernetesBaseTest, ServerDataIsAPersistentVolumeClaimAtDataDir) {
  const Workload& server = Find("loom-server");
  EXPECT_EQ(server.manifest["spec"]["replicas"].as<int>(), 1) << "one server per data directory";
  const std::string data = OptionValue(server.Args(), "--data").value_or("");
  const YAML::Node claim = server.manifest["spec"]["volumeClaimTemplates"][0];
  ASSERT_TRUE(claim);
  bool mounted = false;
  for (const YAML::Node& mount : server.Container()["volumeMounts"]) {
    if (mount["name"].as<std::string>() == claim["metadata"]["name"].as<std::string>()) {
      mounted = true;
      EXPECT_EQ(mount["mountPath"].as<std::string>(), data);
    }
  }
  EXPECT_TRUE(mounted);
  EXPECT_EQ(server.Pod()["securityContext"]["fsGroup"].as<std::string>(""),
            server.Pod()["securityContext"]["runAsGroup"].as<std::string>());
}

TEST_P(KubernetesTest, GpuWorkerAsksForOneGpuWithGraphicsAndCpuWorkerForNone) {
  const Workload& gpu = Find("loom-worker-gpu");
  EXPECT_EQ(At(gpu.Container(), {"resources", "limits", "nvidia.com/gpu"}).as<int>(0), 1);
  std::map<std::string, std::string> env;
  for (const YAML::Node& variable : gpu.Container()["env"]) env[variable["name"].as<std::string>()] = variable["value"].as<std::string>();
  EXPECT_NE(env["NVIDIA_DRIVER_CAPABILITIES"].find("graphics"), std::string::npos);
  EXPECT_FALSE(HasFlag(gpu.Args(), "--software"));

  const Workload& cpu = Find("loom-worker-cpu");
  EXPECT_FALSE(At(cpu.Container(), {"resources", "limits", "nvidia.com/gpu"}));
  EXPECT_FALSE(At(cpu.Container(), {"resources", "requests", "nvidia.com/gpu"}));
  EXPECT_TRUE(HasFlag(cpu.Args(), "--software"));
  env.clear();
  for (const YAML::Node& variable : cpu.Container()["env"]) env[variable["name"].as<std::string>()] = variable["value"].as<std::string>();
  EXPECT_EQ(env["NVIDIA_VISIBLE_DEVICES"], "void");
}

TEST_F(KubernetesPostgresTest, SeveralServersShareOneVolumeBehindTheService) {
  EXPECT_FALSE(FindManifest("StatefulSet", "loom-server")) << "the base's one-server StatefulSet is replaced";
  const Workload& server = Find("loom-server");
  EXPECT_EQ(server.manifest["kind"].as<std::string>(), "Deployment");
  EXPECT_GE(server.manifest["spec"]["replicas"].as<int>(0), 2);
  const YAML::Node* service = FindManifest("Service", "loom-server");
  ASSERT_TRUE(service);
  EXPECT_TRUE(Selects(*service, server));
  // --data is one ReadWriteMany claim every server mounts.
  const std::string data = OptionValue(server.Args(), "--data").value_or("");
  std::string claim_name;
  for (const YAML::Node& mount : server.Container()["volumeMounts"]) {
    if (mount["mountPath"].as<std::string>() != data) continue;
    for (const YAML::Node& volume : server.Pod()["volumes"]) {
      if (volume["name"].as<std::string>() == mount["name"].as<std::string>()) {
        claim_name = At(volume, {"persistentVolumeClaim", "claimName"}).as<std::string>("");
      }
    }
  }
  const YAML::Node* claim = FindManifest("PersistentVolumeClaim", claim_name);
  ASSERT_TRUE(claim) << "--data " << data << " is not a claim the kustomization makes";
  EXPECT_EQ(Strings((*claim)["spec"]["accessModes"]), std::vector<std::string>{"ReadWriteMany"});
  EXPECT_EQ(server.Pod()["securityContext"]["fsGroup"].as<std::string>(""),
            server.Pod()["securityContext"]["runAsGroup"].as<std::string>());
}

// --store is $(VAR) from the loom-store secret's uri, the password reaches libpq as
// PGPASSWORD and PostgreSQL as POSTGRES_PASSWORD from one key, and the uri names the
// in-cluster PostgreSQL's Service, port, user and database.
TEST_F(KubernetesPostgresTest, TheStoreIsThePostgresTheOverlayRuns) {
  const Workload& server = Find("loom-server");
  const std::string store = OptionValue(server.Args(), "--store").value_or("");
  ASSERT_TRUE(store.starts_with("$(") && store.ends_with(")")) << store;
  const std::string uri_ref = server.Env(store.substr(2, store.size() - 3));
  const size_t slash = uri_ref.find('/');
  ASSERT_NE(slash, std::string::npos) << "--store's variable is not from a secret: " << uri_ref;
  const std::string secret = uri_ref.substr(0, slash);
  const std::string uri = built_.secrets[secret].literals[uri_ref.substr(slash + 1)];
  const std::string password = secret + "/password";
  EXPECT_EQ(server.Env("PGPASSWORD"), password);
  EXPECT_TRUE(built_.secrets[secret].files.count("password")) << "the password comes from a file under tokens/";

  const std::optional<PostgresUri> parsed = ParsePostgresUri(uri);
  ASSERT_TRUE(parsed) << uri << ": not postgresql://USER@HOST:PORT/DB without a password";

  const YAML::Node* service = FindManifest("Service", parsed->server.host);
  ASSERT_TRUE(service) << uri << " names no Service";
  const Workload& postgres = Find("loom-postgres");
  EXPECT_TRUE(Selects(*service, postgres));
  const YAML::Node service_port = (*service)["spec"]["ports"][0];
  EXPECT_EQ(service_port["port"].as<int>(), parsed->server.port);
  const YAML::Node container_port = postgres.Container()["ports"][0];
  EXPECT_EQ(service_port["targetPort"].as<std::string>(), container_port["name"].as<std::string>());
  EXPECT_EQ(container_port["containerPort"].as<int>(), 5432);
  EXPECT_EQ(postgres.Env("POSTGRES_USER"), parsed->user);
  EXPECT_EQ(postgres.Env("POSTGRES_DB"), parsed->database);
  EXPECT_EQ(postgres.Env("POSTGRES_PASSWORD"), password);
  // Its data on its own claim, below the mount (PGDATA), as a non-root user.
  const std::string pgdata = postgres.Env("PGDATA");
  const YAML::Node claim = postgres.manifest["spec"]["volumeClaimTemplates"][0];
  ASSERT_TRUE(claim);
  bool on_claim = false;
  for (const YAML::Node& mount : postgres.Container()["volumeMounts"]) {
    on_claim |= mount["name"].as<std::string>() == claim["metadata"]["name"].as<std::string>() &&
                pgdata.starts_with(mount["mountPath"].as<std::string>() + "/");
  }
  EXPECT_TRUE(on_claim) << "PGDATA " << pgdata;
  EXPECT_TRUE(postgres.Pod()["securityContext"]["runAsNonRoot"].as<bool>(false));
}

}  // namespace
}  // namespace loom::deploy_test
