// deploy/k8s against the code: the kustomization's manifests parse; every container's
// image, flags, ports, probes and secrets match the code (container_checks.h); the
// GPU worker asks for one GPU with the graphics capability; the server's data is a
// PersistentVolumeClaim mounted at --data.

#include <gtest/gtest.h>

#include <fstream>

#include "binary_options.h"
#include "container_checks.h"
#include "deploy_files.h"

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
};

class KubernetesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::filesystem::path dir = DeployDir() / "k8s";
    const auto kustomization = LoadYamlDocuments(dir / "kustomization.yaml");
    ASSERT_EQ(kustomization.size(), 1u);
    for (const std::string& resource : Strings(kustomization[0]["resources"])) {
      ASSERT_TRUE(std::filesystem::exists(dir / resource)) << resource;
      for (const YAML::Node& manifest : LoadYamlDocuments(dir / resource)) {
        const std::string kind = manifest["kind"].as<std::string>();
        if (kind == "Service") services_.push_back(manifest);
        if (kind == "Deployment" || kind == "StatefulSet") workloads_.push_back({resource, manifest});
      }
    }
    for (const YAML::Node& generator : kustomization[0]["secretGenerator"]) {
      std::set<std::string>& keys = secrets_[generator["name"].as<std::string>()];
      for (const std::string& file : Strings(generator["files"])) {
        const size_t equals = file.find('=');
        keys.insert(equals == std::string::npos ? std::filesystem::path(file).filename().string() : file.substr(0, equals));
        // Token files stay out of git (deploy/.gitignore: tokens/).
        EXPECT_EQ(file.substr(equals + 1).rfind("tokens/", 0), 0u) << file;
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

  // Keys of `secret_name` the volume exposes: its items, or all the secret's keys.
  std::set<std::string> VolumeKeys(const YAML::Node& volume) const {
    const auto secret = secrets_.find(volume["secret"]["secretName"].as<std::string>());
    if (secret == secrets_.end()) return {};
    if (!volume["secret"]["items"]) return secret->second;
    std::set<std::string> keys;
    for (const YAML::Node& item : volume["secret"]["items"]) keys.insert(item["path"].as<std::string>());
    return keys;
  }

  std::vector<YAML::Node> services_;
  std::vector<Workload> workloads_;
  std::map<std::string, std::set<std::string>> secrets_;  // generated secret -> keys
  std::set<std::string> service_names_;
};

TEST_F(KubernetesTest, HasTheServerAGpuWorkerAndACpuWorker) {
  EXPECT_EQ(Find("loom-server").manifest["kind"].as<std::string>(), "StatefulSet");
  EXPECT_EQ(Find("loom-worker-gpu").manifest["kind"].as<std::string>(), "Deployment");
  EXPECT_EQ(Find("loom-worker-cpu").manifest["kind"].as<std::string>(), "Deployment");
  EXPECT_EQ(service_names_, std::set<std::string>{"loom-server"});
}

TEST_F(KubernetesTest, EveryContainerMatchesTheCode) {
  for (const Workload& workload : workloads_) {
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

TEST_F(KubernetesTest, ServicePortReachesTheServersPort) {
  const int port = DefaultServerPort();
  const YAML::Node service = services_.at(0);
  const YAML::Node service_port = service["spec"]["ports"][0];
  EXPECT_EQ(service_port["port"].as<int>(), port);
  const Workload& server = Find("loom-server");
  // The selector picks the server's pods.
  for (const auto& label : service["spec"]["selector"]) {
    EXPECT_EQ(server.manifest["spec"]["template"]["metadata"]["labels"][label.first.as<std::string>()].as<std::string>(""),
              label.second.as<std::string>());
  }
  const YAML::Node container_port = server.Container()["ports"][0];
  EXPECT_EQ(container_port["containerPort"].as<int>(), port);
  const std::string target = service_port["targetPort"].as<std::string>();
  EXPECT_TRUE(target == container_port["name"].as<std::string>("") || target == std::to_string(port)) << target;
  EXPECT_EQ(server.manifest["spec"]["serviceName"].as<std::string>(), service["metadata"]["name"].as<std::string>());
}

TEST_F(KubernetesTest, SecretsReadAreGeneratedAndMounted) {
  ASSERT_FALSE(secrets_.empty());
  for (const Workload& workload : workloads_) {
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

TEST_F(KubernetesTest, ServerDataIsAPersistentVolumeClaimAtDataDir) {
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

TEST_F(KubernetesTest, GpuWorkerAsksForOneGpuWithGraphicsAndCpuWorkerForNone) {
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

}  // namespace
}  // namespace loom::deploy_test
