#!/usr/bin/env bash
# Writes Loom's two bearer tokens into DIR: loom_client_token (what clients send:
# LOOM_TOKEN) and loom_worker_token (what workers send). Each is 32 random bytes,
# base64url without padding or newline. An existing token is kept, so running it twice changes
# nothing; delete a file to rotate that token (then restart the server and whoever
# uses it).
#
# DIR is mode 700, which is what keeps the tokens private on this machine; the files
# themselves are 644 because compose bind-mounts them as they are into containers
# that run as uid 10001, not as their owner.
#
# Other names after DIR make those files instead, the same way (a database password).
#
#   deploy/make_tokens.sh deploy/tokens        # compose
#   deploy/make_tokens.sh deploy/k8s/tokens    # kustomize secretGenerator
#   deploy/make_tokens.sh /etc/loom            # systemd units (as root)
#   deploy/make_tokens.sh deploy/k8s/postgresql/tokens postgres_password
set -euo pipefail

if [[ $# -lt 1 ]]; then
  echo "usage: $0 DIR [NAME...]" >&2
  exit 2
fi
dir=$1
shift
names=("$@")
[[ ${#names[@]} -gt 0 ]] || names=(loom_client_token loom_worker_token)
umask 077
mkdir -p "$dir"
chmod 700 "$dir"
for name in "${names[@]}"; do
  if [[ -s "$dir/$name" ]]; then
    echo "kept    $dir/$name"
  else
    # No newline: a secret's value is the file's bytes (a password must not end in one).
    head -c 32 /dev/urandom | base64 | tr '+/' '-_' | tr -d '=\n' >"$dir/$name"
    chmod 644 "$dir/$name"
    echo "created $dir/$name"
  fi
done
