// deploy/docker/Dockerfile against the code: what it copies exists, the runtime
// packages provide every library the binaries link, the entry points' flags exist,
// the port is the server's, the images run as a non-root user with a health check
// (for the worker, a liveness check of the alive file its default command writes).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fnmatch.h>

#include <fstream>
#include <sstream>

#include "binary_options.h"
#include "container_checks.h"
#include "core/version.h"
#include "deploy_files.h"
#include "run_command.h"

namespace loom::deploy_test {
namespace {

// Packages every debian:12 image has (Essential or required by apt).
const std::set<std::string> kBaseImagePackages = {"libc6", "libgcc-s1", "libstdc++6"};

std::vector<std::string> DockerIgnorePatterns() {
  std::ifstream in(DeployDir() / "docker" / "Dockerfile.dockerignore");
  std::vector<std::string> patterns;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') patterns.push_back(line);
  }
  return patterns;
}

bool IgnoredByDocker(const std::string& path, const std::vector<std::string>& patterns) {
  // A pattern excludes what it matches and everything under it: try every prefix
  // of whole path components.
  for (size_t end = path.find('/');; end = path.find('/', end + 1)) {
    const std::string prefix = path.substr(0, end);
    for (const std::string& pattern : patterns) {
      if (fnmatch(pattern.c_str(), prefix.c_str(), FNM_PATHNAME) == 0) return true;
    }
    if (end == std::string::npos) return false;
  }
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// The Debian packages (on this machine, set up by scripts/setup.sh) providing the
// libraries `binary` names in its NEEDED entries. dpkg knows a library by the path
// its package installed, /lib/... or /usr/lib/..., or behind an alternatives link.
std::set<std::string> PackagesLinkedBy(const std::string& binary) {
  const CommandResult needed =
      RunCommand("readelf -d " + ShellQuote(binary) + " | sed -n 's/.*(NEEDED).*\\[\\(.*\\)\\]/\\1/p'");
  EXPECT_EQ(needed.exit_code, 0) << needed.output;
  std::map<std::string, std::string> cache;  // soname -> path, from the linker cache
  for (const std::string& line : Lines(RunCommand("/sbin/ldconfig -p").output)) {
    std::istringstream words(line);
    std::string soname, word, path;
    words >> soname;
    while (words >> word) path = word;
    if (line.find("x86-64") != std::string::npos) cache.emplace(soname, path);
  }
  std::string candidates;
  std::map<std::string, std::string> soname_of;  // candidate path -> soname
  for (const std::string& soname : Lines(needed.output)) {
    const std::string path = cache[soname];
    EXPECT_FALSE(path.empty()) << binary << " needs " << soname << ", which the linker cache lacks";
    if (path.empty()) continue;
    const std::string bare = path.rfind("/usr/", 0) == 0 ? path.substr(4) : path;
    for (const std::string& candidate : {bare, "/usr" + bare, std::filesystem::canonical(path).string()}) {
      soname_of[candidate] = soname;
      candidates += " " + ShellQuote(candidate);
    }
  }
  std::map<std::string, std::string> package_of;  // soname -> package
  for (const std::string& line : Lines(RunCommand("dpkg -S" + candidates + " 2>/dev/null").output)) {
    const size_t separator = line.find(": ");
    if (line.rfind("diversion", 0) == 0 || separator == std::string::npos) continue;
    const std::string package = line.substr(0, line.find(':'));
    const auto soname = soname_of.find(line.substr(separator + 2));
    if (soname != soname_of.end()) package_of.emplace(soname->second, package);
  }
  std::set<std::string> packages;
  for (const std::string& soname : Lines(needed.output)) {
    EXPECT_TRUE(package_of.count(soname)) << binary << ": no package provides " << soname;
    if (package_of.count(soname)) packages.insert(package_of[soname]);
  }
  // Loom links gRPC, protobuf, OpenImageIO, Embree, ...: a short list means the
  // lookup itself failed.
  EXPECT_GE(packages.size(), 8u) << binary;
  return packages;
}

TEST(Dockerfile, BuildsTheServerAndWorkerImages) {
  ASSERT_TRUE(LoomImages().count("loom-server"));
  ASSERT_TRUE(LoomImages().count("loom-worker"));
  EXPECT_EQ(LoomImages().at("loom-server").entrypoint, std::vector<std::string>{"loom-server"});
  EXPECT_EQ(LoomImages().at("loom-worker").entrypoint, std::vector<std::string>{"loom-worker"});
  for (const DockerStage& stage : LoomDockerfile().stages) {
    if (LoomDockerfile().Stage(stage.base) == nullptr) {
      EXPECT_EQ(stage.base, "debian:12") << stage.name;
    }
  }
}

TEST(Dockerfile, BuildStageRunsSetupAndBuildsEveryCopiedBinaryAndTheDashboard) {
  const DockerStage* build = LoomDockerfile().Stage("build");
  ASSERT_NE(build, nullptr);
  std::string runs;
  for (const DockerInstruction& instruction : build->instructions) {
    if (instruction.keyword == "RUN") runs += instruction.arguments + "\n";
  }
  EXPECT_NE(runs.find("scripts/setup.sh --no-build"), std::string::npos) << runs;
  for (const auto& [title, image] : LoomImages()) {
    for (const DockerCopy& copy : image.copies) {
      if (copy.from != "build") continue;
      for (const std::string& source : copy.sources) {
        if (source == "/out/web") {  // the dashboard's files
          EXPECT_NE(runs.find("npm run --silent build) && cp -r web/dist /out/web"), std::string::npos) << runs;
          continue;
        }
        const std::string binary = std::filesystem::path(source).filename();
        EXPECT_TRUE(IsLoomBinary(binary)) << title << " copies " << source;
        EXPECT_NE(runs.find(" " + binary + " "), std::string::npos) << "the build stage does not build " << binary;
      }
    }
  }
}

TEST(Dockerfile, CopySourcesExistAndAreInTheBuildContext) {
  const std::vector<std::string> ignored = DockerIgnorePatterns();
  EXPECT_TRUE(IgnoredByDocker("build/server/loom-server", ignored));
  EXPECT_TRUE(IgnoredByDocker(".git/HEAD", ignored));
  int copies = 0;
  for (const DockerStage& stage : LoomDockerfile().stages) {
    for (const DockerInstruction& instruction : stage.instructions) {
      if (instruction.keyword != "COPY") continue;
      const DockerCopy copy = ParseCopy(instruction);
      if (!copy.from.empty()) {
        EXPECT_NE(LoomDockerfile().Stage(copy.from), nullptr) << "line " << copy.line << ": no stage " << copy.from;
        continue;
      }
      for (const std::string& source : copy.sources) {
        ++copies;
        if (source == ".") continue;
        EXPECT_TRUE(std::filesystem::exists(RepoDir() / source)) << "line " << copy.line << ": " << source;
        EXPECT_FALSE(IgnoredByDocker(source, ignored)) << "line " << copy.line << ": " << source << " is ignored";
      }
    }
  }
  EXPECT_GE(copies, 4);
}

TEST(Dockerfile, RuntimePackagesProvideEveryLibraryTheBinariesLink) {
  for (const auto& [title, image] : LoomImages()) {
    for (const std::string& program : image.programs) {
      if (!IsLoomBinary(program)) continue;
      for (const std::string& package : PackagesLinkedBy(LoomBinaryPath(program))) {
        EXPECT_TRUE(image.packages.count(package) || kBaseImagePackages.count(package))
            << "image " << title << ": " << program << " links a library of " << package
            << ", which the image does not install";
      }
    }
  }
}

TEST(Dockerfile, ImagesRunAsNonRootWithAHealthCheckTheyCarry) {
  for (const auto& [title, image] : LoomImages()) {
    ASSERT_FALSE(image.user.empty()) << title;
    const std::string uid = image.user.substr(0, image.user.find(':'));
    EXPECT_NE(uid, "0") << title;
    EXPECT_NE(uid, "root") << title;
    // Numeric, so that Kubernetes' runAsNonRoot can verify it.
    EXPECT_EQ(uid.find_first_not_of("0123456789"), std::string::npos) << title << ": USER " << image.user;
    ASSERT_FALSE(image.healthcheck.empty()) << title;
    EXPECT_TRUE(image.programs.count(image.healthcheck[0])) << title << " health check runs " << image.healthcheck[0];
    EXPECT_TRUE(std::filesystem::exists(DeployDir() / "docker" / image.healthcheck[0])) << image.healthcheck[0];
  }
}

TEST(Dockerfile, ImagesRunWithTheirDefaultArgumentsAndHealthChecksMatchTheCode) {
  for (const auto& [title, image] : LoomImages()) {
    // As `docker run IMAGE` would: the image's CMD, its HEALTHCHECK, next to a server
    // named loom-server (the CMD's default).
    const ContainerSpec container{"Dockerfile image " + title, title + ":" + kVersion, false, {}, image.healthcheck,
                                  {}, {"loom-server"}};
    for (const std::string& problem : ContainerProblems(container)) ADD_FAILURE() << problem;
  }
}

TEST(Dockerfile, EntryPointsTakeTheirDefaultArgumentsAndTheServerExposesItsPort) {
  const int port = DefaultServerPort();
  for (const auto& [title, image] : LoomImages()) {
    const BinaryOptions& options = LoomBinary(image.entrypoint.at(0));
    EXPECT_TRUE(options.Problems(image.cmd).empty()) << title << ": " << options.Problems(image.cmd).front();
  }
  const DockerImage& server = LoomImages().at("loom-server");
  const int dashboard = SplitAddress(OptionValue(server.cmd, "--http").value_or("")).port;
  EXPECT_EQ(server.exposed_ports, (std::vector<int>{port, dashboard}));
  EXPECT_EQ(SplitAddress(OptionValue(server.cmd, "--listen").value_or("")).port, port);
  const DockerImage& worker = LoomImages().at("loom-worker");
  EXPECT_EQ(SplitAddress(OptionValue(worker.cmd, "--server").value_or("")).port, port);
}

TEST(Dockerfile, WorkerImageCarriesTheGlvndLoaderMesaAndTheNvidiaVendorFile) {
  const DockerImage& worker = LoomImages().at("loom-worker");
  for (const char* package : {"libglvnd0", "libegl1", "libopengl0", "libgl1", "libegl-mesa0", "libgl1-mesa-dri"}) {
    EXPECT_TRUE(worker.packages.count(package)) << package;
  }
  EXPECT_NE(worker.env.at("NVIDIA_DRIVER_CAPABILITIES").find("graphics"), std::string::npos);
  EXPECT_FALSE(worker.env.at("NVIDIA_VISIBLE_DEVICES").empty());
  bool vendor_file = false;
  for (const DockerCopy& copy : worker.copies) {
    if (copy.destination != "/usr/share/glvnd/egl_vendor.d/10_nvidia.json") continue;
    vendor_file = true;
    std::ifstream in(RepoDir() / copy.sources.at(0));
    EXPECT_EQ(nlohmann::json::parse(in)["ICD"]["library_path"], "libEGL_nvidia.so.0");
  }
  EXPECT_TRUE(vendor_file);
  // The server image needs no GL driver: it runs no local workers.
  const DockerImage& server = LoomImages().at("loom-server");
  EXPECT_FALSE(server.packages.count("libgl1-mesa-dri"));
  EXPECT_EQ(OptionValue(server.cmd, "--local-workers"), "0");
}

}  // namespace
}  // namespace loom::deploy_test
