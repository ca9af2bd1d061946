# Sourced by the scripts that drive Loom through its job service on this machine:
# starts loom-server on loopback with local workers (data in a temporary
# directory, removed with the server on exit) and defines `loom`, the client
# pointed at it. Expects BUILD_DIR; LOOM_PORT (default 7450), LOCAL_WORKERS
# (default 1).
ADDRESS=127.0.0.1:${LOOM_PORT:-7450}
DATA=$(mktemp -d -t loom-server.XXXXXX)
"$BUILD_DIR/server/loom-server" --data "$DATA" --listen "$ADDRESS" --local-workers "${LOCAL_WORKERS:-1}" &
SERVER=$!
stop_server() {
  kill -TERM "$SERVER" 2>/dev/null && wait "$SERVER" || true
  rm -rf "$DATA"
}
trap stop_server EXIT
loom() { "$BUILD_DIR/client/loom" --server "$ADDRESS" "$@"; }
loom server-info --wait 60
