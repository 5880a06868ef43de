#!/bin/sh
# Runs a command in a private network namespace whose loopback carries 127.0.0.1 and
# 127.0.0.2-5: simulated GigE Vision cameras each listen on their own address (two fake cameras
# on one address answer as one), and nothing on the machine's real network is seen or disturbed.
# Needs unprivileged user namespaces (Debian 12's default) or root.
set -e
exec unshare -rn sh -c '
  ip link set lo up
  for n in 2 3 4 5; do ip addr add 127.0.0.$n/8 dev lo; done
  exec "$@"' netns "$@"
