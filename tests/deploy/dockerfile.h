#pragma once
// deploy/docker/Dockerfile read into its stages and the images they make, enough to
// check the file against the code: what each image installs, copies, runs, exposes
// and health-checks. Not a general Dockerfile parser: it reads the forms Loom uses.

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace loom::deploy_test {

struct DockerInstruction {
  std::string keyword;    // upper case: FROM, RUN, COPY, ...
  std::string arguments;  // continuation lines joined
  int line = 0;
};

struct DockerStage {
  std::string name;  // FROM ... AS name
  std::string base;  // image or earlier stage
  std::vector<DockerInstruction> instructions;
};

// A COPY: its --from stage (empty: the build context), sources and destination.
struct DockerCopy {
  std::string from;
  std::vector<std::string> sources;
  std::string destination;
  int line = 0;
};

// What a final stage (one with an org.opencontainers.image.title label) makes.
struct DockerImage {
  std::string title;  // the image's name: loom-server, loom-worker
  std::string stage;
  std::vector<std::string> entrypoint, cmd, healthcheck;  // exec form words
  std::set<std::string> programs;  // names copied into /usr/local/bin, this stage or its bases
  std::set<std::string> packages;  // apt-get installed, this stage or its bases
  std::map<std::string, std::string> env;
  std::string user;
  std::vector<int> exposed_ports;
  std::vector<DockerCopy> copies;  // this stage and its bases
};

struct Dockerfile {
  std::vector<DockerStage> stages;

  static Dockerfile Read(const std::filesystem::path& path);
  const DockerStage* Stage(const std::string& name) const;
  // The stage and the stages it is built FROM, the stage itself first.
  std::vector<const DockerStage*> Lineage(const std::string& name) const;
  // Every image, by title.
  std::map<std::string, DockerImage> Images() const;
};

DockerCopy ParseCopy(const DockerInstruction& copy);
// The words of an exec-form (JSON array) or shell-form command.
std::vector<std::string> CommandWords(const std::string& arguments);

}  // namespace loom::deploy_test
