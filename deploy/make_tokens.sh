#!/usr/bin/env bash
# Writes Loom's two bearer tokens into DIR (created, mode 700): loom_client_token
# (what clients send: LOOM_TOKEN) and loom_worker_token (what workers send). Each is
# 32 random bytes, base64url without padding. An existing token is kept, so running
# it twice changes nothing; delete a file to rotate that token (then restart the
# server and whoever uses it).
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
for name in loom_client_token loom_worker_token; do
  if [[ -s "$dir/$name" ]]; then
    echo "kept    $dir/$name"
  else
    head -c 32 /dev/urandom | base64 | tr '+/' '-_' | tr -d '=\n' >"$dir/$name"
    echo >>"$dir/$name"
    echo "created $dir/$name"
  fi
done
