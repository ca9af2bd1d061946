#pragma once
// The command line a Loom binary accepts, read from the built binary's own --help
// (CLI11's layout), so that deployment files are checked against the binaries as
// built: renaming a flag, or changing the default port, fails the deploy tests.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace loom::deploy_test {

struct BinaryOptions {
  std::string binary;                           // its name, for messages
  std::map<std::string, bool> takes_value;      // "--listen" -> true, "--probe" -> false
  std::map<std::string, std::string> defaults;  // "--listen" -> "127.0.0.1:7450"

  static BinaryOptions FromHelp(std::string binary, const std::string& help);

  // Every problem with `args`, the arguments after the program's name: an option the
  // binary lacks, an option without its value, a value given to a flag, a positional
  // argument (loom-server and loom-worker take none).
  std::vector<std::string> Problems(const std::vector<std::string>& args) const;
};

// The options of the built loom-server, loom-worker or loom (runs BINARY --help once).
const BinaryOptions& LoomBinary(std::string_view name);
// The built binary's path; throws for a name that is not a Loom binary.
std::string LoomBinaryPath(std::string_view name);
bool IsLoomBinary(std::string_view name);

// The value `args` gives `option` ("--listen X" or "--listen=X"), if any.
std::optional<std::string> OptionValue(const std::vector<std::string>& args, std::string_view option);
bool HasFlag(const std::vector<std::string>& args, std::string_view flag);

// "host:port" split; port -1 when there is none.
struct HostPort {
  std::string host;
  int port = -1;
};
HostPort SplitAddress(std::string_view address);

// "postgresql://USER@HOST:PORT/DB" (a --store value) split; nullopt for anything
// else, a password in it included (the deployments give it as PGPASSWORD).
struct PostgresUri {
  std::string user;
  HostPort server;
  std::string database;
};
std::optional<PostgresUri> ParsePostgresUri(std::string_view uri);

// The server's default port, from loom-server --help (--listen's default).
int DefaultServerPort();

}  // namespace loom::deploy_test
