#pragma once
// Warnings about refused input that anyone who can reach the port can cause: a
// missing or wrong bearer token, a message protobuf cannot parse (it logs invalid
// UTF-8 in a string field before any handler runs). At most one such warning a
// second is written, however many arrive, so a client cannot flood the log; the
// next one says how many went unwritten.

#include <string_view>

namespace loom::server {

void WarnRefused(std::string_view message);

// Routes protobuf's own log lines through WarnRefused (warnings and errors) or
// spdlog (the rest). Process-wide; the server calls it at start.
void RouteProtobufLogs();

}  // namespace loom::server
