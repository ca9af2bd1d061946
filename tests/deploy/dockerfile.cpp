#include "dockerfile.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace loom::deploy_test {
namespace {

std::vector<std::string> SplitWords(const std::string& text) {
  std::istringstream stream(text);
  std::vector<std::string> words;
  for (std::string word; stream >> word;) words.push_back(word);
  return words;
}

std::string Upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::toupper(c); });
  return text;
}

// "apt-get install -y --no-install-recommends a b c && rm ..." -> {a, b, c}.
void AddAptPackages(const std::string& run, std::set<std::string>& packages) {
  const std::vector<std::string> words = SplitWords(run);
  for (size_t i = 0; i + 1 < words.size(); ++i) {
    if (words[i] != "apt-get" || std::find(words.begin() + i, words.end(), "install") == words.end()) continue;
    size_t j = i + 1;
    while (j < words.size() && words[j] != "install") ++j;
    for (++j; j < words.size() && words[j] != "&&" && words[j] != ";" && words[j] != "|"; ++j) {
      if (words[j][0] != '-') packages.insert(words[j]);
    }
  }
}

}  // namespace

std::vector<std::string> CommandWords(const std::string& arguments) {
  const size_t first = arguments.find_first_not_of(" \t");
  if (first != std::string::npos && arguments[first] == '[') {
    return nlohmann::json::parse(arguments.substr(first)).get<std::vector<std::string>>();
  }
  return SplitWords(arguments);
}

DockerCopy ParseCopy(const DockerInstruction& copy) {
  DockerCopy result;
  result.line = copy.line;
  std::vector<std::string> paths;
  for (const std::string& word : SplitWords(copy.arguments)) {
    if (word.rfind("--from=", 0) == 0) result.from = word.substr(7);
    else if (word.rfind("--", 0) != 0) paths.push_back(word);
  }
  if (paths.size() < 2) throw std::runtime_error("COPY at line " + std::to_string(copy.line) + " needs a source and a destination");
  result.destination = paths.back();
  paths.pop_back();
  result.sources = paths;
  return result;
}

Dockerfile Dockerfile::Read(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  Dockerfile file;
  std::string line, pending;
  int line_number = 0, start_line = 0;
  static const std::regex from(R"(^\s*(\S+)(?:\s+[Aa][Ss]\s+(\S+))?\s*$)");
  auto finish = [&] {
    const size_t first = pending.find_first_not_of(" \t");
    if (first == std::string::npos) return;
    const size_t end = pending.find_first_of(" \t", first);
    DockerInstruction instruction{Upper(pending.substr(first, end - first)),
                                  end == std::string::npos ? "" : pending.substr(end + 1), start_line};
    if (instruction.keyword == "FROM") {
      std::smatch match;
      if (!std::regex_match(instruction.arguments, match, from)) {
        throw std::runtime_error(path.string() + ":" + std::to_string(start_line) + ": cannot read FROM");
      }
      file.stages.push_back({match[2].matched ? match[2].str() : "", match[1].str(), {}});
    } else if (file.stages.empty()) {
      if (instruction.keyword != "ARG") {
        throw std::runtime_error(path.string() + ":" + std::to_string(start_line) + ": instruction before FROM");
      }
    } else {
      file.stages.back().instructions.push_back(instruction);
    }
    pending.clear();
  };
  while (std::getline(in, line)) {
    ++line_number;
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;  // comments may sit inside continuations
    if (pending.empty()) start_line = line_number;
    const bool continues = !line.empty() && line.back() == '\\';
    pending += continues ? line.substr(0, line.size() - 1) + " " : line;
    if (!continues) finish();
  }
  finish();
  return file;
}

const DockerStage* Dockerfile::Stage(const std::string& name) const {
  for (const DockerStage& stage : stages) {
    if (stage.name == name) return &stage;
  }
  return nullptr;
}

std::vector<const DockerStage*> Dockerfile::Lineage(const std::string& name) const {
  std::vector<const DockerStage*> lineage;
  for (const DockerStage* stage = Stage(name); stage != nullptr; stage = Stage(stage->base)) {
    lineage.push_back(stage);
  }
  return lineage;
}

std::map<std::string, DockerImage> Dockerfile::Images() const {
  static const std::regex title(R"re(org\.opencontainers\.image\.title="([^"]+)")re");
  static const std::regex env_pair(R"(([A-Za-z_][A-Za-z0-9_]*)=(\S+))");
  std::map<std::string, DockerImage> images;
  for (const DockerStage& stage : stages) {
    DockerImage image;
    image.stage = stage.name;
    for (const DockerInstruction& label : stage.instructions) {
      std::smatch match;
      if (label.keyword == "LABEL" && std::regex_search(label.arguments, match, title)) image.title = match[1];
    }
    if (image.title.empty()) continue;
    // Bases first, so that a stage's own ENTRYPOINT, CMD, USER or ENV wins.
    std::vector<const DockerStage*> lineage = Lineage(stage.name);
    std::reverse(lineage.begin(), lineage.end());
    for (const DockerStage* layer : lineage) {
      for (const DockerInstruction& instruction : layer->instructions) {
        const std::string& keyword = instruction.keyword;
        if (keyword == "ENTRYPOINT") image.entrypoint = CommandWords(instruction.arguments);
        else if (keyword == "CMD") image.cmd = CommandWords(instruction.arguments);
        else if (keyword == "USER") image.user = instruction.arguments;
        else if (keyword == "RUN") AddAptPackages(instruction.arguments, image.packages);
        else if (keyword == "EXPOSE") {
          for (const std::string& port : SplitWords(instruction.arguments)) image.exposed_ports.push_back(std::stoi(port));
        } else if (keyword == "ENV") {
          for (std::sregex_iterator it(instruction.arguments.begin(), instruction.arguments.end(), env_pair), end;
               it != end; ++it) {
            image.env[(*it)[1]] = (*it)[2];
          }
        } else if (keyword == "HEALTHCHECK") {
          const size_t cmd = instruction.arguments.find("CMD ");
          if (cmd != std::string::npos) image.healthcheck = CommandWords(instruction.arguments.substr(cmd + 4));
        } else if (keyword == "COPY") {
          DockerCopy copy = ParseCopy(instruction);
          const std::filesystem::path destination(copy.destination);
          if (copy.destination.back() == '/') {
            for (const std::string& source : copy.sources) {
              if (copy.destination == "/usr/local/bin/") image.programs.insert(std::filesystem::path(source).filename());
            }
          } else if (destination.parent_path() == "/usr/local/bin") {
            image.programs.insert(destination.filename());
          }
          image.copies.push_back(std::move(copy));
        }
      }
    }
    images[image.title] = std::move(image);
  }
  return images;
}

}  // namespace loom::deploy_test
