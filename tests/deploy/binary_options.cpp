#include "binary_options.h"

#include <mutex>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "run_command.h"

namespace loom::deploy_test {

BinaryOptions BinaryOptions::FromHelp(std::string binary, const std::string& help) {
  BinaryOptions options;
  options.binary = std::move(binary);
  // "  --listen TEXT=127.0.0.1:7450", "  -h,--help   Print ...", "  --probe   Make ...":
  // a value type (upper-case word) follows the name after exactly one space; the
  // description after two or more. A default follows the type after '='.
  static const std::regex option_line(R"(^\s+(?:-\w,)?(--[A-Za-z0-9][A-Za-z0-9-]*)( [A-Z][^ ]*)?(.*)$)");
  std::istringstream lines(help);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch match;
    if (!std::regex_match(line, match, option_line)) continue;
    const std::string name = match[1];
    const bool takes_value = match[2].matched;
    options.takes_value[name] = takes_value;
    if (!takes_value) continue;
    // The type with its checks and default runs up to the first double space.
    const std::string rest = match[2].str() + match[3].str();
    const std::string type = rest.substr(0, rest.find("  "));
    if (const size_t equals = type.rfind('='); equals != std::string::npos) {
      options.defaults[name] = type.substr(equals + 1);
    }
  }
  return options;
}

std::vector<std::string> BinaryOptions::Problems(const std::vector<std::string>& args) const {
  std::vector<std::string> problems;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.rfind("--", 0) != 0) {
      problems.push_back(binary + ": unexpected argument '" + arg + "'");
      continue;
    }
    const size_t equals = arg.find('=');
    const std::string name = arg.substr(0, equals);
    const auto option = takes_value.find(name);
    if (option == takes_value.end()) {
      problems.push_back(binary + " has no option " + name);
    } else if (option->second && equals == std::string::npos) {
      if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) {
        problems.push_back(binary + ": " + name + " needs a value");
      } else {
        ++i;
      }
    } else if (!option->second && equals != std::string::npos) {
      problems.push_back(binary + ": " + name + " is a flag and takes no value");
    }
  }
  return problems;
}

bool IsLoomBinary(std::string_view name) {
  return name == "loom-server" || name == "loom-worker" || name == "loom" || name == "loom-lab";
}

std::string LoomBinaryPath(std::string_view name) {
  if (name == "loom-server") return LOOM_SERVER;
  if (name == "loom-worker") return LOOM_WORKER;
  if (name == "loom") return LOOM_CLI;
  if (name == "loom-lab") return LOOM_LAB;
  throw std::invalid_argument("not a Loom binary: " + std::string(name));
}

const BinaryOptions& LoomBinary(std::string_view name) {
  static std::mutex mu;
  static std::map<std::string, BinaryOptions, std::less<>> cache;
  std::lock_guard lock(mu);
  if (const auto found = cache.find(name); found != cache.end()) return found->second;
  const CommandResult help = RunCommand(ShellQuote(LoomBinaryPath(name)) + " --help");
  if (help.exit_code != 0) throw std::runtime_error(std::string(name) + " --help failed: " + help.output);
  return cache.emplace(std::string(name), BinaryOptions::FromHelp(std::string(name), help.output)).first->second;
}

std::optional<std::string> OptionValue(const std::vector<std::string>& args, std::string_view option) {
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == option && i + 1 < args.size()) return args[i + 1];
    if (args[i].size() > option.size() && args[i].compare(0, option.size(), option) == 0 &&
        args[i][option.size()] == '=') {
      return args[i].substr(option.size() + 1);
    }
  }
  return std::nullopt;
}

bool HasFlag(const std::vector<std::string>& args, std::string_view flag) {
  for (const std::string& arg : args) {
    if (arg == flag) return true;
  }
  return false;
}

HostPort SplitAddress(std::string_view address) {
  const size_t colon = address.rfind(':');
  if (colon == std::string_view::npos) return {std::string(address), -1};
  HostPort result{std::string(address.substr(0, colon)), -1};
  try {
    result.port = std::stoi(std::string(address.substr(colon + 1)));
  } catch (const std::exception&) {
    result.port = -1;
  }
  return result;
}

std::optional<PostgresUri> ParsePostgresUri(std::string_view uri) {
  constexpr std::string_view kScheme = "postgresql://";
  if (!uri.starts_with(kScheme)) return std::nullopt;
  const std::string_view rest = uri.substr(kScheme.size());
  const size_t at = rest.find('@');
  const size_t slash = rest.find('/', at == std::string_view::npos ? 0 : at);
  if (at == std::string_view::npos || slash == std::string_view::npos) return std::nullopt;
  PostgresUri parsed{std::string(rest.substr(0, at)), SplitAddress(rest.substr(at + 1, slash - at - 1)),
                     std::string(rest.substr(slash + 1))};
  if (parsed.user.empty() || parsed.user.find(':') != std::string::npos || parsed.server.host.empty() ||
      parsed.server.port <= 0 || parsed.database.empty()) {
    return std::nullopt;
  }
  return parsed;
}

int DefaultServerPort() {
  const auto& defaults = LoomBinary("loom-server").defaults;
  const auto listen = defaults.find("--listen");
  if (listen == defaults.end()) throw std::runtime_error("loom-server --help shows no default for --listen");
  return SplitAddress(listen->second).port;
}

}  // namespace loom::deploy_test
