#!/usr/bin/env bash
# Writes Loom's two bearer tokens into DIR: loom_client_token (what clients send:
# LOOM_TOKEN) and loom_worker_token (what workers send). Each is 32 random bytes,
# base64url without padding. An existing token is kept, so running it twice changes
# nothing; delete a file to rotate that token (then restart the server and whoever
# uses it).
#
# DIR is mode 700, which is what keeps the tokens private on this machine; the files
# themselves are 644 because compose bind-mounts them as they are into containers
# that run as uid 10001, not as their owner.
#
#   deploy/make_tokens.sh deploy/tokens        # compose
#   deploy/make_tokens.sh deploy/k8s/tokens    # kustomize secretGenerator
#   deploy/make_tokens.sh /etc/loom            # systemd units (as root)
set -euo pipefail

if [[ $# -ne 1 ]]; then
  echo "usage: $0 DIR" >&2
  exit 2
fi
dir=$1
umask 077
mkdir -p "$dir"
chmod 700 "$dir"
for name in loom_client_token loom_worker_token; do
  if [[ -s "$dir/$name" ]]; then
    echo "kept    $dir/$name"
  else
    head -c 32 /dev/urandom | base64 | tr '+/' '-_' | tr -d '=\n' >"$dir/$name"
    echo >>"$dir/$name"
    chmod 644 "$dir/$name"
    echo "created $dir/$name"
  fi
done
