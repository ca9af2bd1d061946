// deploy/systemd units against the code: ExecStart runs a Loom binary with flags it
// accepts (after systemd's specifier and environment expansion), on the server's
// port, with its tokens as credentials and its data under /var/lib, hardened.

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "binary_options.h"
#include "deploy_files.h"

namespace loom::deploy_test {
namespace {

// [Service] Key=Value lines (a key may repeat).
std::multimap<std::string, std::string> ServiceSection(const std::string& unit) {
  std::ifstream in(DeployDir() / "systemd" / unit);
  EXPECT_TRUE(in) << unit;
  std::multimap<std::string, std::string> keys;
  std::string section;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line[0] == '[') {
      section = line;
      continue;
    }
    const size_t equals = line.find('=');
    if (section == "[Service]" && equals != std::string::npos) keys.emplace(line.substr(0, equals), line.substr(equals + 1));
  }
  return keys;
}

std::string Value(const std::multimap<std::string, std::string>& keys, const std::string& key) {
  const auto found = keys.find(key);
  return found == keys.end() ? "" : found->second;
}

// ExecStart's words as systemd would pass them: %d the credentials directory, %i
// the instance, ${VAR} one word and $VAR split on blanks, from Environment=
// (`overrides` stands for an EnvironmentFile=).
std::vector<std::string> ExecStartWords(const std::multimap<std::string, std::string>& keys,
                                        const std::map<std::string, std::string>& overrides = {}) {
  std::map<std::string, std::string> environment;
  for (auto [it, end] = keys.equal_range("Environment"); it != end; ++it) {
    const size_t equals = it->second.find('=');
    environment[it->second.substr(0, equals)] = it->second.substr(equals + 1);
  }
  for (const auto& [name, value] : overrides) environment[name] = value;
  std::vector<std::string> words;
  std::istringstream stream(Value(keys, "ExecStart"));
  static const std::regex braced(R"(\$\{(\w+)\})");
  for (std::string word; stream >> word;) {
    word = std::regex_replace(word, std::regex("%d"), "/run/credentials/unit");
    word = std::regex_replace(word, std::regex("%i"), "1");
    std::smatch match;
    if (std::regex_search(word, match, braced)) {
      word = std::regex_replace(word, braced, environment[match[1]]);
    } else if (word.size() > 1 && word[0] == '$') {
      std::istringstream split(environment[word.substr(1)]);
      for (std::string part; split >> part;) words.push_back(part);
      continue;
    }
    words.push_back(word);
  }
  return words;
}

void ExpectAcceptedAndHardened(const std::string& unit, const std::vector<std::string>& words,
                               const std::multimap<std::string, std::string>& keys) {
  ASSERT_FALSE(words.empty()) << unit;
  const std::string binary = std::filesystem::path(words[0]).filename();
  ASSERT_TRUE(IsLoomBinary(binary)) << unit << " runs " << words[0];
  const std::vector<std::string> args(words.begin() + 1, words.end());
  for (const std::string& problem : LoomBinary(binary).Problems(args)) ADD_FAILURE() << unit << ": " << problem;

  // Every credential the command reads is loaded.
  for (const std::string& arg : args) {
    if (arg.rfind("/run/credentials/unit/", 0) != 0) continue;
    const std::string name = arg.substr(std::string("/run/credentials/unit/").size());
    bool loaded = false;
    for (auto [it, end] = keys.equal_range("LoadCredential"); it != end; ++it) loaded |= it->second.rfind(name + ":", 0) == 0;
    EXPECT_TRUE(loaded) << unit << " reads credential " << name << " without LoadCredential=" << name << ":...";
  }
  EXPECT_FALSE(Value(keys, "User").empty()) << unit;
  EXPECT_NE(Value(keys, "User"), "root") << unit;
  EXPECT_EQ(Value(keys, "NoNewPrivileges"), "yes") << unit;
  EXPECT_EQ(Value(keys, "ProtectSystem"), "strict") << unit;
  EXPECT_EQ(Value(keys, "KillSignal"), "SIGTERM") << unit << ": the binaries drain on SIGTERM";
}

TEST(Systemd, ServerUnitRunsLoomServerOnItsPortWithDataUnderVarLib) {
  const auto keys = ServiceSection("loom-server.service");
  const std::vector<std::string> words = ExecStartWords(keys);
  ExpectAcceptedAndHardened("loom-server.service", words, keys);
  const std::vector<std::string> args(words.begin() + 1, words.end());
  EXPECT_EQ(SplitAddress(OptionValue(args, "--listen").value_or("")).port, DefaultServerPort());
  EXPECT_EQ(OptionValue(args, "--data"), "/var/lib/" + Value(keys, "StateDirectory"));
  EXPECT_EQ(Value(keys, "StateDirectory"), "loom");
  EXPECT_TRUE(OptionValue(args, "--client-token-file") && OptionValue(args, "--worker-token-file"));
}

TEST(Systemd, WorkerTemplateRunsLoomWorkerAgainstTheServersPort) {
  const auto keys = ServiceSection("loom-worker@.service");
  const std::vector<std::string> words = ExecStartWords(keys);
  ExpectAcceptedAndHardened("loom-worker@.service", words, keys);
  const std::vector<std::string> args(words.begin() + 1, words.end());
  EXPECT_EQ(SplitAddress(OptionValue(args, "--server").value_or("")).port, DefaultServerPort());
  EXPECT_TRUE(OptionValue(args, "--token-file"));
  // The liveness file lies in the unit's own runtime directory, which systemd makes
  // writable under ProtectSystem=strict.
  EXPECT_EQ(std::filesystem::path(OptionValue(args, "--alive-file").value_or("")).parent_path(),
            "/run/" + std::regex_replace(Value(keys, "RuntimeDirectory"), std::regex("%i"), "1"));
  // What the unit's comments tell CPU-only machines to set in /etc/loom/worker.env.
  const std::vector<std::string> software = ExecStartWords(keys, {{"LOOM_WORKER_FLAGS", "--software"}});
  EXPECT_TRUE(LoomBinary("loom-worker").Problems({software.begin() + 1, software.end()}).empty());
  EXPECT_TRUE(HasFlag(software, "--software"));
}

}  // namespace
}  // namespace loom::deploy_test
