#pragma once
// Reading a /metrics scrape in tests: its samples, and promtool's verdict on it.

#include <map>
#include <string>

namespace loom::server {

// Every sample of a scrape, keyed by its name and labels as written
// ("loom_jobs{kind=\"render\",state=\"queued\"}").
std::map<std::string, double> Samples(const std::string& text);

// The sample `name` of a scrape; a test failure showing the scrape, and -1, if it
// has none.
double Sample(const std::string& text, const std::string& name);

// `promtool check metrics` on a scrape: "" when it passes, else what it said.
std::string PromtoolProblems(const std::string& text);

// `promtool <command> FILE` (e.g. "check rules", "test rules") with `file_text` in
// FILE: "" when it exits 0, else what it said.
std::string PromtoolOnFile(const std::string& command, const std::string& file_text);

}  // namespace loom::server
