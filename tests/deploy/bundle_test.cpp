// The worker bundle (deploy/bundle/make_bundle.sh), made once by the ctest fixture
// deploy.make_bundle into LOOM_BUNDLE_DIR and run here with a clean environment:
// the bundled worker makes its GL context (llvmpipe without a GPU), every library
// of every bundled binary resolves from the bundle or the host's glibc, no GL vendor
// driver is bundled, and run.sh takes the bundled copy of a host-first library, or
// refuses to run, when the host's is too old.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <regex>
#include <sstream>

#include "core/util/file_io.h"
#include "run_command.h"

namespace loom::deploy_test {
namespace {

const std::filesystem::path kBundle = LOOM_BUNDLE_DIR;
const char* const kBinaries[] = {"loom-server", "loom-worker", "loom", "loom-lab"};
// glibc's libraries: the host's, by design (make_bundle.sh).
const std::regex kGlibc(R"(^(ld-linux-x86-64|libc|libm|libmvec|libdl|libpthread|librt|libresolv|libutil)\.so.*)");

std::string RunSh(const std::filesystem::path& bundle, const std::string& arguments, const std::string& environment = "") {
  return "env -i " + environment + " " + ShellQuote((bundle / "run.sh").string()) + " " + arguments;
}

// A copy of the bundle made of symbolic links, whose small files a test may change.
std::filesystem::path LinkedCopy(const std::string& name) {
  const std::filesystem::path copy = kBundle.parent_path() / name;
  std::filesystem::remove_all(copy);
  const CommandResult result = RunCommand("cp -rs " + ShellQuote(kBundle.string()) + " " + ShellQuote(copy.string()));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return copy;
}

void Replace(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::remove(path);  // the link, not the bundle's file
  WriteFileAtomic(path, text);
}

TEST(Bundle, WorkerProbeWithACleanEnvironmentMakesItsGlContext) {
  const CommandResult probe = RunCommand(RunSh(kBundle, "loom-worker --probe --json"));
  ASSERT_EQ(probe.exit_code, 0) << probe.output;
  // stdout's one JSON line, among stderr's log lines.
  nlohmann::json capabilities;
  std::istringstream lines(probe.output);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && line[0] == '{') capabilities = nlohmann::json::parse(line);
  }
  ASSERT_TRUE(capabilities.contains("gl_renderer")) << probe.output;
  if (std::filesystem::exists("/dev/nvidia0")) {
    EXPECT_FALSE(capabilities["software"].get<bool>()) << probe.output;  // a GPU machine: its driver
  } else {
    EXPECT_NE(capabilities["gl_renderer"].get<std::string>().find("llvmpipe"), std::string::npos) << probe.output;
    EXPECT_TRUE(capabilities["software"].get<bool>());
  }
  EXPECT_EQ(capabilities["gl_version"].get<std::string>().rfind("4.", 0), 0u) << probe.output;
}

TEST(Bundle, EveryLibraryResolvesFromTheBundleOrTheHostsGlibc) {
  const std::regex resolved(R"(^\s*(\S+) => (\S+))");
  for (const char* binary : kBinaries) {
    const CommandResult ldd = RunCommand(RunSh(kBundle, "ldd " + ShellQuote((kBundle / "bin" / binary).string())));
    ASSERT_EQ(ldd.exit_code, 0) << ldd.output;
    EXPECT_EQ(ldd.output.find("not found"), std::string::npos) << binary << ":\n" << ldd.output;
    int from_bundle = 0;
    std::istringstream lines(ldd.output);
    for (std::string line; std::getline(lines, line);) {
      std::smatch match;
      if (!std::regex_search(line, match, resolved)) continue;
      const std::string soname = match[1], path = match[2];
      if (path.rfind(kBundle.string() + "/", 0) == 0) {
        ++from_bundle;
      } else {
        // The host's: glibc, or a host-first library the host has new enough.
        EXPECT_TRUE(std::regex_match(soname, kGlibc) || std::filesystem::exists(kBundle / "lib/host-first" / soname))
            << binary << ": " << soname << " resolves outside the bundle, to " << path;
      }
    }
    EXPECT_GE(from_bundle, 10) << binary;
  }
}

TEST(Bundle, CarriesGlvndButNoGlVendorDriver) {
  EXPECT_TRUE(std::filesystem::exists(kBundle / "lib/libEGL.so.1"));
  EXPECT_TRUE(std::filesystem::exists(kBundle / "lib/libOpenGL.so.0"));
  EXPECT_TRUE(std::filesystem::exists(kBundle / "lib/libGLdispatch.so.0"));
  const std::regex vendor(R"(^(libEGL_|libGLX_|libnvidia-|libgallium|libLLVM|.*_dri\.so).*)");
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kBundle / "lib")) {
    EXPECT_FALSE(std::regex_match(entry.path().filename().string(), vendor)) << entry.path();
  }
  // What the MANIFEST leaves to the host is glibc alone.
  std::ifstream manifest(kBundle / "MANIFEST");
  int host = 0;
  for (std::string line; std::getline(manifest, line);) {
    std::istringstream words(line);
    std::string soname, placement;
    words >> soname >> placement;
    if (placement != "host") continue;
    ++host;
    EXPECT_TRUE(std::regex_match(soname, kGlibc)) << line;
  }
  EXPECT_GE(host, 2);
}

TEST(Bundle, TooOldHostLibraryIsReplacedByTheBundledCopy) {
  const std::filesystem::path copy = LinkedCopy("bundle-old-libstdcxx");
  // The host's libstdc++ "lacks" a symbol version the bundle needs.
  Replace(copy / "lib/host-first/versions", "libstdc++.so.6 GLIBCXX_3.4 GLIBCXX_3.4.999\n");
  const std::filesystem::path tmp = copy / "tmp";
  std::filesystem::create_directories(tmp);
  const CommandResult ldd = RunCommand(RunSh(copy, "ldd " + ShellQuote((copy / "bin/loom").string()), "TMPDIR=" + tmp.string()));
  ASSERT_EQ(ldd.exit_code, 0) << ldd.output;
  const std::regex libstdcxx(R"(libstdc\+\+\.so\.6 => (\S+))");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(ldd.output, match, libstdcxx)) << ldd.output;
  EXPECT_EQ(match[1].str().rfind((tmp / "loom-bundle.").string(), 0), 0u) << ldd.output;
  // ... while a host-first library the host has new enough stays the host's.
  const std::regex libz(R"(libz\.so\.1 => (\S+))");
  ASSERT_TRUE(std::regex_search(ldd.output, match, libz)) << ldd.output;
  EXPECT_EQ(match[1].str().find(tmp.string()), std::string::npos) << ldd.output;
  std::filesystem::remove_all(copy);
}

TEST(Bundle, TooOldHostGlibcIsAClearError) {
  const std::filesystem::path copy = LinkedCopy("bundle-old-glibc");
  Replace(copy / "lib/glibc-versions", "GLIBC_2.999\n");
  const CommandResult run = RunCommand(RunSh(copy, "loom --version"));
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find("GLIBC_2.999"), std::string::npos) << run.output;
  std::filesystem::remove_all(copy);
}

}  // namespace
}  // namespace loom::deploy_test
